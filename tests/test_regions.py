"""The loop arrangement and its regions (paper §4.2): analytic checks in model units.

Conventions under test (layout/regions.h): the valence of a region is its number of
sides, a side ending at a crossing of loops or where a dual curve meets the open
boundary; the open boundary between two curve ends is one side (a square sheet's
corners do not split it); the total curvature K is the Gaussian curvature inside plus
the geodesic curvature (and corner turns) of the open-boundary sides, so that a region
whose loops are orthogonal geodesics has K = (4 - valence) pi / 2 exactly.
"""
import math

import numpy as np
import pytest

import stripweave as sw
from models import box, edge_use_counts, sphere, torus
from stripweave._native import native
from stripweave.loops import LoopSession

import Part  # noqa: E402  (after models, which loads FreeCAD)

CUBE_BELTS = [(5, 5, 10, 1, 0, 0), (5, 3, 0, 0, 1, 0), (3, 0, 5, 1, 0, 0)]
GREAT_CIRCLES = [(5, 0, 0, 0, 1, 0), (0, 5, 0, 0, 0, 1), (0, 0, 5, 1, 0, 0)]
MERIDIAN = (13, 0, 0, 0, 0, 1)
OUTER_EQUATOR = (0, 13, 0, 1, 0, 0)


# --- helpers --------------------------------------------------------------------

def grid_sheet(n=10, size=10.0):
    """The square [0,size]^2 in z = 0 as a structured grid, each cell split along y = x."""
    h = size / n
    v = np.array([(i * h, j * h, 0.0) for j in range(n + 1) for i in range(n + 1)])
    t = []
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            t += [(a, b, c), (a, c, d)]
    return v, np.array(t, dtype=np.int32)


def grid_cube(n=10, size=10.0):
    """The surface of [0,size]^3 with a structured n x n grid on every face, counter-clockwise outside."""
    ids, verts, tris = {}, [], []

    def vid(p):
        key = tuple(np.round(p, 9))
        if key not in ids:
            ids[key] = len(verts)
            verts.append(p)
        return ids[key]

    h = size / n
    for axis in range(3):
        u, w = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, 1):
            for j in range(n):
                for i in range(n):
                    def at(a, b):
                        p = np.zeros(3)
                        p[axis], p[u], p[w] = side * size, a * h, b * h
                        return p
                    q = [vid(at(i, j)), vid(at(i + 1, j)), vid(at(i + 1, j + 1)), vid(at(i, j + 1))]
                    a, b, c, d = q if side == 1 else q[::-1]
                    tris += [(a, b, c), (a, c, d)]
    return np.array(verts), np.array(tris, dtype=np.int32)


def trace(surface, corners, closed=False, on_line=1e-13):
    """The straight polyline through `corners` (x, y) on a planar surface in z = 0, embedded like
    session.embed(): per point its mesh vertex (or -1), its mesh edge (or -1) and t along
    surface.edges[edge]. Vertices on the line are passed through; collinear edges are run along."""
    V = np.asarray(surface.vertices)[:, :2]
    E = np.asarray(surface.edges)
    P0, P1 = V[E[:, 0]], V[E[:, 1]]

    def cross(a, b):
        return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]

    def locate(p):
        """A corner of the polyline as (vertex, -1, 0) or (-1, edge, t)."""
        near = np.nonzero(np.linalg.norm(V - p, axis=1) < on_line)[0]
        if len(near):
            return int(near[0]), -1, 0.0
        de = P1 - P0
        t = np.einsum("ij,ij->i", p - P0, de) / np.einsum("ij,ij->i", de, de)
        off = np.abs(cross(de, p - P0)) / np.linalg.norm(de, axis=1)
        for e in np.nonzero((off < on_line) & (t > 0) & (t < 1))[0]:
            return -1, int(e), float(t[e])
        raise ValueError(f"{p} is neither at a mesh vertex nor on a mesh edge")

    corners = [np.asarray(c, float) for c in corners]
    pieces = list(zip(corners[:-1], corners[1:])) + ([(corners[-1], corners[0])] if closed else [])
    points = []
    for a, b in pieces:
        d = b - a
        length = np.linalg.norm(d)
        online = np.abs(cross(d, V - a) / length) < on_line
        u = (V - a) @ d / length ** 2
        hits = [(0.0,) + locate(a), (1.0,) + locate(b)]
        hits += [(u[v], int(v), -1, 0.0) for v in np.nonzero(online & (u > 0) & (u < 1))[0]]
        de = P1 - P0
        den = cross(d, de)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = cross(P0 - a, de) / den
            t = cross(P0 - a, d) / den
        crossed = ~(online[E[:, 0]] | online[E[:, 1]]) & (den != 0) & (t > 0) & (t < 1) & (s > 0) & (s < 1)
        hits += [(s[e], -1, int(e), float(t[e])) for e in np.nonzero(crossed)[0]]
        for hit in sorted(hits):
            if not points or points[-1] != hit[1:]:
                points.append(hit[1:])
    if closed and points[-1] == points[0]:
        points.pop()
    return {"vertex": [p[0] for p in points], "edge": [p[1] for p in points], "t": [p[2] for p in points],
            "closed": closed}


