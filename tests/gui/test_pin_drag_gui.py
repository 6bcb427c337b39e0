"""A real drag (xdotool) of a Layout's primal vertex in Edit layout vertices pins it where it
is released: the Design gets that point as its pin, the octant's vertex is placed "pinned"
within one solver edge of it and drawn green; Esc ends the tool; Clear layout pins removes
the pin. Then a real drag of an edge routes it through the release point: one edge route of
the Design, the edge within one solver edge of the point, the layout still clean; a vertex dragged out of its region stays in it (run_pin_drag_gui.py).  The screenshots are copied to /tmp/stripweave_pinned.png and
/tmp/stripweave_routed.png for a human to look at."""

import shutil
from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_pin_drag_gui.py"
TIMEOUT = 400


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    run = run_scenario(SCRIPT, tmp_path_factory.mktemp("stripweave_pins"), TIMEOUT, tools=("xdotool",))
    for name in ("pinned.png", "dragging.png", "routed.png", "route_dragging.png", "layout_panel.png"):
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


def test_the_dragged_edge_passes_the_release_point(gui_run):
    info = gui_run["result"]["info"]
    assert info["target_off_edge_before"] > 3 * info["solver_edge"]
    assert info["routed_gap"] <= info["solver_edge"]
