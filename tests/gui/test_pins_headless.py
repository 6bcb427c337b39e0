"""Pinned layout vertices under freecadcmd (run_pins_headless.py): on a sphere cut by three
great circles, a vertex moved within its octant is pinned there (within one solver edge), a
second move of the same vertex replaces its pin, a move of another vertex adds one; an edge
routed through a point passes it, a second route of that edge replaces the first; Clear
removes pins and routes and undo brings them back; both are in the exported design.json and
the FCStd."""

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


def test_an_edge_routed_through_a_point_passes_it(run):
    t1, edge = run["points"]["T1"], run["solver_edge"]
    r = run["routed"]
    assert r["undo"] == "Re-route layout edge"
    assert len(r["routes"]) == 1 and r["routes"][0]["through"] == pytest.approx(t1)
    assert len(r["routed"]) == 1 and r["routed"][0] == r["between"]
    assert _gap(r["between"]["through"], t1) <= edge
    assert min(_gap(p, t1) for p in r["between"]["points"]) <= edge
    assert r["patches"] == 6 and r["clean"]
    # The route names its edge by where it crossed its loop (the z = 0 circle).
    assert abs(r["routes"][0]["across"][2]) < 1e-6


def test_a_second_route_of_that_edge_replaces_the_first(run):
    t2, edge = run["points"]["T2"], run["solver_edge"]
    r = run["rerouted"]
    assert len(r["routes"]) == 1 and r["routes"][0]["through"] == pytest.approx(t2)
    assert len(r["routed"]) == 1 and _gap(r["between"]["through"], t2) <= edge
    assert r["patches"] == 6 and r["clean"]
    assert run["bad_edge"].startswith("ValueError: StripWeave: layout") and "no edge 99" in run["bad_edge"]


def test_clear_removes_them_and_undo_restores_them(run):
    c, u, s = run["cleared"], run["undone"], run["second"]
    assert run["cleared_returned"] is True
    assert c["routes"] == [] and c["routed"] == []
    assert u["routes"] == run["rerouted"]["routes"] and len(u["routed"]) == 1
    assert c["pins"] == [] and "pinned" not in c["placements"] and c["undo"] == "Clear layout pins"
    assert c["ppp"]["position"] == pytest.approx(run["before"]["ppp"]["position"])
    assert u["pins"] == s["pins"] and u["placements"] == s["placements"]
    assert u["ppp"]["position"] == pytest.approx(s["ppp"]["position"])


def test_pins_persist_in_design_json_and_the_fcstd(run):
    assert run["exported_pins"] == run["second"]["pins"]
    assert run["reopened_pins"] == run["second"]["pins"]
    assert run["exported_routes"] == run["rerouted"]["routes"]
    assert run["reopened_routes"] == run["rerouted"]["routes"]


def test_a_route_is_removed_alone_and_a_missing_pin_is_refused(run):
    r = run["route_removed"]
    assert r["routes"] == [] and r["pins"] == run["second"]["pins"]
    assert r["undo"] == "Remove edge route"
    assert run["bad_pin"].startswith("ValueError: StripWeave: design") and "no pin 6" in run["bad_pin"]


def test_a_route_of_a_crease_edge_is_refused_and_the_status_says_why(run):
    r = run["crease_route"]
    assert len(r["routes"]) == 1
    assert "edge route 1" in r["status"] and "crease" in r["status"]
    assert r["clean"]
