"""The global parameterization S (paper §6.1): analytic checks in model units.

Every check recomputes what it tests from the raw output (corner coordinates,
transitions, the embedded loop) rather than trusting the summary figures:
  - a loop is an isocurve: in each triangle it crosses, the across-coordinate
    interpolated at the segment's two end points agrees, and carried from
    triangle to triangle through the transitions it keeps one value all the
    way round;
  - S is aligned and isometric: grad u follows the combed cross field, with
    unit length where the surface allows it;
  - transitions are what the charts say: each cut edge's two charts differ
    by the stated quarter turn and translation at both of its ends;
  - fold-overs are counted right.
"""
import math

import numpy as np
import pytest

import stripweave as sw
from field_rotation import assert_singularities_are_the_fields_rotation
from models import box, sphere, torus
from stripweave._native import native
from stripweave.loops import LoopSession

SIZE = dict(target_triangles=12000)  # fast; the bench measures at 30K


def loops_through(session, anchors):
    """The best loop through each directional anchor (model units)."""
    return [session.native.loops([list(a)], 1, True)[0] for a in anchors]


def parameterize(session, anchors, **options):
    return native.parameterize(session.native, loops_through(session, anchors), **options)


# --- recomputation from the raw output ---------------------------------------------

def triangle_normals(surface):
    p = surface.vertices[surface.triangles]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def gradients(surface, values):
    """Per triangle, the 3D gradient of the linear function with corner values (T, 3)."""
    p = surface.vertices[surface.triangles]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    d1, d2 = values[:, 1] - values[:, 0], values[:, 2] - values[:, 0]
    a, b, c = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    det = a * c - b * b
    x, y = (c * d1 - b * d2) / det, (a * d2 - b * d1) / det
    return x[:, None] * e1 + y[:, None] * e2


def combed_field(surface, result):
    """The field direction per triangle turned by its comb (quarter turns about the normal)."""
    n = triangle_normals(surface)
    f = np.asarray(result["direction"])
    f = f - (f * n).sum(1, keepdims=True) * n
    f /= np.linalg.norm(f, axis=1, keepdims=True)
    comb = np.asarray(result["comb"]) % 4
    out = f.copy()
    for r in range(1, 4):
        turned = f
        for _ in range(r):
            turned = np.cross(n, turned)
        out[comb == r] = turned[comb == r]
    return out


