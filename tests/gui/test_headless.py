"""The SurfaceModel object under freecadcmd (no GUI): synchronous build on
recompute, bad input marks the object invalid, save/reload.  ~5 s."""

import json
from pathlib import Path

from launch import run_headless

SCRIPT = Path(__file__).resolve().parent / "run_headless_check.py"


def test_surface_model_headless(tmp_path):
    r = run_headless(SCRIPT, tmp_path, timeout=120)
    assert r["report"]["feature_curves"] == 12
    assert r["feature_counts"] == 12
    assert r["up_to_date"] and not r["has_view_object"]
    assert abs(r["diag_after_change"] - (20 ** 2 + 10 ** 2 + 10 ** 2) ** 0.5) < 1e-6
    assert "Invalid" in r["bad_state"]
    assert "empty shape" in json.loads(r["bad_report"])["error"]
    assert r["reloaded_counts"] == 12 and not r["reloaded_cached"]
    assert r["rebuilt_triangles"] > 0
