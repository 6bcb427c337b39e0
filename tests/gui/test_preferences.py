"""Preferences (Edit > Preferences > StripWeave) are read by the commands,
and a missing native library says what to run (issue 20)."""

import sys

import pytest

from launch import REPO, run_headless

SCRIPT = REPO / "tests" / "gui" / "run_preferences_headless.py"


def test_commands_use_the_preferences(tmp_path):
    r = run_headless(SCRIPT, tmp_path, timeout=120)
    # Auto weave's strip cap is automatic (None: by the part's topology) until one is set.
    assert r["defaults"] == [30000, 30.0, None, "aligned", None, False]
    triangles, angle, built = r["surface_model"]
    assert triangles == 3000 and angle == 40.0
    assert 0.5 * 3000 < built < 2 * 3000           # built at the preferred size, not 30000
    assert r["design"] == ["trimmed", "trimmed"]
    assert r["tolerance"] == 0.02
    assert r["max_strips"] == 12
    assert r["crease_pairs"] is True      # the check box reaches Auto weave's options
    assert "boundary mode" in r["bad_mode"]


def test_missing_native_library_says_what_to_run(monkeypatch):
    import freecad.stripweave_wb as wb
    hint = wb.setup_hint()
    setup = REPO / ".ci" / "setup"
    assert setup.is_file() and "bash {}".format(setup) in hint
    monkeypatch.setitem(sys.modules, "stripweave", None)   # as if it could not be imported
    with pytest.raises(ImportError) as info:
        wb.import_stripweave()
    assert "bash {}".format(setup) in str(info.value)
