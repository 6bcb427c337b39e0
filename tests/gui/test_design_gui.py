"""GUI test of designs: runs tests/gui/run_design_gui.py in FreeCAD's GUI
under xvfb (same set-up as test_gui.py) and asserts on its JSON result.
The screenshots stay in pytest's tmp folder and are copied to
/tmp/stripweave_design_gui.png (torus) and /tmp/stripweave_design_box.png
(cube).  Takes ~1 min."""

from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_design_gui.py"
TIMEOUT = 300


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("stripweave_design_gui")
    return run_scenario(SCRIPT, tmp, TIMEOUT, {"STRIPWEAVE_GUI_SCREENSHOT": str(tmp / "torus.png"),
                                               "STRIPWEAVE_GUI_SCREENSHOT2": str(tmp / "cube.png")})


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_hover_shows_a_preview_loop(gui_run):
    names = {c["name"]: c["ok"] for c in gui_run["result"]["checks"]}
    assert names.get("hover: preview loop drawn")
    assert names.get("mouse move: preview loop drawn")


def test_cube_design_has_eight_corner_singularities(gui_run):
    counts = gui_run["result"]["info"]["box_summary"]["singularity_counts"]
    assert counts == {"+1/4": 8, "-1/4": 0, "other": 0}


def test_screenshots_saved(gui_run):
    for name in ("torus.png", "cube.png"):
        data = (gui_run["tmp"] / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000


def test_torus_picture_shows_each_loop_in_its_colour(gui_run):
    """The screenshot is checked for what it shows: at the visible points of
    each strip's loop, projected, the loop's colour (not just a saved PNG)."""
    info = gui_run["result"]["info"]
    for i in (1, 2):
        hits, seen = info["torus picture loop {} pixels".format(i)]
        assert seen >= 5 and hits >= 0.8 * seen
