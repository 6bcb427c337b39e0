"""GUI test of the StripWeave workbench: runs FreeCAD's GUI under xvfb.

    /usr/bin/python3 -m pytest tests/gui -v

Starts ``xvfb-run freecad tests/gui/run_gui_test.py`` with a throw-away
FreeCAD user folder (FREECAD_USER_HOME) whose Mod/StripWeave links to
<repo>/workbench (made by workbench/link_into_freecad.sh), then asserts on the
JSON result the script writes.  The screenshot is kept in pytest's tmp folder
(and copied to /tmp/stripweave_gui.png by the script).

Needs: freecad, xvfb-run, the native build (<repo>/build/_stripweave*.so, or
$STRIPWEAVE_BUILD).  Takes ~20 s.
"""

import glob
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "tests" / "gui" / "run_gui_test.py"
LINK_SCRIPT = REPO / "workbench" / "link_into_freecad.sh"
TIMEOUT = 180


def _build_dir():
    return Path(os.environ.get("STRIPWEAVE_BUILD") or os.environ.get("STRIPWEAVE_BUILD_DIR")
                or REPO / "build")


def _require(tool):
    if shutil.which(tool) is None:
        pytest.fail("{} is not installed".format(tool))


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    _require("freecad")
    _require("xvfb-run")
    build = _build_dir()
    if not glob.glob(str(build / "_stripweave*.so")):
        pytest.fail("native module not built: no _stripweave*.so in {}".format(build))

    tmp = tmp_path_factory.mktemp("stripweave_gui")
    home = tmp / "freecad_home"
    home.mkdir()
    env = dict(os.environ)
    env.update({
        "FREECAD_USER_HOME": str(home),
        "QTWEBENGINE_DISABLE_SANDBOX": "1",
        "STRIPWEAVE_REPO": str(REPO),
        "STRIPWEAVE_BUILD": str(build),
        "STRIPWEAVE_GUI_RESULT": str(tmp / "result.json"),
        "STRIPWEAVE_GUI_SCREENSHOT": str(tmp / "screenshot.png"),
        "STRIPWEAVE_GUI_WORKDIR": str(tmp),
        "STRIPWEAVE_GUI_TIMEOUT": str(TIMEOUT - 30),
    })
    link = subprocess.run(["sh", str(LINK_SCRIPT)], env=env, capture_output=True, text=True, timeout=30)
    assert link.returncode == 0, link.stderr
    assert (home / "Mod" / "StripWeave").resolve() == (REPO / "workbench").resolve()

    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "freecad", str(SCRIPT)]
    log_path = tmp / "freecad.log"
    with open(log_path, "w") as log:
        try:
            proc = subprocess.run(cmd, env=env, cwd=str(tmp), stdout=log, stderr=subprocess.STDOUT,
                                  timeout=TIMEOUT)
            returncode = proc.returncode
        except subprocess.TimeoutExpired:
            returncode = None
    log_text = log_path.read_text(errors="replace")
    result_path = tmp / "result.json"
    assert result_path.is_file(), "FreeCAD wrote no result (exit code {}); log tail:\n{}".format(
        returncode, log_text[-4000:])
    result = json.loads(result_path.read_text())
    return {"result": result, "returncode": returncode, "log": log_text, "tmp": tmp}


def _failures(result):
    return ["{}: {}".format(c["name"], c["detail"]) for c in result["checks"] if not c["ok"]]


def test_scenario_passes(gui_run):
    result = gui_run["result"]
    assert result["error"] is None, result["error"]
    failures = _failures(result)
    assert not failures, "failed checks:\n" + "\n".join(failures)
    assert result["ok"]
    assert gui_run["returncode"] == 0


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
