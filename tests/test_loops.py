"""Elastica loops (paper §5): analytic checks in model units."""
import heapq
import math

import numpy as np
import pytest

import stripweave as sw
from models import box, capped_cylinder, open_cylinder_shell, sphere, torus, winding_numbers
from stripweave.loops import LoopSession


@pytest.fixture(scope="module")
def torus_session():
    return LoopSession(sw.from_shape(torus(10, 3)))


@pytest.fixture(scope="module")
def cube_session():
    return LoopSession(sw.from_shape(box(10)))


@pytest.fixture(scope="module")
def coarse_torus_session():
    """A torus coarse enough (g': ~33k nodes) to search exhaustively in Python."""
    return LoopSession(sw.from_shape(torus(10, 3), target_triangles=1000))


def closed_length(loop):
    p = np.asarray(loop["points"])
    return np.linalg.norm(np.diff(p, axis=0), axis=1).sum()


# --- torus ----------------------------------------------------------------------

def test_torus_meridian_from_a_directional_anchor(torus_session):
    loop = torus_session.loops([(13, 0, 0, 0, 0, 1)])[0]
    assert loop["closed"]
    assert loop["length"] == pytest.approx(2 * math.pi * 3, rel=0.02)
    assert winding_numbers(loop["points"]) in {(0, 1), (0, -1)}


def test_torus_outer_equator_from_a_directional_anchor(torus_session):
    loop = torus_session.loops([(0, 13, 0, 1, 0, 0)])[0]
    assert loop["closed"]
    assert loop["length"] == pytest.approx(2 * math.pi * 13, rel=0.02)
    assert winding_numbers(loop["points"]) in {(1, 0), (-1, 0)}


def test_torus_positional_anchor_best_is_the_meridian_and_alternatives_span_homotopy_classes(torus_session):
    loops = torus_session.loops([(13, 0, 0)], alternatives=8)
    assert loops[0]["length"] == pytest.approx(2 * math.pi * 3, rel=0.02)
    assert [l["cost"] for l in loops] == sorted(l["cost"] for l in loops)
    classes = {tuple(abs(w) for w in winding_numbers(l["points"])) for l in loops if l["closed"]}
    assert (0, 1) in classes and (1, 0) in classes  # the meridian and the equator-type loop


def test_torus_another_direction_gives_another_homotopy_class(torus_session):
    """Figure 3: at one point, the direction picks the homotopy class: along the tube the
    meridian, around the axis the equator-type loop."""
    across = torus_session.loops([(13, 0, 0, 0, 0, 1)])[0]
    around = torus_session.loops([(13, 0, 0, 0, 1, 0)])[0]
    assert tuple(map(abs, winding_numbers(across["points"]))) == (0, 1)
    assert tuple(map(abs, winding_numbers(around["points"]))) == (1, 0)
    assert around["length"] == pytest.approx(2 * math.pi * 13, rel=0.02)


def shortest_distances(arcs, source, bound):
    """Plain Dijkstra over g' from one node: {node: cost} of the nodes within `bound`."""
    offsets, head, weight = arcs
    dist, done, heap = {source: 0.0}, set(), [(0.0, source)]
    while heap:
        d, x = heapq.heappop(heap)
        if x in done:
            continue
        done.add(x)
        for a in range(offsets[x], offsets[x + 1]):
            y, dy = head[a], d + weight[a]
            if dy <= bound and dy < dist.get(y, math.inf):
                dist[y] = dy
                heapq.heappush(heap, (dy, y))
    return dist


def exhaustive_loop_cost(session, anchors, bound):
    """The cheapest closed walk in g' from a candidate node of anchor 0 through a candidate of
    each next anchor in turn and back to that same node (paper §5.4's minimum metagraph
    cycle), every metaedge a Dijkstra of its own, combined in min-plus algebra over all
    candidate choices. Walks costing more than `bound` count as unreachable (inf)."""
    g = session.native.graph_arcs()
    arcs = (g["offsets"].tolist(), g["head"].tolist(), g["weight"].tolist())
    candidates = [session.native.anchor_candidates(list(a))[1] for a in anchors]
    metaedges = []
    for i, here in enumerate(candidates):
        there = candidates[(i + 1) % len(anchors)]
        rows = [shortest_distances(arcs, a, bound) for a in here]
        metaedges.append(np.array([[row.get(b, math.inf) for b in there] for row in rows]))
    through = metaedges[0]
    for m in metaedges[1:]:
        through = np.min(through[:, :, None] + m[None, :, :], axis=1)
    return float(np.min(np.diag(through)))


