"""Surfacing stage: patch network -> fitted B-spline patches, shell, STEP.

Until the layout stage produces networks, the networks are built here from
analytic geometry: the 6 faces of a cube, each a triangulated grid, mapped
onto the model (the box itself, or radially onto a sphere: the "cube sphere"
with its 8 valence-3 corners)."""
import math
import os

import numpy as np
import pytest

import models
import stripweave as sw
from stripweave._native import native

# The 6 faces of the cube [-1, 1]^3 as (center, a, b) with a x b outward.
CUBE_FACES = [
    ((0, 0, -1), (0, 1, 0), (1, 0, 0)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 1, 0), (0, 0, 1), (1, 0, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
]


def cube_network(mapping, grid, sharp, face_of=lambda center: 0, split=1):
    """The cube's 6 faces (each split into split x split patches) as a patch
    network, every point mapped by `mapping` (cube point -> model point);
    face_of(center) is the B-rep face of a patch."""
    vertices, vertex_id = [], {}
    edges, edge_id = [], {}
    patches = []

    def corner(p):
        key = tuple(int(round(x * split)) for x in p)
        if key not in vertex_id:
            vertex_id[key] = len(vertices)
            vertices.append(mapping(np.array(p, dtype=float)))
        return vertex_id[key]

    sub_squares = []
    for center, a, b in CUBE_FACES:
        c, a, b = (np.array(x, dtype=float) for x in (center, a, b))
        for I in range(split):
            for J in range(split):
                sub_squares.append((c, c + ((2 * I + 1) / split - 1) * a + ((2 * J + 1) / split - 1) * b,
                                    a / split, b / split))
    for face_centre, c, a, b in sub_squares:
        g = grid
        idx = lambda i, j: i * (g + 1) + j  # noqa: E731  (i along u = a, j along v = b)
        cube_pts = {(i, j): c + (2 * i / g - 1) * a + (2 * j / g - 1) * b for i in range(g + 1) for j in range(g + 1)}
        pts = np.array([mapping(cube_pts[(i, j)]) for i in range(g + 1) for j in range(g + 1)])
        tris = []
        for i in range(g):
            for j in range(g):
                tris.append((idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)))
                tris.append((idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)))
        sides = [[(i, 0) for i in range(g + 1)], [(g, j) for j in range(g + 1)],
                 [(g - i, g) for i in range(g + 1)], [(0, g - j) for j in range(g + 1)]]
        p_edges, p_rev = [], []
        for side in sides:
            v0, v1 = corner(cube_pts[side[0]]), corner(cube_pts[side[-1]])
            key = frozenset((v0, v1))
            if key not in edge_id:
                edge_id[key] = len(edges)
                edges.append({"points": np.array([pts[idx(*ij)] for ij in side]), "vertices": [v0, v1],
                              "sharp": sharp, "boundary": False})
                p_rev.append(False)
            else:
                p_rev.append(edges[edge_id[key]]["vertices"][0] != v0)
            p_edges.append(edge_id[key])
        patches.append({"edges": p_edges, "reversed": p_rev, "vertices": pts, "triangles": np.array(tris),
                        "corners": [idx(0, 0), idx(g, 0), idx(g, g), idx(0, g)],
                        "source_face": np.full(len(tris), face_of(face_centre), dtype=np.int32)})
    return {"vertices": np.array(vertices), "edges": edges, "patches": patches}


def box_face_index(shape):
    """B-rep face id (0-based, TopExp order = Shape.Faces order) of a box face by its outward direction."""
    centre = shape.BoundBox.Center

    def face_of(direction):
        best, best_dot = -1, -2
        for k, f in enumerate(shape.Faces):
            d = f.CenterOfMass - centre
            d.normalize()
            dot = d.x * direction[0] + d.y * direction[1] + d.z * direction[2]
            if dot > best_dot:
                best, best_dot = k, dot
        return best
    return face_of


