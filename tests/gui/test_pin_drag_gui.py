"""A real drag (xdotool) of a Layout's primal vertex in Edit layout vertices pins it where it
is released: the Design gets that point as its pin, the octant's vertex is placed "pinned"
within one solver edge of it and drawn green; Esc ends the tool; Clear layout pins removes
the pin (run_pin_drag_gui.py).  The screenshot is copied to /tmp/stripweave_pinned.png for a
human to look at."""

import shutil
from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_pin_drag_gui.py"
TIMEOUT = 400


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    run = run_scenario(SCRIPT, tmp_path_factory.mktemp("stripweave_pins"), TIMEOUT, tools=("xdotool",))
    for name in ("pinned.png", "dragging.png"):
        shot = run["tmp"] / name
        if shot.is_file():
            shutil.copyfile(shot, "/tmp/stripweave_" + name)
    return run


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_the_vertex_is_pinned_under_the_release(gui_run):
    info = gui_run["result"]["info"]
    assert info["vertex_after"]["placement"] == "pinned"
    assert info["pinned_gap"] <= info["solver_edge"]