def chain_cost(session, nodes):
    """The loop's cost summed again from g''s arcs along its closed node chain (inf if a step is no arc)."""
    g = session.native.graph_arcs()
    offsets, head, weight = g["offsets"], g["head"], g["weight"]
    total = 0.0
    for x, y in zip(nodes, nodes[1:] + nodes[:1]):
        arc = np.flatnonzero(head[offsets[x]:offsets[x + 1]] == y)
        if len(arc) == 0:
            return math.inf
        total += weight[offsets[x] + arc[0]]
    return total


def passes_in_order(loop, vertices):
    """Read from its first pass through vertices[0], the closed loop's points hold the other
    vertices as a subsequence, in order (a closed loop may start anywhere along itself)."""
    visited = list(loop["mesh_vertex"])[:-1]  # the last point repeats the first
    if vertices[0] not in visited:
        return False
    start = visited.index(vertices[0])
    visited = visited[start:] + visited[:start]
    at = 0
    for v in vertices[1:]:
        if v not in visited[at + 1:]:
            return False
        at = visited.index(v, at + 1)
    return True


@pytest.mark.parametrize("anchors", [
    [(13, 0, 0), (0, 13, 0)],
    [(13, 0, 0, 0, 0, 1), (0, 13, 0, 0, 0, 1)],  # both along meridians: the loop must turn between them
])
def test_two_anchors_in_order(coarse_torus_session, anchors):
    """From anchor 1 the loop passes anchor 2, and no walk through both is cheaper: its cost
    equals an exhaustive search of g' within 1e-9."""
    session = coarse_torus_session
    loop = session.loops(anchors)[0]
    assert loop["closed"]
    vertices = [session.native.anchor_candidates(list(a))[0] for a in anchors]
    assert passes_in_order(loop, vertices)
    p = np.asarray(loop["points"])
    assert np.allclose(p[0], loop["points"][-1])
    for a in anchors:
        assert np.min(np.linalg.norm(p - np.array(a[:3]), axis=1)) < 1.5  # within a mesh edge (~1.3)
    assert chain_cost(session, loop["nodes"]) == pytest.approx(loop["cost"], rel=1e-9)
    assert exhaustive_loop_cost(session, anchors, loop["cost"] * (1 + 1e-6)) == pytest.approx(loop["cost"], rel=1e-9)


def test_four_anchors_are_passed_in_their_order(coarse_torus_session):
    """Around the outer equator in turn, or zig-zagging across the hole: each loop passes its
    anchors in the order given, and the zig-zag costs more."""
    session = coarse_torus_session
    east, north, west, south = (13, 0, 0), (0, 13, 0), (-13, 0, 0), (0, -13, 0)
    costs = []
    for anchors in ([east, north, west, south], [east, west, north, south]):
        loop = session.loops(anchors)[0]
        vertices = [session.native.anchor_candidates(list(a))[0] for a in anchors]
        assert passes_in_order(loop, vertices)
        assert not passes_in_order(loop, vertices[:1] + vertices[:0:-1])  # not the other way round
        costs.append(loop["cost"])
    assert costs[1] > 1.2 * costs[0]


def test_hover_is_exact_whatever_the_pruning(torus_session):
    """Hover prunes each direction by the best loop so far, defers expensive directions and
    shares them between threads; plain Dijkstra on one thread must find the same best cost."""
    surf = torus_session.surface
    plain = LoopSession(surf, algorithm="dijkstra", threads=1)
    rng = np.random.default_rng(11)
    for i in rng.choice(len(surf.vertices), size=6, replace=False):
        p = tuple(surf.vertices[i])
        assert torus_session.best_loop(p)["cost"] == pytest.approx(plain.best_loop(p)["cost"], rel=1e-9)
    assert torus_session.best_loop((13, 0, 0))["length"] == pytest.approx(2 * math.pi * 3, rel=0.02)


