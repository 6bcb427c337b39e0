"""Primalization (paper §7): the quad layout of a valid design, analytic checks in model units.

Structure: one vertex per region, one edge per arc, one quad patch per crossing, so
V - E + F is the Euler characteristic. Geometry: vertices at corners / boundary /
singularities / centres, edges on creases and boundaries where their corridors hold them.
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
from models import box, capped_cylinder, sphere, torus
from stripweave.design import Design
from stripweave.layout import compute_layout
from stripweave.loops import LoopSession
from stripweave.strips import DesignSession
from test_regions import check_topology, clipped_line, grid_cube, grid_sheet, trace

native = sw._native

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CUBE_BELTS = [[(5, 5, 10, 1, 0, 0)], [(5, 3, 0, 0, 1, 0)], [(3, 0, 5, 1, 0, 0)]]
MERIDIAN = [(13, 0, 0, 0, 0, 1)]
OUTER_EQUATOR = [(0, 13, 0, 1, 0, 0)]
GREAT_CIRCLES = [[(5, 0, 0, 0, 1, 0)], [(0, 5, 0, 0, 0, 1)], [(0, 0, 5, 1, 0, 0)]]
SHEET_CORNERS = [(0, 0, 0), (10, 0, 0), (10, 10, 0), (0, 10, 0)]


def check_layout(L):
    """What every layout must satisfy: the structure of §7, closed patch cycles, Euler."""
    s = L["summary"]
    e = s["euler"]
    assert (e["V"], e["E"], e["F"]) == (len(L["vertices"]), len(L["edges"]), len(L["patches"]))
    assert e["V"] - e["E"] + e["F"] == e["chi"]
    assert L["problems"] == []
    assert len(L["vertices"]) == len(L["regions"])
    assert len(L["patches"]) == L["crossings"]
    ends = [0] * len(L["vertices"])
    for edge in L["edges"]:
        pts = np.asarray(edge["points"])
        i, j = edge["vertices"]
        assert np.allclose(pts[0], L["vertices"][i]["position"]) and np.allclose(pts[-1], L["vertices"][j]["position"])
        ends[i] += 1
        ends[j] += 1
    assert ends == [v["valence"] for v in L["vertices"]]
    for p in L["patches"]:
        assert p["quad"] and len(p["edges"]) == 4
        # Side k runs from corner k to corner k + 1.
        for k in range(4):
            i, j = L["edges"][p["edges"][k]]["vertices"]
            a, b = (j, i) if p["reversed"][k] else (i, j)
            assert a == p["corners"][k] and b == p["corners"][(k + 1) % 4]


def on_cube_edge(p, size=10.0, tol=0.1):
    """Distance-based: at least two coordinates on a face plane (0 or size)."""
    return sum(min(abs(c), abs(c - size)) <= tol for c in p) >= 2


@pytest.fixture(scope="module")
def cube_layout():
    ds = DesignSession(sw.from_shape(box(10), target_triangles=12000), Design(CUBE_BELTS))
    return ds, compute_layout(ds)


def test_cube_three_belts_give_six_patches_on_the_cube_faces(cube_layout):
    ds, L = cube_layout
    check_layout(L)
    assert L["valid"]
    assert [r["valence"] for r in L["regions"]] == [3] * 8
    for r in L["regions"]:
        assert r["total_curvature"] == pytest.approx(math.pi / 2, abs=1e-6)
    assert (len(L["patches"]), len(L["edges"]), len(L["vertices"])) == (6, 12, 8)
    # Vertices at the cube's corners, edges along its sharp edges (within 1% of the edge length).
    corners = {tuple(round(c) for c in v["position"]) for v in L["vertices"]}
    assert corners == {(x, y, z) for x in (0, 10) for y in (0, 10) for z in (0, 10)}
    for v in L["vertices"]:
        assert v["valence"] == 3 and v["placement"] == "corner"
        assert np.allclose(v["position"], np.round(v["position"]), atol=1e-9)
    for e in L["edges"]:
        assert e["sharp"]
        assert e["length"] == pytest.approx(10, rel=0.01)
        for p in e["points"]:
            assert on_cube_edge(p, tol=0.1)
    for p in L["patches"]:
        assert p["area"] == pytest.approx(100, rel=0.02)
        assert p["corner_angles_deg"] == pytest.approx([90] * 4, abs=1.0)
    assert L["summary"]["irregular_vertices"] == {"3": 8}
    assert L["summary"]["corner_deviation_deg"]["max"] < 1.0


def test_torus_meridian_and_equator_give_one_patch_at_one_vertex():
    ds = DesignSession(sw.from_shape(torus(10, 3), target_triangles=16000), Design([MERIDIAN, OUTER_EQUATOR]))
    L = compute_layout(ds)
    check_layout(L)
    assert L["valid"]
    (region,) = L["regions"]
    assert region["disc"] and region["valence"] == 4
    assert (len(L["patches"]), len(L["edges"]), len(L["vertices"])) == (1, 2, 1)
    (v,) = L["vertices"]
    assert v["valence"] == 4 and not v["boundary"]
    # The single vertex is all four corners of the single patch, which covers the torus.
    (p,) = L["patches"]
    assert p["corners"] == [0, 0, 0, 0]
    assert p["area"] == pytest.approx(4 * math.pi ** 2 * 10 * 3, rel=0.01)
    # Each primal edge is a closed curve around the torus crossing its loop once.
    for e in L["edges"]:
        pts = np.asarray(e["points"])
        assert np.allclose(pts[0], pts[-1])
        assert e["length"] > 2 * math.pi * 3 * 0.95


def test_layout_with_an_extra_loop_is_the_layout_of_all_loops():
    """Automatic weaving predicts a candidate strip by DesignState.layout_with: the design's
    loops (as derived) and the candidate under the design's singularities, without a solve.
    On the torus, the meridian's design with the outer equator as the extra loop must give
    the one-patch layout, the same as the layout of both loops from scratch."""
    from stripweave._native import native
    ds = DesignSession(sw.from_shape(torus(10, 3), target_triangles=16000), Design([MERIDIAN]))
    session = ds.loop_session.native
    ds.native.apply_mask()                       # as weaving asks: compatible with the meridian
    (equator,) = session.loops([list(OUTER_EQUATOR[0])], 1, True)
    session.clear_disabled()
    predicted = ds.native.layout_with([equator])
    sing = ds.singularities()
    direct = native.layout(session, list(native.design_loops(ds.native)) + [equator],
                           [x["vertex"] for x in sing], [round(4 * x["index"]) for x in sing], False)
    assert predicted["valid"] and len(predicted["patches"]) == 1
    assert predicted["patches"] == direct["patches"] and predicted["summary"] == direct["summary"]
    assert predicted["patches"][0]["area"] == pytest.approx(4 * math.pi ** 2 * 10 * 3, rel=0.01)
    assert not ds.native.layout()["valid"]       # the design itself is unchanged: one loop


def test_a_regular_vertex_sits_midway_between_its_sides():
    """Meridians 60 degrees apart and the outer and inner equators cut a torus into four
    valence-4 regions, one a 300-degree band. Its vertex belongs where the middles of its
    corridors cross (§7), half-way round the band (210 degrees), not anywhere along the
    band's ridge, all of which is equally far from the loops."""
    a = math.radians(60)
    design = Design([MERIDIAN, [(13 * math.cos(a), 13 * math.sin(a), 0, 0, 0, 1)], OUTER_EQUATOR, [(0, 7, 0, 1, 0, 0)]],
                    options={"compatibility_band": 3.0})
    L = compute_layout(DesignSession(sw.from_shape(torus(10, 3), target_triangles=16000), design))
    check_layout(L)
    assert len(L["patches"]) == 4 and L["summary"]["irregular_vertices"] == {}
    azimuths = sorted(math.degrees(math.atan2(v["position"][1], v["position"][0])) % 360 for v in L["vertices"])
    assert azimuths[:2] == pytest.approx([30, 30], abs=10)      # the 60-degree band's vertices
    assert azimuths[2:] == pytest.approx([210, 210], abs=15)    # the 300-degree band's