def clipped_line(point, angle, size=10.0):
    """The chord of the square [0,size]^2 through `point` at `angle`."""
    p, d = np.asarray(point, float), np.array([math.cos(angle), math.sin(angle)])
    s = []
    for axis in range(2):
        if abs(d[axis]) > 1e-12:
            for bound in (0.0, size):
                k = (bound - p[axis]) / d[axis]
                if -1e-9 <= (p + k * d)[1 - axis] <= size + 1e-9:
                    s.append(k)
    return [p + min(s) * d, p + max(s) * d]


def check_topology(r):
    """The arrangement is a valid refinement and its regions add up (Euler, Gauss-Bonnet)."""
    chi = r["euler_characteristic"]
    assert r["refined_euler_characteristic"] == chi
    assert r["euler_sum"] == chi  # graph V - E + sum of the regions' chi
    assert r["graph_vertices"] - r["graph_edges"] + sum(g["euler_characteristic"] for g in r["regions"]) == chi
    assert r["inverted_triangles"] == 0
    assert r["min_area_ratio"] > 0
    assert r["star_triangles"] == 0
    assert sum(g["total_curvature"] for g in r["regions"]) == pytest.approx(2 * math.pi * chi, abs=1e-6)
    for g in r["regions"]:
        assert g["euler_characteristic"] == 2 - 2 * g["genus"] - g["boundaries"]
        assert g["disc"] == (g["euler_characteristic"] == 1)
    assert r["valid"] == all(g["disc"] for g in r["regions"])
    if "triangles" in r:
        assert edge_use_counts(r["triangles"]).max() <= 2


def regions_of(session, anchors, **kw):
    loops = [session.native.loops([list(a)], 1, True)[0] for a in anchors]
    r = native.regions(session.native, loops, **kw)
    check_topology(r)
    return r


def region_at(r, point):
    """The region of a refined triangle at the refined vertex nearest to `point`."""
    v = int(np.argmin(np.linalg.norm(r["vertices"] - np.asarray(point, float), axis=1)))
    t = int(np.nonzero((r["triangles"] == v).any(axis=1))[0][0])
    return r["triangle_region"][t]


def arcs_per_region(r):
    count = [0] * len(r["regions"])
    for arc in r["arc_list"]:
        for side in (arc["left"], arc["right"]):
            if side >= 0:
                count[side] += 1
    return count


# --- fixtures -------------------------------------------------------------------

@pytest.fixture(scope="module")
def cube_session():
    return LoopSession(sw.from_shape(box(10), target_triangles=12000))


@pytest.fixture(scope="module")
def torus_session():
    return LoopSession(sw.from_shape(torus(10, 3), target_triangles=16000))


@pytest.fixture(scope="module")
def square_session():
    return LoopSession(sw.from_shape(Part.makePlane(10, 10), target_triangles=8000))


@pytest.fixture(scope="module")
def sheet():
    return sw.from_mesh(*grid_sheet(10), target_triangles=0)


def sheet_regions(sheet, paths):
    r = native.regions_of_paths(sheet, paths, details=True)
    check_topology(r)
    return r


# --- closed surfaces --------------------------------------------------------------

