"""GUI test of the StripWeave workbench: runs FreeCAD's GUI under xvfb.

    /usr/bin/python3 -m pytest tests/gui -v

Starts ``xvfb-run freecad tests/gui/run_gui_test.py`` with a throw-away
FreeCAD user folder (FREECAD_USER_HOME) whose Mod/StripWeave links to
<repo> (made by workbench/link_into_freecad.sh, the Addon Manager's layout), then asserts on the
JSON result the script writes.  The screenshot is kept in pytest's tmp folder
(and copied to /tmp/stripweave_gui.png by the script).

Needs: freecad, xvfb-run, the native build (<repo>/build/_stripweave*.so, or
$STRIPWEAVE_BUILD).  Takes ~20 s.
"""

import pytest

from launch import REPO, assert_passed, run_scenario

SCRIPT = REPO / "tests" / "gui" / "run_gui_test.py"
TIMEOUT = 180


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("stripweave_gui")
    run = run_scenario(SCRIPT, tmp, TIMEOUT, {"STRIPWEAVE_GUI_SCREENSHOT": str(tmp / "screenshot.png")})
    assert (tmp / "freecad_home" / "Mod" / "StripWeave").resolve() == REPO.resolve()  # as the Addon Manager
    return run


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_box_overlay_has_twelve_feature_curves(gui_run):
    info = gui_run["result"]["info"]
    assert info.get("overlay_box") == [12, 0]
    assert info["report_box"]["feature_curves"] == 12


def test_bad_input_reported_without_crash(gui_run):
    info = gui_run["result"]["info"]
    for name in ("Empty", "JustAWire"):
        err = info.get("error_" + name)
        assert err, "no error recorded for " + name
        assert name in err["report_view"]
        assert len(err["message_boxes"]) == 1


def test_screenshot_saved(gui_run):
    png = gui_run["tmp"] / "screenshot.png"
    assert png.is_file()
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(data) > 5000
