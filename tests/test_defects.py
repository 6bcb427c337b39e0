"""Strict layout checks (issue 16, native layout_defects.h): what keeps a valid layout from
being clean, counted, located, and agreed on by layout.json, report.json and the CLI.

Each defect is produced by a design on a generated model and checked against an independent
reading of layout.json (valences, corners, edge polylines, patch corners), not against the
native flags alone.
"""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import FreeCAD  # noqa: F401  (before Part)
import Part

import stripweave as sw
from models import capped_cylinder, sphere, torus
from stripweave.design import Design
from stripweave.job import make_report
from stripweave.layout import DEFECT_KEYS, compute_layout, format_defects, layout_json
from stripweave.loops import LoopSession
from stripweave.strips import DesignSession
from stripweave.symmetry import mean_edge_length
from test_layout import MERIDIAN, OUTER_EQUATOR, cube_layout  # noqa: F401  (a fixture)

native = sw._native

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = os.path.join(REPO, "build", "stripweave")
TWO_GREAT_CIRCLES = [[(5, 0, 0, 0, 1, 0)], [(0, 5, 0, 0, 0, 1)]]


def loops_layout(session, anchors):
    """layout.json of loops through these anchors (no design compatibility asked)."""
    loops = [session.native.loops([list(a)], 1, True)[0] for a in anchors]
    return layout_json(native.layout(session.native, loops))


def locations(L, kind):
    return [d for d in L["defect_locations"] if d["kind"] == kind]


def overlapping_edges(L):
    """Independently of the native check: the edges whose polylines (model units) share a point
    that is not a primal vertex both end at, or that visit a point twice."""
    visits = {}
    for e, edge in enumerate(L["edges"]):
        pts = [tuple(p) for p in edge["points"]]
        for i, p in enumerate(pts):
            end = edge["vertices"][0] if i == 0 else edge["vertices"][1] if i == len(pts) - 1 else None
            visits.setdefault(p, []).append((e, end))
    flagged = set()
    for p, at in visits.items():
        for a in range(len(at)):
            for b in range(a + 1, len(at)):
                (ea, va), (eb, vb) = at[a], at[b]
                if va is not None and va == vb and np.allclose(L["vertices"][va]["position"], p, atol=1e-9):
                    continue
                flagged |= {ea, eb}
    return flagged


@pytest.fixture(scope="module")
def sheet():
    return LoopSession(sw.from_shape(Part.makePlane(10, 10), target_triangles=8000))


@pytest.fixture(scope="module")
def squeezed(sheet):
    """Two curves 0.12 apart (under one solver edge, 0.18) and one across them: the thin strip
    between them leaves its primal edges no corridor of their own."""
    return loops_layout(sheet, [(5, 3, 0, 0, 1, 0), (5.12, 3, 0, 0, 1, 0), (3, 5, 0, 1, 0, 0)])


def test_a_squeezed_layout_reports_non_quads_and_overlaps_where_they_are(squeezed):
    L = squeezed
    assert L["valid"] and not L["clean"]
    d = L["defects"]
    # Non-quad patches: those whose boundary is not four sides or whose corners repeat.
    non_quad = {i for i, p in enumerate(L["patches"]) if not p["quad"] or len(set(p["corners"])) != 4}
    assert d["non_quad_patches"] == len(non_quad) >= 1
    assert {i for i, p in enumerate(L["patches"]) if "non_quad" in p["defects"]} == non_quad
    assert {x["patch"] for x in locations(L, "non_quad")} == non_quad
    # Overlapping edges, read from the polylines.
    overlapping = overlapping_edges(L)
    assert d["overlapping_edges"] == len(overlapping) >= 1
    assert {i for i, e in enumerate(L["edges"]) if "overlapping_edges" in e["defects"]} == overlapping
    for x in locations(L, "overlapping_edges"):
        # The touching point lies on both edges.
        for e in x["edges"]:
            assert np.min(np.linalg.norm(np.asarray(L["edges"][e]["points"]) - x["position"], axis=1)) < 1e-9
    # Valence 2 away from the sheet's corners (where the part forces it).
    # (The arcs across the thin strip are single refined edges between two crossings; since
    # such arcs get an inner vertex, their primal edges exist and no vertex is left with two.)
    valence2 = {i for i, v in enumerate(L["vertices"]) if v["valence"] == 2 and v["placement"] != "corner"}
    assert d["valence2_vertices"] == len(valence2)
    for x in locations(L, "valence2"):
        assert x["vertex"] in valence2
        assert np.allclose(x["position"], L["vertices"][x["vertex"]]["position"])
    # Every location is on the sheet and says where in words.
    for x in L["defect_locations"]:
        assert abs(x["position"][2]) < 1e-9 and all(-1e-9 <= c <= 10 + 1e-9 for c in x["position"][:2])
        assert "(" in x["text"] and x["text"].endswith(")")