def test_torus_meridian_alone_has_no_layout():
    ds = DesignSession(sw.from_shape(torus(10, 3), target_triangles=16000), Design([MERIDIAN]))
    L = compute_layout(ds)
    assert not L["valid"]
    assert [r["colour"] for r in L["regions"]] == ["red"]
    assert L["vertices"] == [] and L["edges"] == [] and L["patches"] == []


def test_sphere_three_great_circles_give_six_patches_and_eight_valence_three_vertices():
    ds = DesignSession(sw.from_shape(sphere(5), target_triangles=12000), Design(GREAT_CIRCLES))
    L = compute_layout(ds)
    check_layout(L)
    assert len(L["patches"]) == 6 and len(L["vertices"]) == 8
    assert [v["valence"] for v in L["vertices"]] == [3] * 8
    assert L["summary"]["irregular_vertices"] == {"3": 8}
    # Each vertex lies on the sphere, inside its octant.
    for v in L["vertices"]:
        p = np.asarray(v["position"])
        assert np.linalg.norm(p) == pytest.approx(5, rel=0.01)
        assert np.all(np.abs(p) > 1.0)
    assert sum(p["area"] for p in L["patches"]) == pytest.approx(4 * math.pi * 25, rel=0.01)


@pytest.fixture(scope="module")
def square_session():
    return LoopSession(sw.from_shape(Part.makePlane(10, 10), target_triangles=8000))


