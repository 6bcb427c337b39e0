"""A real drag (xdotool) in the Design strips tool sets a directional anchor whose loop follows
the drag: tangent within 10 degrees at the press point; Shift+click collects anchors and Enter
adds the strip through them, Esc drops them (run_drag_gui.py).  The screenshot is
copied to /tmp/stripweave_drag.png for a human to look at."""

import shutil
from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_drag_gui.py"
TIMEOUT = 300


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    run = run_scenario(SCRIPT, tmp_path_factory.mktemp("stripweave_drag"), TIMEOUT, tools=("xdotool",))
    shot = run["tmp"] / "drag.png"
    if shot.is_file():
        shutil.copyfile(shot, "/tmp/stripweave_drag.png")
    return run


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_loop_follows_the_drag(gui_run):
    info = gui_run["result"]["info"]
    assert info["anchor_vs_drag_deg"] <= 10.0
    assert info["strip_tangent_vs_drag_deg"] <= 10.0


def test_shift_click_and_enter(gui_run):
    checks = {c["name"]: c["ok"] for c in gui_run["result"]["checks"]}
    assert checks["Shift+click: two anchors pending, no strip yet"]
    assert checks["Enter: one strip through the anchors"] and checks["Enter: the strip is the outer equator"]
    assert checks["Esc: the pending anchors dropped, the tool still open"]