def test_cube_three_belts_make_eight_triangular_regions(cube_session):
    r = regions_of(cube_session, CUBE_BELTS, details=True)
    assert len(r["regions"]) == 8
    assert r["crossings"] == 6
    assert r["arcs"] == 12
    assert r["valid"]
    for g in r["regions"]:
        assert g["disc"] and g["boundaries"] == 1
        assert g["valence"] == 3
        assert g["total_curvature"] == pytest.approx(math.pi / 2, rel=0.01)  # one cube corner inside
        assert g["colour"] == "none"
    assert sum(g["area"] for g in r["regions"]) == pytest.approx(600, rel=1e-6)
    # The arrangement graph of the octahedron: V - E + F = 6 - 12 + 8.
    assert (r["graph_vertices"], r["graph_edges"]) == (6, 12)
    # Each arc separates two different regions, and each region is bounded by its three arcs.
    assert all(a["left"] != a["right"] for a in r["arc_list"])
    assert arcs_per_region(r) == [3] * 8
    # Every crossing is a refined vertex with four arc ends.
    assert len(r["crossing_vertices"]) == 6


def test_cube_singularities_one_per_region_or_orange(cube_session):
    """Three belts: a corner and a singularity per region. One belt: two halves, each holding
    four corners: four extrema of one kind (3 in excess, orange by itself), and four crease
    junctions, which take precedence as the crease colour (issue 17)."""
    for anchors, colours in ((CUBE_BELTS, {"none"}), (CUBE_BELTS[:1], {"crease"})):
        loops = [cube_session.native.loops([list(a)], 1, True)[0] for a in anchors]
        field = native.cross_field(cube_session.native, loops)
        vertices = [s["vertex"] for s in field["singularities"]]
        quarters = [round(4 * s["index"]) for s in field["singularities"]]
        r = native.regions(cube_session.native, loops, vertices, quarters)
        check_topology(r)
        assert sum(len(g["singularities"]) for g in r["regions"]) == len(vertices) == 8
        assert {g["colour"] for g in r["regions"]} == colours
        if len(anchors) == 1:  # a belt halves the cube into two discs with four corners each
            assert [len(g["singularities"]) for g in r["regions"]] == [4, 4]
            assert [g["excess_extrema"] for g in r["regions"]] == [3, 3]
            assert {g["crease_problem"] for g in r["regions"]} == {"two crease nodes"}
            assert all(g["valence"] == 0 and g["total_curvature"] == pytest.approx(2 * math.pi, rel=1e-6)
                       for g in r["regions"])


def test_torus_meridian_and_equator_leave_one_quad_region(torus_session):
    r = regions_of(torus_session, [MERIDIAN, OUTER_EQUATOR])
    assert len(r["regions"]) == 1
    g = r["regions"][0]
    assert g["disc"] and g["valence"] == 4
    assert g["total_curvature"] == pytest.approx(0, abs=1e-6)
    assert g["colour"] == "none"
    assert r["crossings"] == 1 and r["arcs"] == 2
    assert r["valid"]
    assert g["area"] == pytest.approx(4 * math.pi ** 2 * 10 * 3, rel=0.01)


def test_torus_meridian_alone_leaves_a_red_annulus(torus_session):
    r = regions_of(torus_session, [MERIDIAN])
    assert len(r["regions"]) == 1
    g = r["regions"][0]
    assert not g["disc"]
    assert (g["euler_characteristic"], g["boundaries"], g["genus"]) == (0, 2, 0)  # cut open: an annulus
    assert g["colour"] == "red"
    assert not r["valid"]
    assert r["crossings"] == 0 and r["arcs"] == 1


def test_sphere_three_great_circles_make_eight_triangles():
    session = LoopSession(sw.from_shape(sphere(5), target_triangles=12000))
    r = regions_of(session, GREAT_CIRCLES)
    assert len(r["regions"]) == 8
    assert r["crossings"] == 6 and r["arcs"] == 12 and r["valid"]
    assert [g["valence"] for g in r["regions"]] == [3] * 8
    assert all(g["disc"] for g in r["regions"])
    # On a sphere K is area / R^2, whatever the loops' exact route.
    for g in r["regions"]:
        assert g["total_curvature"] == pytest.approx(g["area"] / 25, rel=0.02)


# --- a surface with boundary ----------------------------------------------------

SHEET_CORNERS = [(0, 0, 0), (10, 0, 0), (10, 10, 0), (0, 10, 0)]


