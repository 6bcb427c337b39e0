"""GUI test of designs: runs tests/gui/run_design_gui.py in FreeCAD's GUI
under xvfb (same set-up as test_gui.py) and asserts on its JSON result.
The screenshots stay in pytest's tmp folder and are copied to
/tmp/stripweave_design_gui.png (torus) and /tmp/stripweave_design_box.png
(cube).  Takes ~1 min."""

import glob
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "tests" / "gui" / "run_design_gui.py"
LINK_SCRIPT = REPO / "workbench" / "link_into_freecad.sh"
TIMEOUT = 300


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    for tool in ("freecad", "xvfb-run"):
        if shutil.which(tool) is None:
            pytest.fail("{} is not installed".format(tool))
    build = Path(os.environ.get("STRIPWEAVE_BUILD") or os.environ.get("STRIPWEAVE_BUILD_DIR") or REPO / "build")
    if not glob.glob(str(build / "_stripweave*.so")):
        pytest.fail("native module not built: no _stripweave*.so in {}".format(build))
    tmp = tmp_path_factory.mktemp("stripweave_design_gui")
    home = tmp / "freecad_home"
    home.mkdir()
    env = dict(os.environ)
    env.update({
        "FREECAD_USER_HOME": str(home),
        "QTWEBENGINE_DISABLE_SANDBOX": "1",
        "STRIPWEAVE_BUILD": str(build),
        "STRIPWEAVE_GUI_RESULT": str(tmp / "result.json"),
        "STRIPWEAVE_GUI_SCREENSHOT": str(tmp / "torus.png"),
        "STRIPWEAVE_GUI_SCREENSHOT2": str(tmp / "cube.png"),
        "STRIPWEAVE_GUI_WORKDIR": str(tmp),
        "STRIPWEAVE_GUI_TIMEOUT": str(TIMEOUT - 30),
    })
    link = subprocess.run(["sh", str(LINK_SCRIPT)], env=env, capture_output=True, text=True, timeout=30)
    assert link.returncode == 0, link.stderr
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "freecad", str(SCRIPT)]
    log_path = tmp / "freecad.log"
    with open(log_path, "w") as log:
        try:
            returncode = subprocess.run(cmd, env=env, cwd=str(tmp), stdout=log, stderr=subprocess.STDOUT,
                                        timeout=TIMEOUT).returncode
        except subprocess.TimeoutExpired:
            returncode = None
    result_path = tmp / "result.json"
    assert result_path.is_file(), "FreeCAD wrote no result (exit code {}); log tail:\n{}".format(
        returncode, log_path.read_text(errors="replace")[-4000:])
    return {"result": json.loads(result_path.read_text()), "returncode": returncode, "tmp": tmp}


def test_scenario_passes(gui_run):
    result = gui_run["result"]
    assert result["error"] is None, result["error"]
    failures = ["{}: {}".format(c["name"], c["detail"]) for c in result["checks"] if not c["ok"]]
    assert not failures, "failed checks:\n" + "\n".join(failures)
    assert result["ok"] and gui_run["returncode"] == 0


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