def test_refit_reports_two_sided_deviation_and_coverage():
    """refit's result carries the two-sided deviation and the coverage (design.md's fit
    keys): the box's exact network covers the whole part, both directions are zero, and
    triangle_uncovered holds one float per surface triangle, all zero."""
    shape = models.box(10.0)
    surf = sw.from_shape(shape)
    net = cube_network(lambda p: 5.0 + 5.0 * p, grid=6, sharp=True, face_of=box_face_index(shape))
    r = native.refit(surf, net)
    assert r["max_deviation_source_to_patches"] < 1e-9 and r["max_deviation_patches_to_source"] < 1e-9
    assert r["max_deviation"] == max(r["max_deviation_source_to_patches"], r["max_deviation_patches_to_source"])
    assert r["coverage"] == pytest.approx(1.0) and r["uncovered_area"] < 1e-9
    assert r["source_area"] == pytest.approx(600.0, rel=1e-6)
    # Dense: about one source sample per solver triangle or more, 8 patch samples per span.
    assert r["source_samples"] >= 0.5 * len(surf.triangles) and r["patch_samples"] >= 6 * 9 * 9
    assert r["measurement_error"] < 0.5 * r["tolerance"]
    u = r["triangle_uncovered"]
    assert isinstance(u, np.ndarray) and u.dtype == np.float64 and u.shape == (len(surf.triangles),)
    assert np.all(u == 0)
    for p in r["per_patch"]:
        assert p["max_deviation"] == max(p["max_deviation_source_to_patch"], p["max_deviation_patch_to_source"])
        assert p["source_area"] == pytest.approx(100.0, rel=0.01)  # each face's source is nearest its own patch


def test_cube(tmp_path):
    shape = models.box(10.0)
    surf = sw.from_shape(shape)
    net = cube_network(lambda p: 5.0 + 5.0 * p, grid=6, sharp=True, face_of=box_face_index(shape))
    step = str(tmp_path / "cube.step")
    r = native.refit(surf, net, step_path=step)
    diag = 10 * math.sqrt(3)
    assert r["faces"] == 6
    assert r["max_deviation"] <= 1e-4 * diag
    assert r["max_edge_deviation"] <= 1e-4 * diag
    assert r["tolerance_met"]
    assert r["valid_shell"] and r["closed"]
    assert r["volume"] == pytest.approx(1000.0, rel=1e-3)
    assert r["max_seam_gap"] < 1e-9 * diag
    assert r["sharp_seams"] == 12 and r["smooth_seams"] == 0
    assert r["max_sharp_angle_deg"] == pytest.approx(90.0, abs=1e-6)
    assert r["step_faces_read_back"] == 6
    assert os.path.getsize(step) > 0
    with open(step) as f:
        head = f.read(4000)
    assert "AUTOMOTIVE_DESIGN" in head.upper()  # AP214
    assert len(r["per_patch"]) == 6
    assert all(p["nu"] == 1 and p["nv"] == 1 for p in r["per_patch"])  # a plane needs one span


def sphere_case(R=5.0, grid=10, **kw):
    shape = models.sphere(R)
    surf = sw.from_shape(shape)
    net = cube_network(lambda p: R * p / np.linalg.norm(p), grid=grid, sharp=False)
    return native.refit(surf, net, **kw)


def test_cube_sphere(tmp_path):
    R = 5.0
    diag = 2 * R * math.sqrt(3)
    r = sphere_case(R, step_path=str(tmp_path / "sphere.step"))
    assert r["faces"] == 6 and r["step_faces_read_back"] == 6
    assert r["tolerance_met"]
    assert r["max_deviation"] <= 1e-3 * diag
    assert r["max_seam_gap"] < 1e-6 * diag
    assert r["smooth_seams"] == 12
    # G1 along the regular middle of each seam; the valence-3 corners cannot be.
    assert r["max_seam_angle_deg"] < 1.0
    assert r["valid_shell"] and r["closed"]
    assert r["volume"] == pytest.approx(4 / 3 * math.pi * R ** 3, rel=5e-3)