def angle_deg(a, b):
    cos = (a * b).sum(1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


def barycentric(surface, path, i, t):
    """Barycentric coordinates of path point i in triangle t, from the path's vertex/edge/t."""
    tri = surface.triangles[t]
    b = np.zeros(3)
    if path["vertex"][i] >= 0:
        b[list(tri).index(path["vertex"][i])] = 1
    else:
        a, c = surface.edges[path["edge"][i]]
        s = path["t"][i]
        b[list(tri).index(a)] += 1 - s
        b[list(tri).index(c)] += s
    return b


def turn(p, r):
    """R^r p, R the counter-clockwise quarter turn."""
    for _ in range(r % 4):
        p = np.array([-p[1], p[0]])
    return p


class Charts:
    """Chart changes between triangles, composed from the per-edge transitions."""

    def __init__(self, surface, result):
        self.et = np.asarray(result["edge_triangles"])
        self.r = np.asarray(result["transition_r"])
        self.tr = np.asarray(result["transition_tr"])
        self.tris = surface.triangles
        self.edge_of = {tuple(sorted(e)): i for i, e in enumerate(surface.edges)}

    def across(self, e, frm):
        """(r, tr) with chart(other) = R^r chart(frm) + tr across edge e."""
        r, tr = int(self.r[e]), self.tr[e]
        if self.et[e][0] == frm:
            return r, tr
        return (-r) % 4, -turn(tr, -r)  # chart0 = R^-r (chart1 - tr)

    def path_between(self, t0, t1, vertex=None, edge=None):
        """A walk of edges from t0 to t1 through triangles that hold the shared point."""
        if t0 == t1:
            return []
        if edge is not None:
            assert set(self.et[edge]) == {t0, t1}
            return [(edge, t0)]
        # Breadth first around the vertex, through edges at the vertex.
        previous = {t0: None}
        queue = [t0]
        while queue:
            t = queue.pop(0)
            tri = list(self.tris[t])
            for w in tri:
                if w == vertex:
                    continue
                e = self.edge_of[tuple(sorted((vertex, w)))]
                u = self.et[e][1] if self.et[e][0] == t else self.et[e][0]
                if u >= 0 and u not in previous:
                    previous[u] = (e, t)
                    queue.append(u)
        walk, t = [], t1
        while previous[t] is not None:
            e, frm = previous[t]
            walk.append((e, frm))
            t = frm
        return walk[::-1]

    def carry(self, axis, value, walk):
        """The isocurve {coordinate `axis` = value} mapped through a walk of edges."""
        for e, frm in walk:
            r, tr = self.across(e, frm)
            image = np.zeros(2)
            image[axis] = value  # any point of the isocurve; its image's other coordinate is free
            image = turn(image, r) + tr
            axis = axis if r % 2 == 0 else 1 - axis
            value = image[axis]
        return axis, value


def carried_values(surface, result, loop):
    """Walk a loop segment by segment, carrying its first segment's isocurve through the
    transitions; per step (carried axis, carried value, stated axis, stated value)."""
    charts = Charts(surface, result)
    path, tris = loop["path"], loop["triangles"]
    n = len(tris)
    axis, value = loop["axis"][0], loop["value"][0]
    steps = []
    for k in range(n if loop["closed"] else n - 1):
        j = (k + 1) % n
        i = loop["to"][k]
        vertex = path["vertex"][i] if path["vertex"][i] >= 0 else None
        edge = path["edge"][i] if vertex is None else None
        axis, value = charts.carry(axis, value, charts.path_between(tris[k], tris[j], vertex, edge))
        steps.append((axis, value, loop["axis"][j], loop["value"][j]))
    return steps


def across_residuals(surface, result, loop):
    """|c(from) - c(to)| per segment, c the across-coordinate interpolated from the corners."""
    uv = np.asarray(result["uv"])
    out = []
    for k, t in enumerate(loop["triangles"]):
        a = loop["axis"][k]
        cf = barycentric(surface, loop["path"], loop["from"][k], t) @ uv[t][:, a]
        ct = barycentric(surface, loop["path"], loop["to"][k], t) @ uv[t][:, a]
        out.append(abs(cf - ct))
    return np.array(out)


def loop_length(loop):
    p = np.asarray(loop["path"]["points"])
    if loop["closed"]:
        p = np.vstack([p, p[:1]])
    return np.linalg.norm(np.diff(p, axis=0), axis=1).sum()


def fold_overs(result):
    uv = np.asarray(result["uv"])
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return int(np.sum(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0))


def assert_isocurves(surface, result):
    for loop in result["loops"]:
        width = loop_length(loop) / 10  # a typical strip width
        tolerance = 1e-6 * width
        assert np.max(across_residuals(surface, result, loop)) < tolerance
        for carried_axis, carried, axis, value in carried_values(surface, result, loop):
            assert carried_axis == axis
            assert carried == pytest.approx(value, abs=tolerance)


def assert_transitions_match_charts(surface, result):
    """On every cut edge, both ends' coordinates obey chart1 = R^r chart0 + tr; off the cut
    the two triangles agree at the shared corners."""
    uv = np.asarray(result["uv"])
    tris = surface.triangles
    scale = np.ptp(uv.reshape(-1, 2), axis=0).max()
    for e, (t0, t1) in enumerate(np.asarray(result["edge_triangles"])):
        if t1 < 0:
            continue
        r, tr = int(result["transition_r"][e]), np.asarray(result["transition_tr"][e])
        if not result["on_cut"][e]:
            assert r == 0 and not tr.any()
        for v in surface.edges[e]:
            p0 = uv[t0][list(tris[t0]).index(v)]
            p1 = uv[t1][list(tris[t1]).index(v)]
            assert np.linalg.norm(turn(p0, r) + tr - p1) < 1e-9 * scale


# --- torus with a meridian loop --------------------------------------------------

@pytest.fixture(scope="module")
def torus_case():
    surface = sw.from_shape(torus(10, 3), **SIZE)
    session = LoopSession(surface)
    return surface, parameterize(session, [(13, 0, 0, 0, 0, 1)])


def test_torus_meridian_is_an_isocurve_without_fold_overs(torus_case):
    surface, result = torus_case
    assert result["fold_overs"] == 0 == fold_overs(result)
    (loop,) = result["loops"]
    assert loop["closed"]
    assert loop_length(loop) == pytest.approx(2 * math.pi * 3, rel=0.02)
    assert_isocurves(surface, result)
    # The loop runs along one coordinate throughout: the field follows it.
    assert len(set(loop["axis"])) == 1


def test_torus_has_no_singularity_and_a_cut_of_two_cycles(torus_case):
    """Genus 1, a field without singularities: the cut is a connected graph of cycle rank
    2g = 2 (two non-contractible cycles) without dangling branches."""
    surface, result = torus_case
    assert result["singularities"] == [] and list(result["cut_ends"]) == []
    assert assert_singularities_are_the_fields_rotation(surface, result["direction"], result["singularities"]) == {}
    cut_edges = surface.edges[np.asarray(result["on_cut"], bool)]
    degree = np.bincount(cut_edges.ravel(), minlength=len(surface.vertices))
    assert not np.any(degree == 1)
    cut_vertices = np.count_nonzero(degree)
    assert len(cut_edges) - cut_vertices + 1 == 2


def test_torus_transitions_match_the_charts(torus_case):
    surface, result = torus_case
    assert_transitions_match_charts(surface, result)


def test_torus_gradients_follow_the_combed_field_isometrically(torus_case):
    """grad u follows the combed field f and grad v its quarter turn n x f. The coordinate
    along the meridians (the one varying along the loop) is arc length, |grad| = 1; the one
    around the axis cannot be (parallels of radius rho = 7..13 all map to one period), so
    its gradient is c / rho for one constant c."""
    surface, result = torus_case
    uv = np.asarray(result["uv"])
    f = combed_field(surface, result)
    n = triangle_normals(surface)
    gu, gv = gradients(surface, uv[:, :, 0]), gradients(surface, uv[:, :, 1])
    centroid = surface.vertices[surface.triangles].mean(axis=1)
    away = np.abs(np.arctan2(centroid[:, 1], centroid[:, 0])) > 0.3  # away from the loop at angle 0
    assert np.percentile(angle_deg(gu, f)[away], 99) < 3
    assert np.percentile(angle_deg(gv, np.cross(n, f))[away], 99) < 3
    across = result["loops"][0]["axis"][0]  # constant on the meridian: the coordinate around the axis
    along_gradient = np.linalg.norm(gv if across == 0 else gu, axis=1)
    around_gradient = np.linalg.norm(gu if across == 0 else gv, axis=1)
    assert np.median(along_gradient[away]) == pytest.approx(1, abs=0.02)
    assert np.percentile(np.abs(along_gradient[away] - 1), 95) < 0.05
    rho = np.linalg.norm(centroid[:, :2], axis=1)
    c = around_gradient[away] * rho[away]
    assert np.std(c) / np.mean(c) < 0.03


# --- cube with three belts ------------------------------------------------------

@pytest.fixture(scope="module")
def cube_case():
    surface = sw.from_shape(box(10), **SIZE)
    session = LoopSession(surface)
    anchors = [(5, 5, 10, 1, 0, 0), (5, 3, 0, 0, 1, 0), (3, 0, 5, 1, 0, 0)]
    return surface, parameterize(session, anchors)


def test_cube_belts_are_isocurves_without_fold_overs(cube_case):
    surface, result = cube_case
    assert len(result["loops"]) == 3 and all(l["closed"] for l in result["loops"])
    for loop in result["loops"]:
        assert loop_length(loop) == pytest.approx(40, rel=0.02)  # a belt around the cube
    assert result["fold_overs"] == 0 == fold_overs(result)
    assert_isocurves(surface, result)


def test_cube_cut_reaches_the_eight_corners(cube_case):
    """The feature-aligned field has a +1/4 singularity at each corner (Poincare-Hopf: 8/4 = 2),
    and the cut must reach each of them."""
    surface, result = cube_case
    corners = {tuple(np.round(surface.vertices[s["vertex"]], 6)) for s in result["singularities"]}
    assert corners == {(x, y, z) for x in (0, 10) for y in (0, 10) for z in (0, 10)}
    # Counted independently from the field's turns around each vertex: +1/4 at each corner.
    count = assert_singularities_are_the_fields_rotation(surface, result["direction"], result["singularities"])
    assert sorted(count.values()) == [1] * 8
    on_cut = np.asarray(result["on_cut"], bool)
    degree = np.bincount(surface.edges[on_cut].ravel(), minlength=len(surface.vertices))
    for s in result["singularities"]:
        assert degree[s["vertex"]] >= 1
    assert set(result["cut_ends"]) == {s["vertex"] for s in result["singularities"]}


def test_cube_transitions_match_the_charts(cube_case):
    surface, result = cube_case
    assert_transitions_match_charts(surface, result)
    # Around a quarter-index corner the charts turn by an odd number of quarter turns.
    assert any(r % 2 == 1 for r, c in zip(result["transition_r"], result["on_cut"]) if c)


def test_cube_faces_are_mapped_isometrically(cube_case):
    """A cube is flat away from its corners: S is an exact isometry on every face."""
    surface, result = cube_case
    uv = np.asarray(result["uv"])
    f = combed_field(surface, result)
    gu = gradients(surface, uv[:, :, 0])
    assert np.percentile(angle_deg(gu, f), 95) < 2
    assert np.percentile(np.abs(np.linalg.norm(gu, axis=1) - 1), 95) < 0.05


# --- sphere with three great circles ---------------------------------------------

@pytest.fixture(scope="module")
def sphere_session():
    return LoopSession(sw.from_shape(sphere(5), **SIZE))


def test_sphere_great_circles_are_isocurves(sphere_session):
    surface = sphere_session.surface
    anchors = [(5, 0, 0, 0, 1, 0), (0, 5, 0, 0, 0, 1), (0, 0, 5, 1, 0, 0)]
    result = parameterize(sphere_session, anchors)
    for loop in result["loops"]:
        assert loop_length(loop) == pytest.approx(2 * math.pi * 5, rel=0.02)
    assert_isocurves(surface, result)
    assert_transitions_match_charts(surface, result)
    # Fold-overs: reported as S has them (few, next to the singularities).
    assert result["fold_overs"] == fold_overs(result) == int(np.sum(result["flipped"]))
    assert result["fold_overs"] <= 0.01 * len(surface.triangles)
    # Eight octants, each with a +1/4 singularity (counted again from the field's turns).
    assert sorted(s["index"] for s in result["singularities"]) == [0.25] * 8
    count = assert_singularities_are_the_fields_rotation(surface, result["direction"], result["singularities"])
    octants = {tuple(np.sign(surface.vertices[v]).astype(int)) for v in count}
    assert sorted(count.values()) == [1] * 8 and len(octants) == 8


def test_loops_crossing_at_a_shallow_angle_are_rejected(sphere_session):
    """Two great circles at 30 degrees: the cross field averages them, both run along
    the same coordinate where they cross, and they cannot both be its isocurves."""
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    with pytest.raises(sw.InputError, match="meet"):
        parameterize(sphere_session, [(5, 0, 0, 0, 1, 0), (5, 0, 0, 0, c, s)])


def test_no_loops_gives_the_field_aligned_map(sphere_session):
    """Without loops S is still computed (aligned to the field) and consistent across the cut."""
    surface = sphere_session.surface
    result = native.parameterize(sphere_session.native, [])
    assert result["loops"] == []
    assert_transitions_match_charts(surface, result)
