"""GUI test of symmetric design: runs tests/gui/run_symmetry_gui.py in FreeCAD's GUI under
xvfb with real input (xdotool) and asserts on its JSON result: the detected mirror plane is
ticked and drawn, a click adds a strip and its mirror image, None turns symmetry off; then on
a slab whose bosses are a half turn apart, the detected rotation is ticked and its axis drawn,
and a click adds a strip and its half-turn image.  The screenshots stay in pytest's tmp folder
(symmetry.png, rotation.png; rotation.png is also copied to /tmp/stripweave_rotation.png).
Takes ~1.5 min."""

import shutil
from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_symmetry_gui.py"
TIMEOUT = 300


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("stripweave_symmetry_gui")
    run = run_scenario(SCRIPT, tmp, TIMEOUT, {"STRIPWEAVE_GUI_SCREENSHOT": str(tmp / "symmetry.png")},
                       tools=("xdotool",))
    if (tmp / "rotation.png").is_file():
        shutil.copyfile(tmp / "rotation.png", "/tmp/stripweave_rotation.png")
    return run


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_strip_and_its_mirror_image(gui_run):
    x = gui_run["result"]["info"]["x_means"]
    assert len(x) == 2 and x[0] == pytest.approx(-x[1], abs=1e-6)


def test_screenshot_saved(gui_run):
    assert (gui_run["tmp"] / "symmetry.png").stat().st_size > 5000


def test_strip_and_its_half_turn_image(gui_run):
    info = gui_run["result"]["info"]
    assert info["rotation_error"] <= 1e-3 * info["rotation_diagonal"]