def test_tolerance_drives_refinement():
    """A tighter tolerance, more spans, and both tolerances met on the two-sided measure.
    (At 1e-3 the refinement stops on its own samples at 0.76e-3 while the two-sided
    deviation is 2.7e-3: the fit's samples are too sparse for 19 spans, issue 19.)"""
    coarse = sphere_case(tolerance=1e-2)
    fine = sphere_case(tolerance=2e-3)
    assert coarse["tolerance_met"] and fine["tolerance_met"]
    assert fine["max_deviation"] <= 2e-3 < coarse["tolerance"]
    spans = lambda r: sum(p["nu"] * p["nv"] for p in r["per_patch"])  # noqa: E731
    assert spans(fine) > spans(coarse)


def test_mesh_source():
    """Without a B-rep the samples come from the source mesh."""
    R = 5.0
    shape = models.sphere(R)
    mesh = shape.tessellate(0.01)
    surf = sw.from_mesh(np.array([[p.x, p.y, p.z] for p in mesh[0]]), np.array(mesh[1], dtype=np.int32),
                       target_triangles=5000)
    net = cube_network(lambda p: R * p / np.linalg.norm(p), grid=10, sharp=False)
    for p in net["patches"]:
        del p["source_face"]
    r = native.refit(surf, net)
    assert r["faces"] == 6 and r["closed"] and r["valid_shell"]
    assert r["max_deviation"] <= r["tolerance"]
    assert r["volume"] == pytest.approx(4 / 3 * math.pi * R ** 3, rel=1e-2)


def test_bad_networks():
    surf = sw.from_shape(models.box(10.0))
    net = cube_network(lambda p: 5.0 + 5.0 * p, grid=3, sharp=True)
    bad = dict(net, patches=[dict(net["patches"][0], corners=[0, 3, 15, 12])] + net["patches"][1:])
    with pytest.raises(sw.InputError):
        native.refit(surf, bad)
    bad = dict(net, patches=[dict(net["patches"][0], edges=[0, 1, 2, 99])] + net["patches"][1:])
    with pytest.raises(sw.InputError):
        native.refit(surf, bad)
    with pytest.raises(sw.InputError):
        native.refit(surf, {"vertices": np.zeros((0, 3)), "edges": [], "patches": []})
    with pytest.raises(sw.InputError):
        native.refit(surf, net, tolerance=-1)


def test_hundred_patches_regular_seams():
    """96 patches (each cube face split 4 x 4): regular valence-4 vertices
    inside the faces, where the seams must come out G1; timing target 10 s."""
    R = 5.0
    surf = sw.from_shape(models.sphere(R))
    net = cube_network(lambda p: R * p / np.linalg.norm(p), grid=4, sharp=False, split=4)
    assert len(net["patches"]) == 96
    r = native.refit(surf, net)
    assert r["faces"] == 96 and r["closed"] and r["valid_shell"]
    assert r["tolerance_met"]
    assert r["max_seam_gap"] < 1e-6 * 2 * R * math.sqrt(3)
    # G1 within 1 deg at the regular seams: at the default tolerance every
    # patch here is a single bicubic span, too few controls for the C1 rows
    # to absorb the varying speed ratio along a seam (1.7 deg), so the fits
    # without the seam condition, which meet better (0.7 deg), are kept.
    assert r["max_seam_angle_deg_regular"] < 1.0
    assert r["max_seam_angle_deg"] < 1.0
    assert r["volume"] == pytest.approx(4 / 3 * math.pi * R ** 3, rel=5e-3)
    assert r["time_s"] < 10.0


