"""The Design object under freecadcmd (no GUI): a meridian strip on a torus
becomes one closed wire of length 2 pi 3; undo/redo; a failing strip keeps
the design; export/import; save/reopen.  ~15 s."""

from pathlib import Path

import pytest

from launch import run_headless

SCRIPT = Path(__file__).resolve().parent / "run_design_headless.py"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(SCRIPT, tmp_path_factory.mktemp("design_headless"))


def test_empty_design_has_no_wires(run):
    assert run["empty"]["wires"] == []
    assert "Invalid" not in run["empty"]["state"]


def test_meridian_strip_is_one_closed_wire(run):
    m = run["meridian"]
    assert len(m["wires"]) == 1
    assert m["wires"][0]["closed"]
    assert m["wires"][0]["length"] == pytest.approx(run["expected_length"], rel=0.02)
    assert m["strip_count"] == 1 and "Invalid" not in m["state"]
    assert m["undo_names"][0] == "Add strip"
    assert m["derived_strips"] == 1 and m["stripe_vertices"] > 0
    assert m["summary"]["strips"][0]["area_fraction"] == pytest.approx(1.0, abs=0.05)
    assert m["summary"]["singularities"] == [] and m["summary"]["error"] is None


def test_undo_removes_the_added_strip_and_redo_restores_it(run):
    assert run["two"]["strips_in_json"] == 2 and len(run["two"]["wires"]) == 2
    assert run["after_undo"]["strips_in_json"] == 1
    assert run["after_undo"]["wires_after_recompute"] == 1
    assert run["after_redo"] == {"strips_in_json": 2, "wires": 2}


def test_incompatible_strip_is_refused_without_changing_the_document(run):
    assert run["refused"] and "InputError" in run["refused"]
    assert run["after_refusal"]["strips_in_json"] == 1
    assert "Add strip" in run["after_refusal"]["undo_names"][0]


def test_failing_strip_keeps_the_design_and_reports(run):
    bad = run["bad"]
    assert "Invalid" in bad["state"]
    assert bad["strips_in_json"] == 2 and bad["unknown_key_kept"] == "kept"
    assert bad["wires"] == 1 and bad["strip_count"] == 1          # what could be derived
    assert bad["status"].startswith("error") and "strip 2" in bad["status"]
    assert bad["summary_error"]
    assert "Invalid" not in run["repaired_state"]


def test_boundary_property_mirrors_the_json(run):
    assert run["boundary_in_json"] == "trimmed"


def test_features_flag_rederives_on_the_same_graph(run):
    f = run["features_off"]
    assert "Invalid" not in f["state"] and f["strip_count"] == 1
    assert f["same_loop_engine"]


def test_export_import_round_trip(run):
    assert run["exported"]["strips"] == 1
    assert run["exported"]["model"]["label"] == "Torus"
    assert run["after_remove"] == 0
    assert len(run["after_import"]["wires"]) == 1 and run["after_import"]["undo"] == "Import design"


def test_reopened_document_keeps_design_and_rebuilds_session(run):
    r = run["reopened"]
    assert r["is_design"] and r["json_equal"]
    assert len(r["wires"]) == 1 and r["wires"][0]["closed"]
    assert not r["derived_before"] and r["derived_after"]
    assert r["session_strips"] == 1
    assert r["session_length"] == pytest.approx(run["expected_length"], rel=0.02)


def test_edit_strip_replaces_the_anchors_in_one_undoable_step(run):
    e = run["edited"]
    assert e["anchors"] == [[[0, 13, 0, 0, 0, 1]]] and e["undo"] == "Edit strip" and e["wires"] == 1
    assert e["max_abs_x"] < 0.5           # the meridian at phi = 90 degrees (x = 0)
    assert run["edit_undone"]


def test_refused_edit_leaves_the_document_unchanged(run):
    assert run["edit_refused"] and "InputError" in run["edit_refused"]
    assert run["edit_refused_unchanged"]


def test_set_options_applies_the_band_to_the_session(run):
    assert run["band"] == {"json": 2.5, "undo": "Set compatibility band", "native": 2.5, "strip_count": 1}
    assert run["bad_band"] and "compatibility_band" in run["bad_band"] and run["bad_band_unchanged"]
    assert run["band_back"] is None
