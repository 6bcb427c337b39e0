"""Editing committed strips with real input (xdotool) in the Design strips tool
(run_edit_gui.py): grab-and-drag re-routes a strip through the release point and
Ctrl+Z restores it; the panel lists a selected strip's anchors with their direction
flags, and Make positional / Delete anchor re-derive the design.  The screenshots
are copied to /tmp/stripweave_grab.png and /tmp/stripweave_edit_panel.png for a
human to look at."""

import shutil
from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_edit_gui.py"
TIMEOUT = 400


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    run = run_scenario(SCRIPT, tmp_path_factory.mktemp("stripweave_edit"), TIMEOUT, tools=("xdotool",))
    for name, copy in (("grab.png", "/tmp/stripweave_grab.png"), ("panel.png", "/tmp/stripweave_edit_panel.png")):
        if (run["tmp"] / name).is_file():
            shutil.copyfile(run["tmp"] / name, copy)
    return run


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def checks(run):
    return {c["name"]: c["ok"] for c in run["result"]["checks"]}


def test_grab_and_drag_passes_the_release_point(gui_run):
    c = checks(gui_run)
    assert c["release: the loop passes the release point's surface point"]
    assert c["release: the strip count is unchanged"]
    assert c["Ctrl+Z: the old loop back"]


def test_anchor_edits(gui_run):
    c = checks(gui_run)
    assert c["select strip 1: its two anchors listed with their direction flags"]
    assert c["Make positional: both anchors positional, the design re-derived"]
    assert c["Delete anchor: one anchor left, the design re-derived"]