def rotated_box_network(size=10.0, grid=24, turn_deg=45.0):
    """The cube network turned about z by turn_deg and projected centrally onto the
    box [0, size]^3: every patch then lies over one or more of the box's 90 degree
    creases (a layout that ignores the feature curves). source_face per triangle: the
    box face under its centroid."""
    shape = models.box(size)
    face_of = box_face_index(shape)
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))
    turn = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])

    def onto_box(p):
        q = turn @ p
        return size / 2 * (1 + q / np.abs(q).max())
    net = cube_network(onto_box, grid=grid, sharp=False)
    for P in net["patches"]:
        V, T = np.asarray(P["vertices"]), np.asarray(P["triangles"])
        centroids = V[T].mean(axis=1) - size / 2
        axis = np.abs(centroids).argmax(axis=1)
        P["source_face"] = np.array([face_of(tuple(np.eye(3)[a] * np.sign(ctr[a])))
                                     for a, ctr in zip(axis, centroids)], dtype=np.int32)
    return shape, net


def fitted_faces(result):
    import Part
    shell = Part.Shape()
    shell.importBrepFromString(result["brep"])
    return shell.Faces


def test_creases_inside_patches_are_reported():
    """A layout whose patches lie over the box's creases: the refit says so per patch
    (a C2 patch cannot follow a crease), and the deviation it reports is the true one:
    samples by a crease are projected within their B-rep face's trim, never onto a
    face's continuation past the crease (off the box), so the fitted surfaces stay as
    close to the real box as the report says."""
    import Part
    size = 10.0
    shape, net = rotated_box_network(size)
    r = native.refit(sw.from_shape(shape), net, return_brep=True)
    assert r["creased_patches"] == 6
    for p in r["per_patch"]:
        assert p["creased"] and 80 <= p["crease_deg"] <= 100 and p["crease_length"] > size
    assert not r["tolerance_met"]  # 24 spans cannot round a 90 degree crease within 1e-3
    # The reported deviation bounds the fitted surfaces' true distance from the box
    # (sampled on each fitted patch).
    true = 0.0
    for f in fitted_faces(r):
        u0, u1, v0, v1 = f.ParameterRange
        for u in np.linspace(u0, u1, 9):
            for v in np.linspace(v0, v1, 9):
                true = max(true, shape.distToShape(Part.Vertex(f.Surface.value(u, v)))[0])
    assert true <= 1.05 * r["max_deviation"]
    from stripweave.surfacing import problem_of
    assert all(problem_of(p, r["tolerance"]).startswith("layout:") for p in r["per_patch"]
               if p["max_deviation"] > r["tolerance"])


def test_aligned_layout_has_no_creased_patch():
    """The same box with the layout along its creases (sharp seams): no patch is creased,
    and the tolerance holds on every patch."""
    shape = models.box(10.0)
    net = cube_network(lambda p: 5.0 + 5.0 * p, grid=6, sharp=True,
                       face_of=lambda centre: box_face_index(shape)(centre))
    r = native.refit(sw.from_shape(shape), net)
    assert r["creased_patches"] == 0 and r["folded_patches"] == 0
    assert all(p["crease_deg"] < 1.0 and not p["creased"] for p in r["per_patch"])
    assert r["tolerance_met"] and r["tolerance_met_uncreased"]