def test_square_sheet_one_curve_each_way(square_session):
    r = regions_of(square_session, [(5, 3, 0, 1, 0, 0), (3, 5, 0, 0, 1, 0)], details=True)
    assert len(r["regions"]) == 4
    assert r["crossings"] == 1 and r["valid"]
    # Each region holds one corner of the sheet; its sides are two arcs and one piece of the
    # boundary (around the corner, whose quarter turn is its curvature).
    assert sorted(region_at(r, c) for c in SHEET_CORNERS) == [0, 1, 2, 3]
    for g in r["regions"]:
        assert g["disc"] and g["valence"] == 3
        assert g["total_curvature"] == pytest.approx(math.pi / 2, abs=1e-6)
        assert g["valence"] == pytest.approx(g["ideal_valence"], abs=1e-6)
        assert g["colour"] == "none"
    assert arcs_per_region(r) == [2] * 4
    assert sum(g["area"] for g in r["regions"]) == pytest.approx(100, rel=1e-6)
    # Nodes: the crossing and the four curve ends on the boundary; edges: four arcs, four boundary pieces.
    assert (r["graph_vertices"], r["graph_edges"]) == (5, 8)


def test_square_sheet_two_curves_each_way(square_session):
    anchors = [(5, 3, 0, 1, 0, 0), (5, 7, 0, 1, 0, 0), (3, 5, 0, 0, 1, 0), (7, 5, 0, 0, 1, 0)]
    r = regions_of(square_session, anchors, details=True)
    assert len(r["regions"]) == 9
    assert r["crossings"] == 4 and r["valid"]
    corner_regions = {region_at(r, c) for c in SHEET_CORNERS}
    assert len(corner_regions) == 4
    for k, g in enumerate(r["regions"]):
        assert g["disc"]
        assert g["valence"] == (3 if k in corner_regions else 4)
        assert g["valence"] == pytest.approx(g["ideal_valence"], abs=1e-6)
        assert g["colour"] == "none"


def test_open_sides_count_the_stretches_of_boundary_a_region_touches(sheet):
    """The layout is aligned to the open boundary, and a region's one vertex closes one
    stretch of it (regions.h, open_sides). A lone chord: two caps, one stretch each. Two
    chords that do not cross: the band between them touches the boundary in two stretches,
    one of which no patch will cover. A third chord cutting a corner off one of four valid
    corner regions, crossing neither chord: a cap, and the rest with two stretches. Every
    region stays a disc, valid in the paper's sense."""
    lone = sheet_regions(sheet, [trace(sheet, clipped_line((5, 3.3), 0.2))])
    assert [(g["open_sides"], g["valence"]) for g in lone["regions"]] == [(1, 2), (1, 2)] and lone["valid"]

    band = sheet_regions(sheet, [trace(sheet, clipped_line((5, 3.3), 0.1)),
                                 trace(sheet, clipped_line((5, 6.7), -0.1))])
    middle = band["regions"][region_at(band, (5, 5, 0))]
    assert (middle["open_sides"], middle["valence"]) == (2, 4) and middle["disc"] and band["valid"]

    cross = [trace(sheet, clipped_line((5, 5.3), 0.05)), trace(sheet, clipped_line((5.3, 5), 1.6))]
    four = sheet_regions(sheet, cross)
    assert [g["open_sides"] for g in four["regions"]] == [1] * 4
    r = sheet_regions(sheet, cross + [trace(sheet, [(0, 2.1), (2.3, 0)])])
    cap, rest = r["regions"][region_at(r, (0, 0, 0))], r["regions"][region_at(r, (3, 3, 0))]
    assert (cap["open_sides"], cap["valence"]) == (1, 2)
    assert (rest["open_sides"], rest["valence"]) == (2, 5)
    assert sorted(g["open_sides"] for g in r["regions"]) == [1, 1, 1, 1, 2]


