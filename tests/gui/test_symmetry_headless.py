"""A design's symmetry under freecadcmd (no GUI), on a slab with an off-centre boss mirrored
in x (tests/models.py mirrored_box): accepting the detected reflection stores it in
design.symmetry (one transaction, round-trips through design.json); a strip added then comes
with its mirror image (loops within 1e-3 of the diagonal of each other's mirror); turning it
off clears design.symmetry; a refused image leaves the design unchanged; Auto weave mirrors
the strips it adds.  ~10 s."""

from pathlib import Path

import pytest

from launch import run_headless

SCRIPT = Path(__file__).resolve().parent / "run_symmetry_headless.py"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(SCRIPT, tmp_path_factory.mktemp("symmetry_headless"))


def test_detects_the_mirror_plane(run):
    assert run["mirror_found"]


def test_accepting_stores_it_in_one_transaction_and_round_trips(run):
    assert run["set_changed"] and run["undo_after_set"] == ["Set symmetry"]
    assert len(run["stored"]) == 1 and run["stored"][0]["kind"] == "reflection"
    assert run["round_trip"]


def test_a_strip_comes_with_its_mirror_image(run):
    m = run["with_mirror"]
    assert m["strips"] == 2 and m["wires"] == 2 and m["image_of"] == [None, 0]
    assert m["mirror_error"] <= 1e-3 * run["diagonal"]
    assert m["x_means"][0] == pytest.approx(-m["x_means"][1], abs=1e-3 * run["diagonal"])
    assert m["undo"] == ["Add strip"] and run["after_undo"] == 0   # one undo step: both


def test_turning_off_clears_it(run):
    assert run["off_changed"] and not run["off_stored"] and run["off_undo"] == ["Turn symmetry off"]
    assert run["alone"] == 1


def test_a_refused_image_leaves_the_design_unchanged(run):
    assert run["refused"] is not None and "symmetric image" in run["refused"] and "\n" not in run["refused"]
    assert run["refused_kept"]


def test_auto_weave_takes_the_accepted_symmetry(run):
    # Without it the same weave's loops are 5.0 off their mirror images (6 strips, none mirrored).
    w = run["woven"]
    assert w["strips"] >= 2 and w["mirror_error"] <= 1e-3 * run["diagonal"]