def sheet_layout(session, anchors):
    loops = [session.native.loops([list(a)], 1, True)[0] for a in anchors]
    L = native.layout(session.native, loops)
    check_layout(L)
    return L


def test_square_sheet_one_curve_each_way_gives_one_patch_at_the_corners(square_session):
    L = sheet_layout(square_session, [(5, 3, 0, 1, 0, 0), (3, 5, 0, 0, 1, 0)])
    assert L["valid"] and len(L["patches"]) == 1
    assert sorted(tuple(np.round(v["position"], 6)) for v in L["vertices"]) == sorted(SHEET_CORNERS)
    for v in L["vertices"]:
        assert v["boundary"] and v["placement"] == "corner" and v["valence"] == 2
    # The edges follow the boundary between its corners.
    for e in L["edges"]:
        assert e["boundary"]
        assert e["length"] == pytest.approx(10, rel=1e-6)
    (p,) = L["patches"]
    assert p["area"] == pytest.approx(100, rel=1e-6)
    assert p["corner_angles_deg"] == pytest.approx([90] * 4, abs=1e-6)


def test_square_sheet_two_curves_each_way_give_four_patches(square_session):
    anchors = [(5, 3, 0, 1, 0, 0), (5, 7, 0, 1, 0, 0), (3, 5, 0, 0, 1, 0), (7, 5, 0, 0, 1, 0)]
    L = sheet_layout(square_session, anchors)
    assert L["valid"] and len(L["patches"]) == 4 and len(L["vertices"]) == 9 and len(L["edges"]) == 12
    boundary = [v for v in L["vertices"] if v["boundary"]]
    inner = [v for v in L["vertices"] if not v["boundary"]]
    assert len(boundary) == 8 and len(inner) == 1
    # The inner vertex is the centre of the middle region; the corner regions' vertices are the corners.
    assert inner[0]["valence"] == 4
    assert np.allclose(inner[0]["position"], (5, 5, 0), atol=0.5)
    corners = [v for v in boundary if v["placement"] == "corner"]
    assert sorted(tuple(np.round(v["position"], 6)) for v in corners) == sorted(SHEET_CORNERS)
    assert sum(p["area"] for p in L["patches"]) == pytest.approx(100, rel=1e-6)
    for p in L["patches"]:
        assert p["area"] == pytest.approx(25, rel=0.1)


def test_layout_of_loops_through_mesh_vertices():
    """Near-degenerate input: on a structured cube the belts run along mesh edges and cross
    at mesh vertices; the layout is still the cube's."""
    session = LoopSession(sw.from_mesh(*grid_cube(10), target_triangles=0))
    loops = [session.native.loops([list(a)], 1, True)[0] for (a,) in CUBE_BELTS]
    L = native.layout(session.native, loops)
    check_layout(L)
    assert (len(L["patches"]), len(L["edges"]), len(L["vertices"])) == (6, 12, 8)
    for p in L["patches"]:
        assert p["area"] == pytest.approx(100, rel=1e-9)