def test_stretches_a_loop_only_touches_apart_are_bridged_as_two(sheet):
    """A loop that touches the boundary at one vertex (a diamond with a corner on the bottom
    edge) and a chord above it that crosses nothing: the region between them wraps over the
    diamond and touches the bottom edge in two stretches that share the touching vertex. They
    are two pieces for the weave's bridge (weave_seeds.h), so the region gets its cut: across
    the bridge over the diamond's top, upright. As one piece (joined at that vertex, as on
    lionstatue's open base) it got no anchor at all."""
    diamond = trace(sheet, [(5, 0), (7, 2), (5, 4), (3, 2)], closed=True)
    r = sheet_regions(sheet, [diamond, trace(sheet, clipped_line((5, 6.3), 0.05))])
    k = region_at(r, (1, 1, 0))
    assert r["regions"][k]["open_sides"] == 2 and r["regions"][k]["disc"]
    (x, y, z, dx, dy, dz), *_ = r["bridge_anchors"][k]
    assert 4 <= y <= 6.6 and abs(x - 5) < 1.5 and abs(dy) > 0.9


def test_square_sheet_without_curves_is_one_disc_of_valence_zero(square_session):
    r = native.regions(square_session.native, [])
    check_topology(r)
    (g,) = r["regions"]
    assert g["disc"] and g["valence"] == 0 and g["boundaries"] == 1
    assert g["total_curvature"] == pytest.approx(2 * math.pi, abs=1e-6)  # the four corner turns
    assert r["valid"]


# --- near-degenerate arrangements -------------------------------------------------

def test_belts_along_mesh_edges_through_vertices():
    """On a structured cube the belts run exactly along mesh edges and cross at mesh vertices."""
    session = LoopSession(sw.from_mesh(*grid_cube(10), target_triangles=0))
    r = regions_of(session, CUBE_BELTS, details=True)
    assert r["refined_triangles"] == 1200  # nothing to cut: every loop step is a mesh edge
    assert len(r["regions"]) == 8 and r["crossings"] == 6 and r["arcs"] == 12 and r["valid"]
    for g in r["regions"]:
        assert g["valence"] == 3
        assert g["total_curvature"] == pytest.approx(math.pi / 2, abs=1e-9)
    # The crossings are surface vertices (refined ids below the surface's vertex count).
    assert all(v < len(session.surface.vertices) for v in r["crossing_vertices"])


def test_lines_along_grid_lines_cross_at_a_vertex(sheet):
    r = sheet_regions(sheet, [trace(sheet, [(5, 0), (5, 10)]), trace(sheet, [(0, 5), (10, 5)])])
    assert len(r["regions"]) == 4 and r["crossings"] == 1
    assert [g["valence"] for g in r["regions"]] == [3] * 4
    assert r["refined_triangles"] == 200


@pytest.mark.parametrize("offset", [1e-2, 1e-5, 1e-7, 1e-9, 1e-12, 0.0])
def test_crossing_close_to_a_vertex(sheet, offset):
    """Two curves crossing at `offset` from the mesh vertex (5, 5): snapped onto it when
    nearer than the tolerance, kept apart otherwise; the arrangement is the same."""
    a = trace(sheet, [(0, 5 - 0.37 * 5 + offset), (10, 5 + 0.37 * 5 + offset)])
    b = trace(sheet, [(3 - offset, 0), (7 - offset, 10)])
    r = sheet_regions(sheet, [a, b])
    assert len(r["regions"]) == 4 and r["crossings"] == 1 and r["arcs"] == 4
    assert sorted(region_at(r, c) for c in SHEET_CORNERS) == [0, 1, 2, 3]
    for g in r["regions"]:
        assert g["valence"] == 3 and g["total_curvature"] == pytest.approx(math.pi / 2, abs=1e-6)


@pytest.mark.parametrize("offset", [1e-3, 1e-6, 1e-8, 1e-10, 0.0])
def test_two_curves_meeting_on_a_mesh_edge(sheet, offset):
    """The curves cross the mesh edge x = 5 at almost the same t (they cross there)."""
    a = trace(sheet, [(0, 5.5 - 1.5), (10, 5.5 + 1.5 + offset)])
    b = trace(sheet, [(5 - 5.5 / 2.2, 0), (5 + 4.5 / 2.2 + offset, 10)])
    r = sheet_regions(sheet, [a, b])
    assert len(r["regions"]) == 4 and r["crossings"] == 1
    assert [g["valence"] for g in r["regions"]] == [3] * 4