def test_concave_crease_samples_stay_on_the_part():
    """A sphere poking out of a box (R 5, box half-size 3): 53 degree concave creases
    inside the patches, where the continuation of each face runs inside the other's
    material. Samples by a crease take the nearest foot point within their own face's
    trim (else the crease itself); the nearest untrimmed foot point lay off the part,
    and the edge curves crossing the creases missed their samples (0.020 against the
    tolerance 0.017, deviation 0.11)."""
    import Part
    from FreeCAD import Vector
    R, H = 5.0, 3.0
    shape = Part.makeSphere(R).fuse(Part.makeBox(2 * H, 2 * H, 2 * H, Vector(-H, -H, -H))).removeSplitter()

    def onto(p):
        d = p / np.linalg.norm(p)
        return d * max(R, H / np.abs(d).max())
    net = cube_network(onto, grid=16, sharp=False)
    faces = shape.Faces
    for P in net["patches"]:
        V, T = np.asarray(P["vertices"]), np.asarray(P["triangles"])
        P["source_face"] = np.array(
            [min(range(len(faces)), key=lambda k: faces[k].distToShape(Part.Vertex(Vector(*onto(c))))[0])
             for c in V[T].mean(axis=1)], dtype=np.int32)
    r = native.refit(sw.from_shape(shape), net)
    assert r["creased_patches"] == 6 and all(45 < p["crease_deg"] < 60 for p in r["per_patch"])
    assert r["max_edge_deviation"] <= r["tolerance"]
    # The fit's own samples (on the part) are met within 4 tolerances; the two-sided
    # deviation sees more: where a patch cuts a box corner, 0.11 inside the part (6.4
    # tolerances, FreeCAD's distToShape there agrees), so the tolerance is not met, and
    # the reason given is the layout's (creased patches).
    assert r["fit_max_deviation"] <= 4 * r["tolerance"]
    assert 4 * r["tolerance"] < r["max_deviation"] < 8 * r["tolerance"] and not r["tolerance_met"]
    from stripweave.surfacing import problem_of
    assert all(problem_of(p, r["tolerance"]).startswith("layout:") for p in r["per_patch"]
               if p["max_deviation"] > r["tolerance"])
    assert r["valid_shell"] and r["closed"] and r["max_seam_gap"] < 1e-6 * 2 * H * math.sqrt(3)


def test_vertex_tangent_planes_option():
    """The experimental vertex_tangent_planes: the edge curves at each smooth vertex leave
    it in one plane, so on the 96-patch cube sphere (valence 3 and 4 vertices, all smooth)
    the patches meeting at a vertex share its normal and the seams stay G1 within 1 deg,
    at the same accuracy."""
    R = 5.0
    surf = sw.from_shape(models.sphere(R))
    net = cube_network(lambda p: R * p / np.linalg.norm(p), grid=4, sharp=False, split=4)
    r = native.refit(surf, net, vertex_tangent_planes=True, return_brep=True)
    assert r["tolerance_met"] and r["valid_shell"] and r["closed"]
    assert r["max_seam_angle_deg_regular"] < 1.0
    # At every network vertex the patches' corner normals agree.
    import Part
    from FreeCAD import Vector
    normals = {}
    for f in fitted_faces(r):
        u0, u1, v0, v1 = f.ParameterRange
        for u, v in ((u0, v0), (u1, v0), (u1, v1), (u0, v1)):
            p = f.Surface.value(u, v)
            key = tuple(round(x, 6) for x in (p.x, p.y, p.z))
            normals.setdefault(key, []).append(f.Surface.normal(u, v))
    worst = max(math.degrees(ns[0].getAngle(n)) for ns in normals.values() for n in ns)
    assert len(normals) == 98 and worst < 0.01  # 0.14 deg without the option