def test_hover_searching_half_the_directions_finds_the_best_over_all_directions(torus_session):
    """Hover searches only the directions in [0, pi + max turn]: every loop's reversed copy
    leaves there. The alternatives search every direction; their cheapest must cost the same."""
    surf = torus_session.surface
    rng = np.random.default_rng(5)
    for i in rng.choice(len(surf.vertices), size=4, replace=False):
        p = tuple(surf.vertices[i])
        every = torus_session.loops([p], alternatives=100)
        assert torus_session.best_loop(p)["cost"] == pytest.approx(min(l["cost"] for l in every), rel=1e-9)


def test_a_query_past_its_work_cap_stops_the_same_way_every_time(torus_session):
    """Automatic weaving caps each loop query's work (polls, one per 4096 settled g' nodes)
    instead of timing it out, so that the design does not depend on the machine. On one
    thread the work a query does is exact: the same count every time, and a cap below it
    always stops the query."""
    n = torus_session.native
    n.set_threads(1)
    try:
        counts = set()
        for _ in range(2):
            assert torus_session.loops([(13, 0, 0)], alternatives=3)
            counts.add(n.last_query_polls)
            assert not n.query_limited
        (work,) = counts
        assert work > 2
        n.max_query_polls = work - 1
        for _ in range(2):
            with pytest.raises(sw.Cancelled):
                torus_session.loops([(13, 0, 0)], alternatives=3)
            assert n.query_limited
        n.max_query_polls = work   # exactly enough
        assert torus_session.loops([(13, 0, 0)], alternatives=3) and not n.query_limited
    finally:
        n.max_query_polls = 0
        n.set_threads(2)


# --- sphere, cylinder, cube --------------------------------------------------------

def test_sphere_great_circle():
    session = LoopSession(sw.from_shape(sphere(5)))
    loop = session.loops([(5, 0, 0, 0, 1, 0)])[0]
    assert loop["closed"]
    assert loop["length"] == pytest.approx(2 * math.pi * 5, rel=0.02)
    p = np.asarray(loop["points"])
    assert np.allclose(np.linalg.norm(p, axis=1), 5, atol=0.05)


def test_capped_cylinder_circumference():
    session = LoopSession(sw.from_shape(capped_cylinder(5, 20)))
    loop = session.loops([(5, 0, 10, 0, 1, 0)])[0]
    assert loop["closed"]
    assert loop["length"] == pytest.approx(2 * math.pi * 5, rel=0.02)
    assert np.ptp(np.asarray(loop["points"])[:, 2]) < 0.5  # stays at one height


def test_cube_belt_crosses_edges_orthogonally(cube_session):
    loop = cube_session.loops([(5, 5, 10, 1, 0, 0)])[0]
    assert loop["closed"]
    assert loop["length"] == pytest.approx(40, rel=0.02)
    p = np.asarray(loop["points"])
    on_edge = [i for i, q in enumerate(p[:-1]) if np.sum(np.isclose(q, 0, atol=1e-9) | np.isclose(q, 10, atol=1e-9)) >= 2]
    assert len(on_edge) >= 4
    edge_dirs = []
    for i in on_edge:
        q = p[i]
        axis = np.flatnonzero(~(np.isclose(q, 0, atol=1e-9) | np.isclose(q, 10, atol=1e-9)))
        if len(axis) != 1:
            continue  # a cube corner
        e = np.zeros(3)
        e[axis[0]] = 1
        for j in (i - 1, i + 1):
            d = p[j % (len(p) - 1)] - q
            d /= np.linalg.norm(d)
            edge_dirs.append(math.degrees(math.asin(min(1.0, abs(d @ e)))))
    assert len(edge_dirs) >= 8
    assert max(edge_dirs) < 10.0


