"""Start a GUI scenario script in FreeCAD under Xvfb (for the pytest files in
tests/gui): a throw-away FreeCAD user folder (FREECAD_USER_HOME) whose
Mod/StripWeave links to <repo> (the Addon Manager's layout: FreeCAD reads
<repo>/package.xml), the native build, and the
scenario's JSON result read back."""

import glob
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
LINK_SCRIPT = REPO / "workbench" / "link_into_freecad.sh"


def build_dir():
    return Path(os.environ.get("STRIPWEAVE_BUILD") or os.environ.get("STRIPWEAVE_BUILD_DIR") or REPO / "build")


def run_scenario(script, tmp, timeout, env_extra=None, tools=()):
    """Run ``script`` in ``freecad`` under xvfb-run in folder ``tmp``; returns
    {"result", "returncode", "log", "tmp"}.  ``tools``: further programs the
    scenario needs (e.g. xdotool)."""
    for tool in ("freecad", "xvfb-run") + tuple(tools):
        if shutil.which(tool) is None:
            pytest.fail("{} is not installed (bash .ci/setup installs it)".format(tool))
    build = build_dir()
    if not glob.glob(str(build / "_stripweave*.so")):
        pytest.fail("native module not built: no _stripweave*.so in {}".format(build))
    home = tmp / "freecad_home"
    home.mkdir(exist_ok=True)
    env = dict(os.environ)
    env.update({
        "FREECAD_USER_HOME": str(home),
        "QTWEBENGINE_DISABLE_SANDBOX": "1",
        "STRIPWEAVE_REPO": str(REPO),
        "STRIPWEAVE_BUILD": str(build),
        "STRIPWEAVE_GUI_TESTS": str(REPO / "tests" / "gui"),
        "STRIPWEAVE_GUI_RESULT": str(tmp / "result.json"),
        "STRIPWEAVE_GUI_WORKDIR": str(tmp),
        "STRIPWEAVE_GUI_TIMEOUT": str(timeout - 30),
    })
    env.update(env_extra or {})
    link = subprocess.run(["sh", str(LINK_SCRIPT)], env=env, capture_output=True, text=True, timeout=30)
    assert link.returncode == 0, link.stderr
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "freecad", str(script)]
    log_path = tmp / "freecad.log"
    with open(log_path, "w") as log:
        try:
            returncode = subprocess.run(cmd, env=env, cwd=str(tmp), stdout=log, stderr=subprocess.STDOUT,
                                        timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            returncode = None
    log_text = log_path.read_text(errors="replace")
    result_path = tmp / "result.json"
    assert result_path.is_file(), "FreeCAD wrote no result (exit code {}); log tail:\n{}".format(
        returncode, log_text[-4000:])
    return {"result": json.loads(result_path.read_text()), "returncode": returncode, "log": log_text, "tmp": tmp}


def failures(result):
    return ["{}: {}".format(c["name"], c["detail"]) for c in result["checks"] if not c["ok"]]


def assert_passed(run):
    result = run["result"]
    assert result["error"] is None, result["error"]
    failed = failures(result)
    assert not failed, "failed checks:\n" + "\n".join(failed)
    assert result["ok"] and run["returncode"] == 0


def run_headless(script, tmp, timeout=300):
    """Run ``script`` under ``freecadcmd`` (no GUI) with a throw-away user
    folder whose Mod/StripWeave links to the repository; returns the JSON it
    wrote to $STRIPWEAVE_HEADLESS_RESULT (its "error" must be None)."""
    if shutil.which("freecadcmd") is None:
        pytest.fail("freecadcmd is not installed (bash .ci/setup installs it)")
    build = build_dir()
    if not glob.glob(str(build / "_stripweave*.so")):
        pytest.fail("native module not built: no _stripweave*.so in {}".format(build))
    home = tmp / "freecad_home"
    (home / "Mod").mkdir(parents=True, exist_ok=True)
    link = home / "Mod" / "StripWeave"
    if not link.is_symlink():
        link.symlink_to(REPO)
    env = dict(os.environ, FREECAD_USER_HOME=str(home), STRIPWEAVE_BUILD=str(build),
               STRIPWEAVE_HEADLESS_RESULT=str(tmp / "result.json"), STRIPWEAVE_HEADLESS_WORKDIR=str(tmp))
    proc = subprocess.run(["freecadcmd", str(script)], env=env, cwd=str(tmp), capture_output=True, text=True,
                          timeout=timeout)
    out = tmp / "result.json"
    assert out.is_file(), proc.stdout[-3000:] + proc.stderr[-3000:]
    result = json.loads(out.read_text())
    assert result["error"] is None, result["error"]
    return result