def _cox_de_boor(knots, i, p, t, derivative=0):
    """N_{i,p}(t) or its derivative, by the recursion of The NURBS Book (2.5, 2.9), with
    0/0 = 0 and the last span closed at its end: the reference for the span table."""
    if derivative:
        if p == 0:
            return 0.0
        out = 0.0
        if knots[i + p] > knots[i]:
            out += p / (knots[i + p] - knots[i]) * _cox_de_boor(knots, i, p - 1, t, derivative - 1)
        if knots[i + p + 1] > knots[i + 1]:
            out -= p / (knots[i + p + 1] - knots[i + 1]) * _cox_de_boor(knots, i + 1, p - 1, t, derivative - 1)
        return out
    if p == 0:
        last = knots[-1]
        inside = knots[i] <= t < knots[i + 1] or (t == last and knots[i] < knots[i + 1] == last)
        return 1.0 if inside else 0.0
    out = 0.0
    if knots[i + p] > knots[i]:
        out += (t - knots[i]) / (knots[i + p] - knots[i]) * _cox_de_boor(knots, i, p - 1, t)
    if knots[i + p + 1] > knots[i + 1]:
        out += (knots[i + p + 1] - t) / (knots[i + p + 1] - knots[i + 1]) * _cox_de_boor(knots, i + 1, p - 1, t)
    return out


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 6, 9])
def test_the_cubic_basis_agrees_with_cox_de_boor_on_every_span_of_the_clamped_uniform_knots(n):
    """cubic_basis evaluates each span of the clamped uniform cubic spline from one of nine
    span shapes (bspline.cpp). Against the textbook recursion on the knot vector
    0,0,0,0, 1/n, .., 1,1,1,1: the four nonzero functions, their first and second
    derivatives and the first index, at points inside every span, at the knots and at both
    ends, for spline sizes whose end spans meet (n < 5) and ones with uniform spans between.
    The functions also sum to one and their derivatives to zero."""
    knots = [0.0] * 4 + [k / n for k in range(1, n)] + [1.0] * 4
    ts = sorted(set([0.0, 1.0] + [k / n for k in range(n + 1)] + [(k + f) / n for k in range(n)
                                                                  for f in (0.13, 0.5, 0.91)]))
    for t in ts:
        first, N, dN, d2N = native.cubic_basis(n, t)
        assert first == min(n - 1, int(math.floor(t * n)))
        for a in range(4):
            i = first + a
            assert N[a] == pytest.approx(_cox_de_boor(knots, i, 3, t), abs=1e-13)
            assert dN[a] == pytest.approx(_cox_de_boor(knots, i, 3, t, 1), abs=1e-11 * n)
            assert d2N[a] == pytest.approx(_cox_de_boor(knots, i, 3, t, 2), abs=1e-10 * n * n)
        assert sum(N) == pytest.approx(1.0, abs=1e-14)
        assert abs(sum(dN)) < 1e-12 * n and abs(sum(d2N)) < 1e-11 * n * n
    with pytest.raises(ValueError, match="span"):
        native.cubic_basis(0, 0.5)


def _patch_point(patch, u, v):
    """The patch at (u, v) summed here from native.cubic_basis at u and at v."""
    iu, Nu, _, _ = native.cubic_basis(patch["nu"], u)
    iv, Nv, _, _ = native.cubic_basis(patch["nv"], v)
    control = patch["control"].reshape(patch["nu"] + 3, patch["nv"] + 3, 3)
    return np.einsum("a,b,abk->k", Nu, Nv, control[iu:iu + 4, iv:iv + 4])


@pytest.mark.parametrize("spans,cells", [((1, 1), (3, 2)), ((3, 5), (7, 4)), ((6, 2), (13, 9))])
def test_a_grid_from_the_basis_kept_per_row_and_column_is_the_patch_at_each_node(spans, cells):
    """patch_grid evaluates the basis once per grid row and column (CubicBasis, bspline.h) and
    reuses it at every node and triangle centroid: each node is the patch at its (u, v), and
    max_chord the largest distance between a triangle's flat centroid and the patch at the
    centroid's (u, v), as evaluated point by point."""
    rng = np.random.default_rng(7)
    nu, nv = spans
    patch = {"nu": nu, "nv": nv, "control": rng.normal(size=((nu + 3) * (nv + 3), 3))}
    cu, cv = cells
    g = native.patch_grid(patch, cu, cv)
    assert g["uv"].shape == ((cu + 1) * (cv + 1), 2)
    for (u, v), x in zip(g["uv"], g["points"]):
        assert np.abs(x - _patch_point(patch, u, v)).max() < 1e-12
    at = g["points"].reshape(cu + 1, cv + 1, 3)
    chord = 0.0
    for i in range(cu):
        for j in range(cv):
            for tri in (((i, j), (i + 1, j), (i + 1, j + 1)), ((i, j), (i + 1, j + 1), (i, j + 1))):
                u, v = np.mean([(a / cu, b / cv) for a, b in tri], axis=0)
                flat = np.mean([at[a, b] for a, b in tri], axis=0)
                chord = max(chord, np.linalg.norm(_patch_point(patch, u, v) - flat))
    assert g["max_chord"] == pytest.approx(chord, rel=1e-12, abs=1e-12)