def test_an_anchor_along_a_crease_leaves_it(cube_session):
    """A directional anchor on a cube edge, pointing along the edge: a dual loop may cross a
    crease but never run along it (the crease must be a primal edge). The anchor takes the
    nearest direction that leaves the edge, and the loop found is a belt across it, with no
    step along the edge (before: its first step ran along the edge, the loop with it)."""
    loop = cube_session.loops([(10, 5, 10, 0, 1, 0)])[0]
    p = np.asarray(loop["points"])

    def on_that_edge(q):
        return abs(q[0] - 10) < 1e-6 and abs(q[2] - 10) < 1e-6
    steps = [i for i in range(len(p) - 1) if on_that_edge(p[i]) and on_that_edge(p[i + 1])
             and np.linalg.norm(p[i + 1] - p[i]) > 1e-6]
    assert not steps
    assert loop["closed"] and loop["length"] == pytest.approx(40, rel=0.03)


def test_open_cylinder_aligned_gives_an_open_curve_meeting_the_boundaries_orthogonally():
    session = LoopSession(sw.from_shape(open_cylinder_shell(5, 20)), boundary="aligned")
    loop = session.loops([(5, 0, 10, 0, 0, 1)])[0]
    assert not loop["closed"]
    assert loop["length"] == pytest.approx(20, rel=0.03)
    p = np.asarray(loop["points"])
    assert {round(p[0, 2]), round(p[-1, 2])} == {0, 20}
    for a, b in ((p[0], p[1]), (p[-1], p[-2])):
        d = (b - a) / np.linalg.norm(b - a)
        assert math.degrees(math.acos(min(1.0, abs(d[2])))) < 10.0


# --- properties of every loop ---------------------------------------------------------

def test_polylines_lie_on_the_surface_and_respect_the_turn_limit(torus_session):
    surf = torus_session.surface
    v = surf.vertices
    edges = surf.edges
    diag = surf.bbox_diagonal
    for anchor in [(13, 0, 0), (0, 13, 0, 1, 0, 0), (7, 0, 0, 0, 1, 1)]:
        for loop in torus_session.loops([anchor], alternatives=3):
            assert loop["max_turn_deg"] <= 30.0 + 1e-6
            p = np.asarray(loop["points"])
            for q, vert, e, t in zip(p, loop["mesh_vertex"], loop["mesh_edge"], loop["edge_t"]):
                if vert >= 0:
                    on = v[vert]
                else:
                    a, b = edges[e]
                    on = (1 - t) * v[a] + t * v[b]
                assert np.linalg.norm(q - on) < 1e-6 * diag


@pytest.mark.parametrize("algorithm", ["astar", "bidirectional"])
def test_speedups_give_exactly_dijkstras_cost(algorithm):
    surf = sw.from_shape(torus(10, 3), target_triangles=8000)
    session = LoopSession(surf)
    rng = np.random.default_rng(7)
    v = surf.vertices

    def cost(anchors, name):
        session.algorithm = name
        return session.loops(anchors)[0]["cost"]

    for i in rng.choice(len(v), size=12, replace=False):
        anchor = [(*v[i], *np.cross(surf.normals[i], rng.normal(size=3)))]
        assert cost(anchor, algorithm) == pytest.approx(cost(anchor, "dijkstra"), rel=1e-9, abs=1e-9)
    # and for two directional anchors in order
    i, j = rng.choice(len(v), size=2, replace=False)
    anchors = [(*v[i], *np.cross(surf.normals[i], [0, 0, 1.0])), (*v[j], *np.cross(surf.normals[j], [0, 0, 1.0]))]
    assert cost(anchors, algorithm) == pytest.approx(cost(anchors, "dijkstra"), rel=1e-9)


# --- bad input -------------------------------------------------------------------------

def test_anchor_off_the_surface(torus_session):
    with pytest.raises(sw.InputError, match="off the part"):
        torus_session.loops([(40, 0, 0)])


def test_disabled_direction_is_a_clear_error(torus_session):
    native = torus_session.native
    vertex, candidates = native.anchor_candidates([13, 0, 0, 0, 0, 1])
    native.set_disabled(candidates, True)
    try:
        with pytest.raises(sw.InputError, match="disabled"):
            torus_session.loops([(13, 0, 0, 0, 0, 1)])
    finally:
        native.clear_disabled()


