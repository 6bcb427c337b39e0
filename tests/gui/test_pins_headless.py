"""Pinned layout vertices under freecadcmd (run_pins_headless.py): on a sphere cut by three
great circles, a vertex moved within its octant is pinned there (within one solver edge), a
second move of the same vertex replaces its pin, a move of another vertex adds one; Clear
removes them and undo brings them back; the pins are in the exported design.json and the
FCStd."""

import math
from pathlib import Path

import pytest

from launch import run_headless

SCRIPT = Path(__file__).resolve().parent / "run_pins_headless.py"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(SCRIPT, tmp_path_factory.mktemp("pins_headless"), timeout=600)


def _gap(a, b):
    return math.dist(a, b)


def test_no_pins_at_first(run):
    b = run["before"]
    assert b["pins"] == [] and b["patches"] == 6 and "pinned" not in b["placements"]


def test_a_moved_vertex_is_pinned_at_the_point(run):
    p1, edge = run["points"]["P1"], run["solver_edge"]
    first = run["first"]
    assert first["pins"] == [pytest.approx(p1)]
    assert first["undo"] == "Move layout vertex"
    assert first["ppp"]["placement"] == "pinned" and _gap(first["ppp"]["position"], p1) <= edge
    assert first["placements"].count("pinned") == 1 and first["patches"] == 6


def test_a_second_move_of_that_vertex_replaces_its_pin(run):
    p2, edge = run["points"]["P2"], run["solver_edge"]
    r = run["replaced"]
    assert r["pins"] == [pytest.approx(p2)]
    assert r["ppp"]["placement"] == "pinned" and _gap(r["ppp"]["position"], p2) <= edge


def test_another_vertex_adds_a_pin(run):
    pts, edge = run["points"], run["solver_edge"]
    s = run["second"]
    assert s["pins"] == [pytest.approx(pts["P2"]), pytest.approx(pts["P3"])]
    assert s["mmm"]["placement"] == "pinned" and _gap(s["mmm"]["position"], pts["P3"]) <= edge
    assert s["placements"].count("pinned") == 2
    assert run["bad_vertex"].startswith("ValueError: StripWeave: layout") and "no vertex 99" in run["bad_vertex"]


def test_clear_removes_them_and_undo_restores_them(run):
    c, u, s = run["cleared"], run["undone"], run["second"]
    assert run["cleared_returned"] is True
    assert c["pins"] == [] and "pinned" not in c["placements"] and c["undo"] == "Clear layout pins"
    assert c["ppp"]["position"] == pytest.approx(run["before"]["ppp"]["position"])
    assert u["pins"] == s["pins"] and u["placements"] == s["placements"]
    assert u["ppp"]["position"] == pytest.approx(s["ppp"]["position"])


def test_pins_persist_in_design_json_and_the_fcstd(run):
    assert run["exported_pins"] == run["second"]["pins"]
    assert run["reopened_pins"] == run["second"]["pins"]