def test_sphere_cut_by_two_great_circles_has_four_valence_two_vertices():
    """Two great circles cut a sphere into four lunes of two sides each: every primal vertex has
    valence 2 (an inner vertex of two edges is a 180-degree corner); nothing else is wrong."""
    L = loops_layout(LoopSession(sw.from_shape(sphere(5), target_triangles=8000)), [a for (a,) in TWO_GREAT_CIRCLES])
    assert L["valid"] and not L["clean"]
    assert [v["valence"] for v in L["vertices"]] == [2] * 4
    assert L["defects"] == {k: 4 if k == "valence2_vertices" else 0 for k in DEFECT_KEYS}
    assert sorted(x["vertex"] for x in locations(L, "valence2")) == [0, 1, 2, 3]
    for x in L["defect_locations"]:
        assert np.linalg.norm(x["position"]) == pytest.approx(5, rel=0.01)
        assert np.allclose(x["position"], L["vertices"][x["vertex"]]["position"])
    assert all(v["defects"] == ["valence2"] for v in L["vertices"])


def test_a_heptagon_region_gives_a_high_valence_vertex():
    """Seven straight curves tangent to a circle of radius 2 round the sheet's centre bound a
    heptagonal region: its vertex has 7 edges, and no corner of the (flat) part forces them."""
    session = LoopSession(sw.from_shape(Part.makePlane(10, 10), target_triangles=8000), boundary="trimmed")
    anchors = [(5 + 2 * math.cos(a), 5 + 2 * math.sin(a), 0, -math.sin(a), math.cos(a), 0)
               for a in (2 * math.pi * k / 7 for k in range(7))]
    L = loops_layout(session, anchors)
    high = [i for i, v in enumerate(L["vertices"]) if v["valence"] > 6]
    assert len(high) == 1 and L["vertices"][high[0]]["valence"] == 7
    assert L["defects"]["high_valence_vertices"] == 1 and not L["clean"]
    assert "high_valence" in L["vertices"][high[0]]["defects"]
    (x,) = locations(L, "high_valence")
    assert x["vertex"] == high[0] and np.linalg.norm(np.subtract(x["position"], (5, 5, 0))) < 1.0


def test_valences_a_part_corner_forces_are_no_defect(sheet, cube_layout):
    """A sheet cut by one curve each way has one patch whose corners are the sheet's: valence
    2 there is the part's, not the layout's. The cube's vertices sit at its corners, where
    three creases meet: they may have 3 edges, and more than 6 only if more creases met."""
    L = loops_layout(sheet, [(5, 3, 0, 1, 0, 0), (3, 5, 0, 0, 1, 0)])
    assert [v["valence"] for v in L["vertices"]] == [2] * 4
    assert all(v["forced_valence"] == 2 and v["defects"] == [] for v in L["vertices"])
    assert L["clean"] and L["defects"]["valence2_vertices"] == 0
    _, cube = cube_layout
    assert [(v["placement"], v["forced_valence"]) for v in cube["vertices"]] == [("corner", 3)] * 8