def test_mask_changes_without_rebuilding(torus_session):
    """Disabling the meridian's nodes, both ways round, makes the hover propose another loop;
    clearing restores it. (One way round only, the meridian run backwards is as cheap.)"""
    before = torus_session.best_loop((13, 0, 0))
    native = torus_session.native
    native.set_disabled(before["nodes"] + [native.reverse_node(n) for n in before["nodes"]], True)
    try:
        other = torus_session.best_loop((13, 0, 0))
        assert not set(other["nodes"]) & set(before["nodes"])
        assert other["cost"] > before["cost"]
    finally:
        native.clear_disabled()
    again = torus_session.best_loop((13, 0, 0))
    assert again["cost"] == pytest.approx(before["cost"], rel=1e-12)
    assert again["nodes"] == before["nodes"]


def test_unknown_boundary_mode():
    with pytest.raises(sw.InputError, match="boundary"):
        LoopSession(sw.from_shape(box(10), target_triangles=2000), boundary="diagonal")


def test_runs_are_deterministic_whatever_the_threads():
    surf = sw.from_shape(torus(10, 3), target_triangles=8000)
    one = LoopSession(surf, threads=1)
    two = LoopSession(surf, threads=2)
    rng = np.random.default_rng(3)
    for i in rng.choice(len(surf.vertices), size=8, replace=False):
        p = tuple(surf.vertices[i])
        a, b, c = one.best_loop(p), two.best_loop(p), two.best_loop(p)
        assert a["nodes"] == b["nodes"] == c["nodes"]
        assert a["cost"] == b["cost"] == c["cost"]


def test_released_search_workspaces_are_freed_and_come_back_for_the_next_query():
    """The job frees the search scratch space (two workspaces per thread, 20 bytes per g'
    node each) once weaving is done; a later query allocates it again and finds the same
    loop."""
    session = LoopSession(sw.from_shape(torus(10, 3), target_triangles=2000), threads=2)
    assert session.native.workspace_bytes == 0          # nothing before the first query
    nodes = session.stats()["gprime_nodes"]
    first = session.best_loop((13, 0, 0))
    # At least one workspace (which threads took part depends on their timing).
    assert session.native.workspace_bytes >= 20 * nodes
    session.native.release_workspaces()
    assert session.native.workspace_bytes == 0
    again = session.best_loop((13, 0, 0))
    assert again["nodes"] == first["nodes"] and again["cost"] == first["cost"]
    assert session.native.workspace_bytes >= 20 * nodes


def test_a_released_graph_is_freed_and_every_later_use_is_a_clear_error():
    """The job releases g' once its design and layout are derived: the design's strips and
    layout stay readable, and any use of the graph is an InputError, never a crash."""
    from stripweave.design import Design
    from stripweave.strips import DesignSession
    surface = sw.from_shape(torus(10, 3), target_triangles=2000)
    ds = DesignSession(surface, Design([[(13, 0, 0, 0, 0, 1)], [(0, 13, 0, 1, 0, 0)]]))
    session = ds.loop_session
    assert session.stats()["graph_mb"] > 0
    points = ds.strip(1)["points"]
    layout = ds.native.layout(False)
    session.native.release_graph()
    assert session.native.graph_released and session.native.workspace_bytes == 0
    assert ds.native.layout(False)["summary"] == layout["summary"]   # the layout needs no graph
    assert (ds.strip(1)["points"] == points).all()
    for use in (lambda: session.best_loop((13, 0, 0)), lambda: session.loops([(13, 0, 0, 0, 0, 1)]),
                lambda: session.stats(), lambda: session.native.set_disabled([0], True),
                lambda: ds.add_strip([(13, 0, 0)]), lambda: ds.loops([(13, 0, 0)])):
        with pytest.raises(sw.InputError, match="graph was released"):
            use()


