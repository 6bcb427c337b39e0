"""The main job's macro functions under freecadcmd (run_job_headless.py):
auto_weave keeps the user's strip, layout_model.create, patches_model.create
and export_step give a valid solid whose STEP reloads with the same faces,
all survive save / reopen, and a design change recomputes the layout."""

from pathlib import Path

import pytest

from launch import run_headless

SCRIPT = Path(__file__).resolve().parent / "run_job_headless.py"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(SCRIPT, tmp_path_factory.mktemp("job_headless"), timeout=600)


def test_bad_option_is_one_line_and_changes_nothing(run):
    assert run["bad_option"].startswith("InputError: auto weave: unknown option max_stripz")
    assert run["after_bad_option"] == {"strips": 1, "undo": "Add strip"}


def test_auto_weave_keeps_the_user_strip_first(run):
    w = run["weave"]
    assert w["strips"] > 1 and w["red"] == 0
    assert w["first_anchors"] == w["user_anchors"]
    assert w["undo"] == "Auto weave"
    assert w["strip_count"] == w["strips"] and "Invalid" not in w["state"]


def test_layout_object(run):
    lay = run["layout"]
    assert lay["valid"] and lay["patches"] > 0
    assert lay["shape_edges"] >= lay["edges"] > 0 and lay["shape_vertices"] >= lay["vertices"] > 0
    assert lay["undo"] == "Show layout" and "Invalid" not in lay["state"]
    assert "patches" in lay["status"]


def test_patches_are_a_valid_solid(run):
    p = run["patches"]
    assert p["type"] == "Solid" and p["valid"] and p["closed"]
    assert p["faces"] == run["layout"]["patches"] == p["wires"] == p["colours"]
    assert p["undo"] == "Fit patches" and "Invalid" not in p["state"]
    assert 0 < p["max_deviation"] and p["coverage"] > 0.9


def test_step_reloads_with_the_same_faces(run):
    s = run["step"]
    assert s["faces_read_back"] == s["faces"] == run["patches"]["faces"]
    assert s["valid"] and s["solids"] == 1
    assert run["step_of_layout"].startswith("InputError:") and "Fit patches" in run["step_of_layout"]


def test_reopen_keeps_design_layout_and_patches(run):
    assert all(run["reopened"].values()), run["reopened"]


def test_design_change_recomputes_the_layout(run):
    c = run["after_change"]
    assert c["strips"] == run["weave"]["strips"] - 1
    assert c["layout_changed"] and "Invalid" not in c["layout_state"]
