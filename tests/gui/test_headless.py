"""The SurfaceModel object under freecadcmd (no GUI): synchronous build on
recompute, bad input marks the object invalid, save/reload.  ~5 s."""

import glob
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "tests" / "gui" / "run_headless_check.py"


def test_surface_model_headless(tmp_path):
    if shutil.which("freecadcmd") is None:
        pytest.fail("freecadcmd is not installed")
    build = Path(os.environ.get("STRIPWEAVE_BUILD") or REPO / "build")
    if not glob.glob(str(build / "_stripweave*.so")):
        pytest.fail("native module not built: no _stripweave*.so in {}".format(build))
    home = tmp_path / "freecad_home"
    (home / "Mod").mkdir(parents=True)
    (home / "Mod" / "StripWeave").symlink_to(REPO / "workbench")
    env = dict(os.environ, FREECAD_USER_HOME=str(home), STRIPWEAVE_BUILD=str(build),
               STRIPWEAVE_HEADLESS_RESULT=str(tmp_path / "result.json"),
               STRIPWEAVE_HEADLESS_WORKDIR=str(tmp_path))
    proc = subprocess.run(["freecadcmd", str(SCRIPT)], env=env, cwd=str(tmp_path),
                          capture_output=True, text=True, timeout=120)
    out = tmp_path / "result.json"
    assert out.is_file(), proc.stdout[-3000:] + proc.stderr[-3000:]
    r = json.loads(out.read_text())
    assert r["error"] is None, r["error"]
    assert r["report"]["feature_curves"] == 12
    assert r["feature_counts"] == 12
    assert r["up_to_date"] and not r["has_view_object"]
    assert abs(r["diag_after_change"] - (20 ** 2 + 10 ** 2 + 10 ** 2) ** 0.5) < 1e-6
    assert "Invalid" in r["bad_state"]
    assert "empty shape" in json.loads(r["bad_report"])["error"]
    assert r["reloaded_counts"] == 12 and not r["reloaded_cached"]
    assert r["rebuilt_triangles"] > 0