def test_a_curve_curling_across_itself_leaves_a_dangling_edge_and_a_folded_patch():
    """An open curve over a sheet that curls across itself, (0, 3.3) -> (7.3, 3.3) ->
    (7.3, 7.3) -> (3.3, 7.3) -> (3.3, 0), bounds a lobe of one arc: the lobe's vertex has one
    edge, whose tip is a corner of 360 degrees, and the patch at the crossing wraps around it,
    its side into the lobe run out and straight back. Read from layout.json alone (edge ends,
    each patch's sides): that vertex is flagged valence2 and that patch non_quad, and the
    layout is not clean, though every region is a disc."""
    from test_regions import grid_sheet, trace
    sheet = sw.from_mesh(*grid_sheet(20), target_triangles=0)
    curl = trace(sheet, [(0, 3.3), (7.3, 3.3), (7.3, 7.3), (3.3, 7.3), (3.3, 0)])
    L = layout_json(native.layout_of_paths(sheet, [curl], details=True))
    assert L["valid"] and not L["clean"]
    ends = [0] * len(L["vertices"])
    for e in L["edges"]:
        for v in e["vertices"]:
            ends[v] += 1
    (tip,) = [v for v, n in enumerate(ends) if n == 1]
    assert not L["vertices"][tip]["boundary"] and L["vertices"][tip]["defects"] == ["valence2"]
    x, y, _ = L["vertices"][tip]["position"]
    assert 3.3 < x < 7.3 and 3.3 < y < 7.3                # inside the lobe
    folded = [i for i, p in enumerate(L["patches"])
              if any(p["edges"][k] == p["edges"][(k + 1) % 4] and p["reversed"][k] != p["reversed"][(k + 1) % 4]
                     for k in range(4))]
    assert folded and all("non_quad" in L["patches"][i]["defects"] for i in folded)
    assert L["defects"]["valence2_vertices"] == 1 and L["defects"]["non_quad_patches"] == len(folded)
    assert [x["vertex"] for x in locations(L, "valence2")] == [tip]


def test_the_patch_network_holds_only_the_edges_its_patches_have_as_sides():
    """The curling curve's layout has a dangling edge (into the lobe, to a vertex of valence
    1) and the patch folded around it; a straight curve across the curl's first leg adds a
    patch that is a quad. The surfacing stage gets the patches that are quads, not the
    folded one (its fit would fold), and only their sides: an edge
    no patch has as a side is no seam, and one whose path is a single point (two primal
    vertices on one refined vertex, seen on a range scan) stopped the refit ("network edge
    has fewer than 2 points")."""
    from test_regions import grid_sheet, trace
    sheet = sw.from_mesh(*grid_sheet(20), target_triangles=0)
    curl = trace(sheet, [(0, 3.3), (7.3, 3.3), (7.3, 7.3), (3.3, 7.3), (3.3, 0)])
    across = trace(sheet, [(1.6, 0), (1.6, 10)])
    L = layout_json(native.layout_of_paths(sheet, [curl, across], details=True))
    net = native.network_of_paths(sheet, [curl, across])
    sides = {e for p in net["patches"] for e in p["edges"]}
    assert sides == set(range(len(net["edges"])))
    assert all(len(e["points"]) >= 2 for e in net["edges"])
    # The dangling edge is not handed over: fewer edges than the layout's.
    ends = [0] * len(L["vertices"])
    for e in L["edges"]:
        for v in e["vertices"]:
            ends[v] += 1
    dangling = [e for e in L["edges"] if any(ends[v] == 1 for v in e["vertices"])]
    assert dangling and len(net["edges"]) <= len(L["edges"]) - len(dangling)
    folded = [p for p in L["patches"] if "non_quad" in p["defects"]]
    assert folded and len(net["patches"]) == len(L["patches"]) - len(folded) >= 1
    for p in net["patches"]:
        for k in range(4):
            e = net["edges"][p["edges"][k]]
            start = e["points"][-1] if p["reversed"][k] else e["points"][0]
            assert np.allclose(p["vertices"][p["corners"][k]], start)


def test_one_vertex_torus_patch_is_a_quad():
    """The torus's meridian and equator give one patch whose four corners are one vertex: four
    sides, each a closed edge around the torus, so a quad layout of one patch (paper §2), clean."""
    ds = DesignSession(sw.from_shape(torus(10, 3), target_triangles=16000), Design([MERIDIAN, OUTER_EQUATOR]))
    L = compute_layout(ds)
    (p,) = L["patches"]
    assert p["quad"] and p["corners"] == [0, 0, 0, 0]
    assert all(L["edges"][e]["length"] > 15 for e in p["edges"])   # closed edges of real length
    assert L["defects"]["non_quad_patches"] == 0 and p["defects"] == [] and L["clean"]