def test_a_newer_query_cancels_an_older_one(torus_session):
    """Hovering on: a slow query still running is cancelled by the next one (raises Cancelled)."""
    import threading
    import time
    outcome = {}

    def slow():
        try:
            # Two positional anchors on opposite sides: seconds of search.
            torus_session.native.loops([[13, 0, 0], [-7, 0, 0]], 1, True)
            outcome["slow"] = "finished"
        except sw.Cancelled:
            outcome["slow"] = "cancelled"

    worker = threading.Thread(target=slow)
    start = time.perf_counter()
    worker.start()
    time.sleep(0.2)  # the slow query is under way (it releases the GIL)
    hover = torus_session.best_loop((13, 0, 0))
    worker.join()
    elapsed = time.perf_counter() - start
    assert outcome["slow"] == "cancelled", f"the older query was not cancelled ({elapsed:.2f} s)"
    assert hover["length"] == pytest.approx(2 * math.pi * 3, rel=0.02)


def test_open_curves_end_on_a_zigzag_boundary():
    """Open dual curves keep away from where a crease ends on the boundary (a corner of the
    part, loop_search.cpp), but not from where a scan's boundary merely zig-zags: an open
    cylinder mesh whose top rim alternates by +-0.4 (every rim vertex turns by more than 30
    degrees) still gets an open curve from rim to rim (refusing ends near every such turn
    left the camel head's neck no place to end curves)."""
    n, rows, r, h = 64, 40, 5.0, 20.0
    vertices = []
    for j in range(rows + 1):
        for i in range(n):
            t = 2 * math.pi * i / n
            z = h * j / rows + (0.4 * (-1) ** i if j == rows else 0.0)
            vertices.append((r * math.cos(t), r * math.sin(t), z))
    triangles = []
    for j in range(rows):
        for i in range(n):
            a, b = j * n + i, j * n + (i + 1) % n
            triangles += [(a, b, b + n), (a, b + n, a + n)]
    surface = sw.from_mesh(vertices, triangles)
    assert surface.report()["boundary_loops"] == 2
    loop = LoopSession(surface, boundary="aligned").loops([(5, 0, 10, 0, 0, 1)])[0]
    assert not loop["closed"]
    p = np.asarray(loop["points"])
    assert sorted((p[0, 2], p[-1, 2])) == [pytest.approx(0, abs=1e-9), pytest.approx(20, abs=0.41)]


def test_an_open_curve_meets_the_boundary_across_it_not_along_it():
    """A plate (an open face) with four round holes, queried at points on the holes' rims. An
    open curve ends at the boundary (§5.7), meeting it orthogonally: a g' node along the rim,
    both its ends on it, is no end. Before, such a node closed a "curve" of that node alone
    at cost 0, cheaper than any real loop, so every query near a rim returned one (a range
    scan's holes took 12 of its 18 strips, each clipping a corner of a hole)."""
    import FreeCAD  # noqa: F401  (before Part)
    import Part
    plate = Part.makePlane(60, 30)
    for x in (12, 24, 36, 48):
        plate = plate.cut(Part.Face(Part.Wire(Part.makeCircle(3.0, FreeCAD.Vector(x, 15, 0)))))
    session = LoopSession(sw.from_shape(plate, target_triangles=8000))

    def boundary_tangent(p):
        hole = min((12, 24, 36, 48), key=lambda c: abs(math.hypot(p[0] - c, p[1] - 15) - 3))
        if abs(math.hypot(p[0] - hole, p[1] - 15) - 3) < 0.2:
            return np.array([-(p[1] - 15), p[0] - hole, 0.0]) / 3.0
        return np.array([1.0, 0, 0]) if min(p[1], 30 - p[1]) < 0.2 else np.array([0, 1.0, 0])

    for x in (12, 36):
        for a in (0.0, 1.3, 2.9, 4.4):
            loop = session.best_loop((x + 3.0 * math.cos(a), 15 + 3.0 * math.sin(a), 0.0))
            assert loop["cost"] > 0
            assert loop["length"] > 3.0      # it crosses the plate, not a corner of the rim
            points = np.asarray(loop["points"])
            if loop["closed"]:
                continue
            # Each end arrives across the boundary: nearer its normal than its tangent.
            for end, before in ((points[0], points[min(3, len(points) - 1)]), (points[-1], points[max(-4, -len(points))])):
                arriving = (end - before) / np.linalg.norm(end - before)
                assert abs(float(arriving @ boundary_tangent(end))) < math.sqrt(0.5)
