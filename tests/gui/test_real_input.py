"""The design tool driven by REAL X input events (xdotool under Xvfb): runs
tests/gui/run_real_input.py in FreeCAD's GUI and asserts on its result.  The
screenshot (click.png) stays in pytest's tmp folder and is copied to
/tmp/stripweave_real_click.png for a human to look at."""

import shutil
from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_real_input.py"
TIMEOUT = 240


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    run = run_scenario(SCRIPT, tmp_path_factory.mktemp("stripweave_real_input"), TIMEOUT, tools=("xdotool",))
    shot = run["tmp"] / "click.png"
    if shot.is_file():
        shutil.copyfile(shot, "/tmp/stripweave_real_click.png")
    return run


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_real_click_adds_the_hovered_loop(gui_run):
    checks = {c["name"]: c["ok"] for c in gui_run["result"]["checks"]}
    assert checks["click A: click added one strip"]
    assert checks["click A: nothing selected"]
    assert gui_run["result"]["info"]["click A_loop_distance"] < 0.05


def test_screenshot_saved(gui_run):
    data = (gui_run["tmp"] / "click.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000


def test_picture_shows_the_clicked_loop(gui_run):
    hits, seen = gui_run["result"]["info"]["click picture loop 1 pixels"]
    assert seen >= 5 and hits >= 0.8 * seen
