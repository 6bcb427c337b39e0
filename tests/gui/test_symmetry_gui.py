"""GUI test of symmetric design: runs tests/gui/run_symmetry_gui.py in FreeCAD's GUI under
xvfb with real input (xdotool) and asserts on its JSON result: the detected mirror plane is
ticked and drawn, a click adds a strip and its mirror image, None turns symmetry off.
The screenshot stays in pytest's tmp folder (symmetry.png).  Takes ~1 min."""

from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_symmetry_gui.py"
TIMEOUT = 300


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("stripweave_symmetry_gui")
    return run_scenario(SCRIPT, tmp, TIMEOUT, {"STRIPWEAVE_GUI_SCREENSHOT": str(tmp / "symmetry.png")},
                        tools=("xdotool",))


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_strip_and_its_mirror_image(gui_run):
    x = gui_run["result"]["info"]["x_means"]
    assert len(x) == 2 and x[0] == pytest.approx(-x[1], abs=1e-6)


def test_screenshot_saved(gui_run):
    assert (gui_run["tmp"] / "symmetry.png").stat().st_size > 5000