def test_cube_with_three_belts_is_clean(cube_layout):
    ds, L = cube_layout
    assert L["valid"] and L["clean"]
    assert L["defects"] == {k: 0 for k in DEFECT_KEYS} and L["defect_locations"] == []
    assert all(p["defects"] == [] and len(set(p["corners"])) == 4 for p in L["patches"])
    assert all(v["defects"] == [] for v in L["vertices"])
    # A face's patch is 10 wide: its inscribed radius is about 5.
    assert [p["inradius"] for p in L["patches"]] == pytest.approx([5] * 6, rel=0.05)
    report = make_report(ds, L, {})
    assert report["clean"] and report["defects"] == L["defects"]
    assert format_defects(L["clean"], L["defects"], L["defect_locations"]).startswith("clean")


def test_a_thin_patch_is_degenerate(sheet):
    """Curves at x = 0.2 and 0.55 and one across: the patch between the sheet's edge and the
    middle of the strip is about 0.3 wide, its inscribed radius under 2 solver edges (0.18
    each); the other patch, 9.7 wide, is fine."""
    L = loops_layout(sheet, [(0.2, 3, 0, 0, 1, 0), (0.55, 3, 0, 0, 1, 0), (3, 5, 0, 1, 0, 0)])
    assert L["valid"] and len(L["patches"]) == 2 and not L["clean"]
    widths = [max(L["vertices"][c]["position"][0] for c in p["corners"]) -
              min(L["vertices"][c]["position"][0] for c in p["corners"]) for p in L["patches"]]
    thin = int(np.argmin(widths))
    assert widths[thin] < 0.5 and widths[1 - thin] > 9
    # Half the width, measured over mesh edges (a little longer than straight).
    assert L["patches"][thin]["inradius"] == pytest.approx(widths[thin] / 2, rel=0.3)
    assert L["defects"] == {k: 1 if k == "degenerate_patches" else 0 for k in DEFECT_KEYS}
    assert L["patches"][thin]["defects"] == ["degenerate"] and L["patches"][1 - thin]["defects"] == []
    (x,) = locations(L, "degenerate")
    assert x["patch"] == thin and 0 <= x["position"][0] <= widths[thin] + 1e-9


def test_a_thin_walls_patches_are_as_narrow_as_the_part_and_not_degenerate(tmp_path):
    """A plate 0.5 thick: its side walls are under two solver edges wide, so every patch on
    them has an inscribed radius under the degenerate bound. The part forces that width (the
    patch spans its wall from crease to crease), so they are no defect: the plate weaves into
    the clean six patches of a box. Without the rule they were flagged degenerate, and
    refinement split the walls into ever shorter slivers (46 patches, 24 degenerate)."""
    surface = sw.from_shape(Part.makeBox(10, 6, 0.5), target_triangles=8000)
    h = mean_edge_length(surface)
    report = sw.weave(surface, out=str(tmp_path))
    L = json.load(open(tmp_path / "layout.json"))
    narrow = [p for p in L["patches"] if p["inradius"] < 2 * h]
    assert len(narrow) >= 2                  # the walls' patches, under the radius bound
    assert all(p["inradius"] >= 0.2 for p in narrow)   # ... yet as wide as the wall (0.25)
    assert report["defects"]["degenerate_patches"] == 0
    assert report["clean"] and report["patches"] == 6


def test_patches_over_a_crease_are_counted():
    """Two loops through the capped cylinder's axis leave each rim inside patches: both are
    creased; the box-like design puts the rims on patch sides: none is."""
    shape = capped_cylinder(5, 20)
    halves = compute_layout(DesignSession(sw.from_shape(shape, target_triangles=8000),
                                          Design([[(5, 0, 10, 0, 0, 1)], [(0, 5, 10, 0, 0, 1)]])))
    assert halves["valid"] and not halves["clean"]
    assert halves["defects"]["creased_patches"] == 2 == sum(p["creased"] for p in halves["patches"])
    assert all("creased" in p["defects"] for p in halves["patches"])
    for x in locations(halves, "creased"):
        r = math.hypot(x["position"][0], x["position"][1])
        assert r <= 5 + 1e-6 and -1e-6 <= x["position"][2] <= 20 + 1e-6   # on the part
    box_like = Design([[(5, 0, 10, 0, 1, 0)], [(-5, 0, 10, 0, 0, 1)], [(0, 5, 10, 0, 0, 1)]])
    boxed = compute_layout(DesignSession(sw.from_shape(shape, target_triangles=8000), box_like))
    assert boxed["defects"]["creased_patches"] == 0