def octagon_lines(centre, half_width, diagonal_distance):
    """Eight chords of the square [0,10]^2: two each way along x and y at `half_width` from
    `centre`, and two along each diagonal at `diagonal_distance`. With half_width <
    diagonal_distance < half_width * sqrt(2) the diagonals cut the corners of the middle
    square, so the middle region is an octagon: a primal vertex of valence 8."""
    c = np.asarray(centre, float)
    lines = [clipped_line(c + (0, s * half_width), 0.0) for s in (-1, 1)]
    lines += [clipped_line(c + (s * half_width, 0), math.pi / 2) for s in (-1, 1)]
    for angle in (math.pi / 4, 3 * math.pi / 4):
        normal = np.array([-math.sin(angle), math.cos(angle)])
        lines += [clipped_line(c + s * diagonal_distance * normal, angle) for s in (-1, 1)]
    return lines


def test_a_vertex_of_valence_eight_has_its_edges_apart_on_a_valence_six_mesh():
    """A region of valence 8 on a structured sheet whose vertices have 6 neighbours: the 8
    primal edges cannot leave its vertex through 6 neighbours without sharing, so the layout
    had overlapping edges and patches without four sides. Refining the mesh around crowded
    vertices (star_refinement.h) gives every patch its four sides; the refined arrangement
    stays a manifold refinement of the sheet, the patches tile it, and the vertex stays at
    the octagon's centre."""
    sheet = sw.from_mesh(*grid_sheet(40), target_triangles=0)
    centre = (5.0137, 5.0137)  # off the grid's lines, so no loop runs along a mesh edge
    paths = [trace(sheet, line) for line in octagon_lines(centre, 1.6, 1.95)]
    L = native.layout_of_paths(sheet, paths)
    check_topology(L)
    check_layout(L)
    assert len(L["patches"]) == L["crossings"] == 24
    (octagon,) = [v for v in L["vertices"] if v["valence"] == 8]
    assert np.linalg.norm(np.asarray(octagon["position"])[:2] - centre) < 0.5
    assert sum(p["area"] for p in L["patches"]) == pytest.approx(100, rel=1e-9)
    assert not any(L["defects"][k] for k in ("non_quad_patches", "overlapping_edges", "uncovered_triangles"))


def test_layout_with_crossings_near_a_vertex(square_session):
    """Two curves crossing a hair away from a mesh vertex still give one clean patch."""
    sheet = square_session.surface
    v = sheet.vertices[np.argmin(np.linalg.norm(sheet.vertices - (5, 5, 0), axis=1))]
    L = sheet_layout(square_session, [(v[0] + 1e-7, v[1], 0, 1, 0, 0), (v[0], v[1] + 1e-7, 0, 0, 1, 0)])
    assert L["valid"] and len(L["patches"]) == 1
    assert L["patches"][0]["area"] == pytest.approx(100, rel=1e-6)