@pytest.mark.parametrize("offset,regions,crossings", [(1e-2, 7, 3), (1e-5, 7, 3), (1e-9, 6, 1), (0.0, 6, 1)])
def test_three_curves_almost_concurrent_inside_a_triangle(sheet, offset, regions, crossings):
    """Three curves through nearly one point of a triangle: the small triangle between them is
    a region down to the tolerance (1e-6 of the triangle), below it the three cross in one point."""
    c = np.array([5.3, 5.45])
    paths = []
    for k, angle in enumerate([0.3, 1.4, 2.5]):
        normal = np.array([-math.sin(angle), math.cos(angle)])
        paths.append(trace(sheet, clipped_line(c + k * offset * normal, angle)))
    r = sheet_regions(sheet, paths)
    assert len(r["regions"]) == regions
    assert r["crossings"] == crossings
    assert all(g["disc"] for g in r["regions"])


def test_an_arc_of_one_edge_between_two_crossings_gets_an_inner_vertex_and_its_primal_edge(sheet):
    """Three curves nearly concurrent inside one triangle (1e-5 apart) bound a tiny triangular
    region whose three arcs would each be one refined edge from crossing to crossing. A primal
    edge crosses its arc at an inner vertex, so such an arc's edge was lost: the region's vertex
    had two edges, not three, and two patches lost a side. Each such arc is split at its
    midpoint: every arc between two regions has an inner vertex, the arrangement still adds up,
    and every region's vertex has as many primal edges as the region has arcs."""
    c = np.array([5.3, 5.45])
    paths = []
    for k, angle in enumerate([0.3, 1.4, 2.5]):
        normal = np.array([-math.sin(angle), math.cos(angle)])
        paths.append(trace(sheet, clipped_line(c + k * 1e-5 * normal, angle)))
    r = sheet_regions(sheet, paths)
    assert len(r["regions"]) == 7 and r["crossings"] == 3
    inner = [a for a in r["arc_list"] if a["left"] >= 0 and a["right"] >= 0]
    assert inner and all(len(a["vertices"]) >= 3 for a in inner)
    L = native.layout_of_paths(sheet, paths)
    assert not [p for p in L["problems"] if "no corridor path" in p]
    arcs = arcs_per_region(r)
    ends = [0] * len(L["vertices"])
    for e in L["edges"]:
        for v in e["vertices"]:
            ends[v] += 1
    tiny = min(range(len(r["regions"])), key=lambda g: r["regions"][g]["area"])
    assert r["regions"][tiny]["area"] < 1e-8 and arcs[tiny] == 3
    for v, vertex in enumerate(L["vertices"]):
        assert ends[v] == arcs[vertex["region"]]


def test_self_crossing_loop(sheet):
    """A figure eight crossing itself inside a triangle: two lobes and the annulus around them."""
    r = sheet_regions(sheet, [trace(sheet, [(2, 2.3), (8, 8.3), (8, 2.6), (2, 8.6)], closed=True)])
    assert r["crossings"] == 1 and r["arcs"] == 2
    (v,) = r["crossing_vertices"]
    assert v >= len(sheet.vertices)  # a new vertex, inside a triangle
    discs = [g for g in r["regions"] if g["disc"]]
    assert len(r["regions"]) == 3 and len(discs) == 2
    assert [g["valence"] for g in discs] == [1, 1]
    outer = next(g for g in r["regions"] if not g["disc"])
    assert outer["boundaries"] == 2 and outer["valence"] == 2 and outer["colour"] == "red"


def test_loop_along_mesh_edges(sheet):
    r = sheet_regions(sheet, [trace(sheet, [(2, 2), (8, 2), (8, 8), (2, 8)], closed=True)])
    assert r["refined_triangles"] == 200
    inside = r["regions"][region_at(r, (5, 5, 0))]
    assert inside["disc"] and inside["area"] == pytest.approx(36)
    assert inside["valence"] == 0  # one closed arc, no corner
    assert not r["valid"]  # the rest is an annulus


def test_a_loop_given_twice_is_one_loop(sheet):
    loop = trace(sheet, [(2, 2.5), (8, 2.5), (8, 8.5), (2, 8.5)], closed=True)
    once, twice = sheet_regions(sheet, [loop]), sheet_regions(sheet, [loop, loop])
    assert len(twice["regions"]) == len(once["regions"]) == 2
    assert twice["refined_triangles"] == once["refined_triangles"]
    assert sorted(g["area"] for g in twice["regions"]) == pytest.approx(sorted(g["area"] for g in once["regions"]))