def test_an_invalid_design_leaves_every_surface_triangle_uncovered():
    ds = DesignSession(sw.from_shape(torus(10, 3), target_triangles=8000), Design([MERIDIAN]))
    L = compute_layout(ds)
    assert not L["valid"] and not L["clean"] and L["patches"] == []
    n = len(ds.surface.triangles)
    assert L["defects"]["uncovered_triangles"] == n > 0
    (x,) = locations(L, "uncovered")        # the torus is one piece
    assert x["triangles"] == n
    text = format_defects(L["clean"], L["defects"], L["defect_locations"])
    assert text.startswith("NOT clean") and f"{n} surface triangles in no patch or in two at (" in text
    report = make_report(ds, L, {})
    assert not report["valid"] and not report["clean"] and report["defects"]["uncovered_triangles"] == n


def test_report_json_and_layout_json_agree_and_the_cli_names_the_defects(tmp_path):
    model = tmp_path / "ball.brep"
    sphere(5).exportBrep(str(model))
    design = tmp_path / "two.json"
    Design(TWO_GREAT_CIRCLES).save(str(design))
    out = tmp_path / "out"
    run = subprocess.run([CLI, "weave", str(model), "--design", str(design), "--out", str(out),
                          "--target-triangles", "8000"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    report = json.loads((out / "report.json").read_text())
    layout = json.loads((out / "layout.json").read_text())
    assert report["valid"] and report["clean"] is False and layout["clean"] is False
    assert report["defects"] == layout["defects"]
    assert set(report["defects"]) == set(DEFECT_KEYS) and report["defects"]["valence2_vertices"] == 4
    first = locations(layout, "valence2")[0]["position"]
    assert "NOT clean" in run.stdout and "4 vertices of valence 2 or 1 (first at (" in run.stdout
    assert "(" + ", ".join(f"{c:.4g}" for c in first) + ")" in run.stdout
    # `stripweave layout` says the same.
    run = subprocess.run([CLI, "layout", str(model), "--design", str(design), "--out", str(tmp_path / "l"),
                          "--target-triangles", "8000"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "NOT clean" in run.stdout and "4 vertices of valence 2" in run.stdout


# Curves on the sheet a few solver edges apart (generated at random, kept where the first
# pass of the primal edges' routing left an edge without a corridor).
NARROW_CORRIDORS = [
    [(2.746, 5, 0, 0, 1, 0), (3.299, 5, 0, 0, 1, 0), (3.578, 5, 0, 0, 1, 0), (6.907, 5, 0, 0, 1, 0),
     (5, 4.183, 0, 1, 0, 0)],
    [(3.285, 5, 0, 0, 1, 0), (3.806, 5, 0, 0, 1, 0), (5, 2.995, 0, 1, 0, 0), (5, 3.126, 0, 1, 0, 0),
     (5, 5.088, 0, 1, 0, 0)],
]


@pytest.mark.parametrize("anchors", NARROW_CORRIDORS)
def test_an_edge_is_said_to_overlap_only_if_it_still_does_once_every_edge_is_routed(sheet, anchors):
    """Routing one edge after another can close an edge's corridor that rerouting the edges in
    its way opens again (primal_edges.cpp: rip-up and reroute). The layout says an edge
    "overlaps" only of the edges that still share a vertex in the end; here every edge ends
    with a corridor of its own, and none is said to overlap (the first pass alone named one)."""
    L = loops_layout(sheet, anchors)
    assert L["valid"]
    said = {int(p.split()[1]) for p in L["problems"] if "free corridor" in p}
    overlapping_arcs = {L["edges"][e]["arc"] for e in overlapping_edges(L)}
    assert said <= overlapping_arcs
    assert not overlapping_arcs and not said and L["defects"]["overlapping_edges"] == 0