def test_patch_network_hands_over_discs_with_four_corners(cube_layout):
    ds, L = cube_layout
    net = ds.native.patch_network()
    assert len(net["patches"]) == 6 and len(net["edges"]) == 12
    assert net["bbox_diagonal"] == pytest.approx(10 * math.sqrt(3), rel=1e-9)
    for p in net["patches"]:
        V, T = p["vertices"], p["triangles"]
        # A disc: V - E + F = 1.
        edges = {tuple(sorted(e)) for t in T.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
        assert len(V) - len(edges) + len(T) == 1
        for k in range(4):
            e = net["edges"][p["edges"][k]]
            start = e["points"][-1] if p["reversed"][k] else e["points"][0]
            assert np.allclose(V[p["corners"][k]], start)
        assert len(p["source_face"]) == len(T)


def test_layout_cli_writes_layout_json(tmp_path):
    step = tmp_path / "cube.brep"
    box(10).exportBrep(str(step))
    design = tmp_path / "cube.json"
    Design(CUBE_BELTS).save(str(design))
    out = tmp_path / "out"
    run = subprocess.run([os.path.join(REPO, "build", "stripweave"), "layout", str(step), "--design", str(design),
                          "--out", str(out), "--target-triangles", "12000", "--json"],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    summary = json.loads(run.stdout)
    assert summary["valid"] and summary["summary"]["patches"] == 6
    L = json.loads((out / "layout.json").read_text())
    assert L["valid"] and len(L["patches"]) == 6 and len(L["vertices"]) == 8 and len(L["edges"]) == 12
    # The file holds the layout itself, not only its keys: the structure of §7 (closed patch
    # cycles, edges from vertex to vertex, Euler), the cube's corners and edges and faces.
    check_layout(L)
    assert all(r["disc"] and r["valence"] == 3 and r["colour"] == "none" for r in L["regions"])
    assert sum(r["total_curvature"] for r in L["regions"]) == pytest.approx(4 * math.pi, abs=1e-6)
    corners = {tuple(round(c) for c in v["position"]) for v in L["vertices"]}
    assert corners == {(x, y, z) for x in (0, 10) for y in (0, 10) for z in (0, 10)}
    assert all(v["valence"] == 3 and not v["boundary"] for v in L["vertices"])
    for e in L["edges"]:
        assert all(on_cube_edge(p, tol=0.1) for p in e["points"])
    for p in L["patches"]:
        assert len(p["edges"]) == 4 and p["area"] == pytest.approx(100, rel=0.02)


def test_layout_cli_names_a_missing_design(tmp_path):
    step = tmp_path / "cube.brep"
    box(10).exportBrep(str(step))
    run = subprocess.run([os.path.join(REPO, "build", "stripweave"), "layout", str(step), "--design",
                          str(tmp_path / "nope.json"), "--out", str(tmp_path)], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode != 0
    assert "nope.json" in run.stderr


def test_patches_over_creases_are_marked():
    """layout.json's patches tell how much crease lies inside them ("crease_length", model
    units) and whether that makes them "creased" (more than 1% of the diagonal): the
    capped cylinder's box design puts every rim on patch sides (none creased), two loops
    through the axis leave the rims to two patches, which hold at least one whole rim
    (2 pi 5) and less than both."""
    shape = capped_cylinder(5, 20)
    boxed = DesignSession(sw.from_shape(shape, target_triangles=8000),
                          Design([[(5, 0, 10, 0, 1, 0)], [(-5, 0, 10, 0, 0, 1)], [(0, 5, 10, 0, 0, 1)]]))
    L = boxed.native.layout()
    assert len(L["patches"]) == 6 and not any(p["creased"] for p in L["patches"])
    assert all(p["crease_length"] == 0 for p in L["patches"])
    halves = DesignSession(sw.from_shape(shape, target_triangles=8000),
                           Design([[(5, 0, 10, 0, 0, 1)], [(0, 5, 10, 0, 0, 1)]]))
    L = halves.native.layout()
    assert len(L["patches"]) == 2 and all(p["creased"] for p in L["patches"])
    inside = sum(p["crease_length"] for p in L["patches"])
    assert 2 * math.pi * 5 < inside < 4 * math.pi * 5


# --- Pinned primal vertices (paper §7: a vertex dragged within its region) ---------------

def _octant_vertex(L, signs):
    return next(i for i, v in enumerate(L["vertices"]) if all(np.sign(v["position"]) == np.sign(signs)))


def test_a_pinned_vertex_moves_to_the_pin_and_the_others_stay():
    """Three great circles on a sphere of radius 5: a pin in the (+,+,+) octant, off its
    singularity, moves that region's vertex to the surface point nearest the pin (within one
    solver edge); the seven other vertices keep their places, and the layout keeps its six
    quad patches, now with the corners the moved vertex gives them."""
    surface = sw.from_shape(sphere(5), target_triangles=12000)
    ds = DesignSession(surface, Design(GREAT_CIRCLES))
    before = compute_layout(ds)
    k = _octant_vertex(before, (1, 1, 1))
    assert before["vertices"][k]["placement"] == "singularity"
    pin = 5 * np.array([0.8, 0.3, 0.52]) / np.linalg.norm([0.8, 0.3, 0.52])
    ds.design.pins = [list(pin)]
    ds.update()
    after = compute_layout(ds)
    check_layout(after)
    assert len(after["patches"]) == 6 and after["clean"]
    moved = after["vertices"][_octant_vertex(after, (1, 1, 1))]
    assert moved["placement"] == "pinned"
    edge = math.sqrt(4 * math.pi * 25 / 12000 * 4 / math.sqrt(3))   # a solver edge, about
    assert np.linalg.norm(np.asarray(moved["position"]) - pin) <= edge
    others = lambda L: sorted(tuple(np.round(v["position"], 9)) for v in L["vertices"]
                              if not all(np.sign(v["position"]) == 1))
    assert others(after) == others(before)
    # The patches at the moved vertex changed shape: its three corners turned.
    def corners_at(L, k):
        return sorted(p["corner_angles_deg"][i] for p in L["patches"] for i, c in enumerate(p["corners"]) if c == k)
    turned = np.abs(np.subtract(corners_at(before, k), corners_at(after, _octant_vertex(after, (1, 1, 1)))))
    assert len(turned) == 3 and turned.max() > 5
    # No pin, the layout of before.
    ds.design.pins = []
    ds.update()
    assert compute_layout(ds)["vertices"] == before["vertices"]


def test_the_layout_names_the_pins_of_each_vertex():
    """Which pin is whose is the layout's rule, told in layout.json (the vertex key "pins"),
    so that an editor moving a vertex replaces the pins of its region: two pins in the
    (+,+,+) octant (the last places the vertex) and one in the (-,-,+) octant; a pin at a
    corner of the part, which keeps the vertex, is still the corner's."""
    surface = sw.from_shape(sphere(5), target_triangles=8000)
    unit = lambda v: list(5 * np.asarray(v) / np.linalg.norm(v))
    pins = [unit([0.8, 0.3, 0.52]), unit([-0.8, -0.3, 0.52]), unit([0.3, 0.8, 0.52])]
    L = compute_layout(DesignSession(surface, Design(GREAT_CIRCLES, pins=pins)))
    a, b = _octant_vertex(L, (1, 1, 1)), _octant_vertex(L, (-1, -1, 1))
    assert L["vertices"][a]["pins"] == [0, 2] and L["vertices"][b]["pins"] == [1]
    assert all(v["pins"] == [] for i, v in enumerate(L["vertices"]) if i not in (a, b))
    edge = math.sqrt(4 * math.pi * 25 / 8000 * 4 / math.sqrt(3))
    assert np.linalg.norm(np.asarray(L["vertices"][a]["position"]) - pins[2]) <= edge


def test_a_pin_keeps_a_corner_of_the_part_and_a_crease_vertex_on_its_crease(cube_layout):
    """Pins move vertices only where the rules let them: a cube corner (a crease junction)
    stays where it is, and a vertex on a crease slides along the crease to the crease point
    nearest the pin, so the layout stays crease-conforming."""
    ds, before = cube_layout
    pinned = DesignSession(ds.surface, Design(CUBE_BELTS, pins=[[8.0, 9.0, 9.5]]))
    L = compute_layout(pinned)
    assert [v["position"] for v in L["vertices"]] == [v["position"] for v in before["vertices"]]
    assert all(v["placement"] == "corner" for v in L["vertices"])
    assert sorted(i for v in L["vertices"] for i in v["pins"]) == [0]    # kept, still the corner's
    # A capped cylinder cut by two loops along its axis and a belt: the vertices on the rims
    # are crease vertices. A pin beside the top rim, off it, moves one along the rim.
    surface = sw.from_shape(capped_cylinder(5, 20), target_triangles=12000)
    design = Design([[(0, -5, 10, 0, 0, 1)], [(-5, 0, 10, 0, 0, 1)], [(5, 0, 10, 0, 1, 0)]])
    L0 = compute_layout(DesignSession(surface, design))
    rim = [v for v in L0["vertices"] if v["placement"] == "feature" and v["position"][2] > 19.99]
    if not (L0["valid"] and rim):
        pytest.fail(f"the capped cylinder's design gives no rim vertex to pin: {L0['problems']}")
    target = np.asarray(rim[0]["position"]) + np.array([0.0, 0.0, -0.5])
    angle = math.atan2(target[1], target[0]) + 0.2
    target = np.array([4.5 * math.cos(angle), 4.5 * math.sin(angle), 19.5])   # inside, below the rim
    design.pins = [list(target)]
    L1 = compute_layout(DesignSession(surface, design))
    moved = [v for v in L1["vertices"] if v["placement"] == "pinned"]
    assert len(moved) == 1
    p = np.asarray(moved[0]["position"])
    assert p[2] == pytest.approx(20, abs=1e-6) and math.hypot(p[0], p[1]) == pytest.approx(5, abs=1e-3)
    assert L1["crease_conforming"] == L0["crease_conforming"]


def _edge_between(L, a, b):
    ends = lambda e: {tuple(np.sign(L["vertices"][i]["position"]).astype(int)) for i in e["vertices"]}
    return next(k for k, e in enumerate(L["edges"]) if ends(e) == {a, b})


def _distance_to_points(points, p):
    """From p to an edge's points (its refined vertices, at most a solver edge apart)."""
    return float(np.min(np.linalg.norm(np.asarray(points) - np.asarray(p), axis=1)))


def test_an_edge_routed_by_hand_passes_its_point_and_the_layout_stays_clean():
    """Paper §7, manual: the user decides where in its corridor a patch boundary lies. Three
    great circles on a sphere of radius 5; the edge from the (+,+,+) octant's vertex to the
    (+,+,-) one's, routed through a point of the (+,+,+) octant well off its shortest path,
    passes that point (within one solver edge), crosses its loop once, keeps its two
    vertices, and the layout keeps six clean quad patches (the other edges stay clear of
    it). The edge is named by where it crossed its loop, so the route holds whatever path
    the edge had. Without routes, the layout of before."""
    surface = sw.from_shape(sphere(5), target_triangles=12000)
    ds = DesignSession(surface, Design(GREAT_CIRCLES))
    before = compute_layout(ds)
    k = _edge_between(before, (1, 1, 1), (1, 1, -1))
    edge = math.sqrt(4 * math.pi * 25 / 12000 * 4 / math.sqrt(3))   # a solver edge, about
    target = 5 * np.array([0.9, 0.15, 0.35]) / np.linalg.norm([0.9, 0.15, 0.35])
    assert _distance_to_points(before["edges"][k]["points"], target) > 5 * edge
    ds.design.edge_routes = [{"through": list(target), "across": before["edges"][k]["crossing_point"]}]
    ds.apply_layout_inputs()
    after = compute_layout(ds)
    check_layout(after)
    assert after["clean"] and len(after["patches"]) == 6, (after["problems"], after["defects"])
    routed = [e for e in after["edges"] if e["through"] is not None]
    assert len(routed) == 1
    e = routed[0]
    assert e["route"] == 0 and all(x["route"] is None for x in after["edges"] if x is not e)
    assert e["vertices"] == before["edges"][k]["vertices"]
    assert _distance_to_points(e["points"], target) <= edge
    assert np.linalg.norm(np.asarray(e["through"]) - target) <= edge
    assert e["length"] > before["edges"][k]["length"] + 2 * edge
    # Crosses its loop (z = 0) once: the sign of z changes once along it.
    z = np.asarray(e["points"])[:, 2]
    assert np.count_nonzero(np.diff(np.sign(np.where(np.abs(z) < 1e-9, 0, z))[np.abs(z) >= 1e-9]) != 0) == 1
    assert [v["position"] for v in after["vertices"]] == [v["position"] for v in before["vertices"]]
    ds.design.edge_routes = []
    ds.apply_layout_inputs()
    assert compute_layout(ds)["edges"] == before["edges"]


def test_the_layout_names_the_route_of_each_edge():
    """Which route is whose is the layout's rule, told in layout.json ("route"), so that an
    editor re-routing an edge replaces the route the layout applied to it: two routes of one
    edge (the last counts: route 3) and one of another (route 2), all three well inside
    their corridors; the first edge takes route 3's point, not route 1's."""
    surface = sw.from_shape(sphere(5), target_triangles=8000)
    ds = DesignSession(surface, Design(GREAT_CIRCLES))
    before = compute_layout(ds)
    k = _edge_between(before, (1, 1, 1), (1, 1, -1))
    j = _edge_between(before, (-1, -1, 1), (-1, -1, -1))
    unit = lambda v: list(5 * np.asarray(v) / np.linalg.norm(v))
    ds.design.edge_routes = [
        {"through": unit([0.9, 0.15, 0.35]), "across": before["edges"][k]["crossing_point"]},
        {"through": unit([-0.9, -0.15, 0.35]), "across": before["edges"][j]["crossing_point"]},
        {"through": unit([0.15, 0.9, 0.35]), "across": before["edges"][k]["crossing_point"]}]
    ds.apply_layout_inputs()
    after = compute_layout(ds)
    assert after["edges"][k]["route"] == 2 and after["edges"][j]["route"] == 1
    assert all(e["route"] is None for i, e in enumerate(after["edges"]) if i not in (j, k))
    edge = math.sqrt(4 * math.pi * 25 / 8000 * 4 / math.sqrt(3))
    assert np.linalg.norm(np.asarray(after["edges"][k]["through"]) - unit([0.15, 0.9, 0.35])) <= edge


def test_an_edge_on_a_crease_keeps_it_when_routed_by_hand(cube_layout):
    """A route may not take a crease off the primal edges: the cube's edges follow its
    creases, so a route of one through a face's middle is refused (a problem line names
    it) and the layout stays as it was, crease-conforming and clean."""
    ds, before = cube_layout
    e = before["edges"][0]
    assert e["sharp"]
    routed = DesignSession(ds.surface, Design(CUBE_BELTS, edge_routes=[
        {"through": [5.0, 5.0, 10.0], "across": e["crossing_point"]}]))
    L = compute_layout(routed)
    assert any("edge route 1" in p and "crease" in p for p in L["problems"]), L["problems"]
    assert all(x["through"] is None for x in L["edges"])
    assert L["edges"][0]["route"] == 0      # refused, still the edge's route (an editor replaces it)
    assert [x["points"] for x in L["edges"]] == [x["points"] for x in before["edges"]]
    assert L["clean"] and L["crease_conforming"]


def test_the_main_job_keeps_a_designs_edge_routes(tmp_path):
    """weave with a design that routes an edge by hand: layout.json's edge goes through the
    point, design.json keeps the route, and the refit fits the layout the route gave."""
    target = 5 * np.array([0.9, 0.15, 0.35]) / np.linalg.norm([0.9, 0.15, 0.35])
    route = {"through": list(map(float, target)), "across": [3.735, 3.324, 0.0]}
    surface = sw.from_shape(sphere(5), target_triangles=8000)
    sw.weave(surface, design=Design(GREAT_CIRCLES, edge_routes=[route]), auto=False, out=str(tmp_path), step=True)
    design = json.loads((tmp_path / "design.json").read_text())
    layout = json.loads((tmp_path / "layout.json").read_text())
    report = json.loads((tmp_path / "report.json").read_text())
    assert design["edge_routes"] == [route]
    through = [e["through"] for e in layout["edges"] if e["through"] is not None]
    edge = math.sqrt(4 * math.pi * 25 / 8000 * 4 / math.sqrt(3))
    assert len(through) == 1 and np.linalg.norm(np.asarray(through[0]) - target) <= edge
    assert report["valid"] and layout["clean"] and report["fit"]["valid_shell"]


def test_edge_routes_round_trip_through_design_json_and_bad_ones_are_named(tmp_path):
    route = {"through": [1.0, 2.0, 3.0], "across": [4.0, 5.0, 6.0]}
    d = Design(GREAT_CIRCLES, edge_routes=[route])
    path = tmp_path / "d.json"
    d.save(str(path))
    assert Design.load(str(path)).edge_routes == [route]
    assert "edge_routes" not in Design(GREAT_CIRCLES).to_dict()
    for bad, words in (({"through": [1, 2, 3]}, "edge route 1"), ({"through": [1, 2], "across": [1, 2, 3]}, "through"),
                       ("x", "edge route 1")):
        data = d.to_dict()
        data["edge_routes"] = [bad]
        with pytest.raises(sw._native.InputError, match=words):
            Design.from_dict(data)
    data = d.to_dict()
    data["edge_routes"] = {"through": [1, 2, 3]}
    with pytest.raises(sw._native.InputError, match="edge_routes"):
        Design.from_dict(data)


def test_pins_round_trip_through_design_json_and_bad_ones_are_named(tmp_path):
    d = Design(GREAT_CIRCLES, pins=[[1.0, 2.0, 3.0]])
    path = tmp_path / "d.json"
    d.save(str(path))
    assert Design.load(str(path)).pins == [[1.0, 2.0, 3.0]]
    assert "pins" not in Design(GREAT_CIRCLES).to_dict()
    data = d.to_dict()
    data["pins"] = [[1, 2]]
    with pytest.raises(sw._native.InputError, match="pin 1"):
        Design.from_dict(data)