def test_random_lines_in_general_position():
    """Chords of a coarse mesh, several crossing inside one triangle: regions = 1 + lines + crossings."""
    coarse = sw.from_mesh(*grid_sheet(3), target_triangles=0)
    rng = np.random.default_rng(7)
    for _ in range(40):
        lines = [clipped_line(rng.uniform(0.5, 9.5, 2), rng.uniform(0, math.pi)) for _ in range(rng.integers(2, 8))]
        points = []
        for i in range(len(lines)):
            for j in range(i + 1, len(lines)):
                (a, b), (c, d) = lines[i], lines[j]
                s, u = np.linalg.solve(np.array([b - a, c - d]).T, c - a)
                if 0 < s < 1 and 0 < u < 1:
                    points.append(a + s * (b - a))
        gaps = [np.linalg.norm(p - q) for k, p in enumerate(points) for q in points[k + 1:]]
        if gaps and min(gaps) < 1e-4:
            continue  # nearly concurrent: merged below the tolerance, as tested above
        r = sheet_regions(coarse, [trace(coarse, line) for line in lines])
        assert r["crossings"] == len(points)
        assert len(r["regions"]) == 1 + len(lines) + len(points)
        assert all(g["disc"] for g in r["regions"])


def check_line_cells(r, lines, clear=1e-3):
    """The regions of chords of the square sheet are the cells of their arrangement.
    Every sample point of a refined triangle at least `clear` from every line has a sign
    vector (its side of each line); one region holds one sign vector and one sign vector one
    region (slivers thinner than `clear`, where lines merge, are not judged). The areas add
    up to the square's, each region's to its triangles'. Taking the arcs as runs of refined
    vertices (chords merged into one run each give an arc of the arc list), a region's
    valence is its number of sides along chords plus its runs along the sheet's boundary
    (one, or two for a strip between chords that do not cross), and the cells of chords of a disc number
    1 + runs - ends of runs inside (Euler: V - E + F = 1), the ends inside being the crossings."""
    v, t, region = np.asarray(r["vertices"]), np.asarray(r["triangles"]), np.asarray(r["triangle_region"])
    p = v[t][:, :, :2]
    area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    assert sum(g["area"] for g in r["regions"]) == pytest.approx(100, rel=1e-9)
    for k, g in enumerate(r["regions"]):
        assert g["area"] == pytest.approx(area[region == k].sum(), rel=1e-9, abs=1e-12)
    w = np.random.default_rng(0).dirichlet(np.ones(3), size=64)  # sample points of every triangle
    c = np.einsum("sk,tkd->tsd", w, p).reshape(-1, 2)
    sample_region = np.repeat(region, len(w))
    side = []
    for a, b in lines:
        d = (b - a) / np.linalg.norm(b - a)
        side.append((c - a) @ np.array([-d[1], d[0]]))
    side = np.array(side).T
    robust = np.all(np.abs(side) > clear, axis=1)
    cell_region = {}
    for key, k in zip(map(tuple, (side[robust] > 0).tolist()), sample_region[robust].tolist()):
        assert cell_region.setdefault(key, k) == k  # a cell lies in one region ...
    assert len(set(cell_region.values())) == len(cell_region)  # ... and a region holds one cell

    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    owner = np.tile(region, 3)
    _, first, counts = np.unique(edges, axis=0, return_index=True, return_counts=True)
    rim = first[counts == 1]  # the sheet's boundary edges
    boundary_vertices = set(edges[rim].ravel().tolist())
    rim_sides = [0] * len(r["regions"])  # runs of each region along the boundary: a path has V - E = 1
    for k in range(len(r["regions"])):
        mine = edges[rim[owner[rim] == k]]
        rim_sides[k] = len(np.unique(mine)) - len(mine)
    curves = {}  # each run of refined vertices once, whichever way: the chords along it, its regions
    for arc in r["arc_list"]:
        chain = tuple(arc["vertices"])
        loops, sides = curves.setdefault(min(chain, chain[::-1]), (set(), set()))
        loops.add(arc["loop"])
        sides.update((arc["left"], arc["right"]))
    for k, g in enumerate(r["regions"]):
        mine = [(chain, loops) for chain, (loops, sides) in curves.items() if k in sides]
        ends = {}
        for chain, loops in mine:
            for x in (chain[0], chain[-1]):
                ends.setdefault(x, []).append(loops)
        # Where two runs of its boundary meet, the cell has a corner unless a chord goes on
        # through (a straight chord does not turn).
        straight = sum(1 for at in ends.values() if len(at) == 2 and at[0] & at[1])
        valence = len(mine) - straight + rim_sides[k]
        assert g["disc"] and g["valence"] == valence
        assert g["open_sides"] == rim_sides[k]
        # Two sides at least. (A convex cell has 3 unless it reaches the boundary, but where
        # a chord passes within the tolerance of a vertex another runs through, both are
        # snapped onto it, and if they cross near there too the sliver between is a digon.)
        assert g["valence"] >= 2
    inside = {x for chain in curves for x in (chain[0], chain[-1])} - boundary_vertices
    assert {x for x in r["crossing_vertices"] if x not in boundary_vertices} == inside
    assert len(r["regions"]) == 1 + len(curves) - len(inside)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_a_pencil_through_one_point_makes_a_wheel(n):
    """k chords through one point (a vertex, on an edge or inside a triangle; displaced by up
    to 1e-10, far below the merge tolerance) at well-separated angles: one crossing, 2k
    arcs, 2k triangular regions (two sides along chords, one along the boundary)."""
    coarse = sw.from_mesh(*grid_sheet(n), target_triangles=0)
    rng = np.random.default_rng(5)
    hubs = [(5, 5), (1.1, 1.1), (3.217, 6.135)] + ([(10 / n, 10 / n)] if n > 1 else [])  # vertex, edge, inside
    for hub in hubs:
        for k in (2, 3, 5):
            angles = rng.uniform(0, math.pi) + np.arange(k) * math.pi / k + rng.uniform(-0.1, 0.1, k)
            lines = [clipped_line(np.asarray(hub) + rng.choice([0.0, 1e-13, 1e-10]) * rng.normal(size=2), a)
                     for a in angles]
            r = sheet_regions(coarse, [trace(coarse, line) for line in lines])
            assert (r["crossings"], r["arcs"], len(r["regions"])) == (1, 2 * k, 2 * k)
            assert [g["valence"] for g in r["regions"]] == [3] * (2 * k)
            check_line_cells(r, lines)


def test_pencils_of_nearly_coincident_lines():
    """Lines through nearly one point (at, next to, or on a mesh edge or vertex) and at nearly one
    angle: whatever merges, the refinement stays a manifold disc of discs, and its regions
    are the cells of the lines' arrangement (check_line_cells)."""
    rng = np.random.default_rng(11)
    tiny = [0.0, 1e-13, 1e-10, 1e-8, 1e-7, 1e-6, 1e-5]
    for n in (1, 2, 3):
        coarse = sw.from_mesh(*grid_sheet(n), target_triangles=0)
        for _ in range(40):
            hub = rng.uniform(1, 9, 2)
            if n > 1 and rng.random() < 0.5:
                hub = np.array([rng.integers(1, n) * 10 / n, rng.uniform(1, 9)])  # on a mesh edge
            if n > 1 and rng.random() < 0.3:
                hub = np.array([rng.integers(1, n), rng.integers(1, n)]) * 10 / n  # on a mesh vertex
            angle = rng.uniform(0, math.pi)
            lines = [clipped_line(hub + rng.choice(tiny) * rng.normal(size=2),
                                  angle + rng.choice([0.0, 1e-9, 1e-6, 1e-3, 0.7]) * rng.normal())
                     for _ in range(rng.integers(2, 6))]
            r = sheet_regions(coarse, [trace(coarse, line) for line in lines])
            check_line_cells(r, lines)


# --- input errors ---------------------------------------------------------------

def test_bad_input(sheet, square_session):
    far_apart = {"vertex": [0, 120], "edge": [-1, -1], "t": [0.0, 0.0], "closed": False}
    with pytest.raises(ValueError, match="share no triangle"):
        native.regions_of_paths(sheet, [far_apart])
    with pytest.raises(ValueError, match="quarter_indices"):
        native.regions(square_session.native, [], [0, 1], [1])
    with pytest.raises(ValueError, match="not a surface vertex"):
        native.regions(square_session.native, [], [10 ** 7])
