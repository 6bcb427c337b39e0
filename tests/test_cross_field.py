"""The cross field of a design (paper §6.1): analytic checks in model units.

Crosses are compared modulo quarter turns: `cross_deviation_deg(a, b)` is the
angle between the nearest of a's four directions and b, in [0, 45].
"""
import math

import numpy as np
import pytest

import stripweave as sw
from field_rotation import assert_singularities_are_the_fields_rotation, rotation_indices
from models import box, bumpy_sphere_mesh, capped_cylinder, filleted_box, open_cylinder_shell, sphere, torus
from stripweave._native import native
from stripweave.loops import LoopSession

SIZE = dict(target_triangles=8000)


def loops_through(session, anchors):
    """The best loop through each directional anchor (model units)."""
    return [session.native.loops([list(a)], 1, True)[0] for a in anchors]


def cross_deviation_deg(a, b):
    """Per row: the angle between the cross of unit vectors a and direction b, modulo 90 degrees."""
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    cos = np.abs(np.sum(a * b, axis=-1))
    sin = np.linalg.norm(np.cross(a, b), axis=-1)
    angle = np.degrees(np.arctan2(sin, cos))  # 0..90
    return np.minimum(angle, 90 - angle)


def triangle_normals(surface):
    p = surface.vertices[surface.triangles]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def centroids(surface):
    return surface.vertices[surface.triangles].mean(axis=1)


def indices(field):
    return sorted(s["index"] for s in field["singularities"])


# --- torus with one meridian loop ----------------------------------------------------

@pytest.fixture(scope="module")
def torus_design():
    surface = sw.from_shape(torus(10, 3), **SIZE)
    session = LoopSession(surface)
    loops = loops_through(session, [(13, 0, 0, 0, 0, 1)])
    return surface, session, loops, native.cross_field(session.native, loops)


def test_torus_meridian_field_has_no_singularity(torus_design):
    surface, _, _, field = torus_design
    assert field["singularities"] == []
    assert assert_singularities_are_the_fields_rotation(surface, field["direction"], field["singularities"]) == {}
    assert field["index_sum"] == 0 == field["euler_characteristic"]


def test_torus_field_is_aligned_with_the_loop_in_the_triangles_it_crosses(torus_design):
    _, session, loops, field = torus_design
    seg = native.loop_segments(session.native, loops[0])
    assert len(seg["triangle"]) > 20
    assert np.all(field["constrained"][seg["triangle"]] == 1)
    deviation = cross_deviation_deg(field["direction"][seg["triangle"]], seg["direction"])
    assert deviation.max() < 1.0


def test_torus_field_follows_meridians_and_parallels_everywhere(torus_design):
    surface, _, _, field = torus_design
    c = centroids(surface)
    parallel = np.stack([-c[:, 1], c[:, 0], np.zeros(len(c))], axis=1)
    deviation = cross_deviation_deg(field["direction"], parallel)
    assert deviation.max() < 5.0  # the loop itself is a polyline within ~3.5 degrees of the meridian
    assert deviation.mean() < 1.5


def test_loop_segments_lie_in_their_triangles_and_chain_up(torus_design):
    surface, session, loops, _ = torus_design
    seg = native.loop_segments(session.native, loops[0])
    points = seg["points"]
    assert np.allclose(points[0], points[-1])  # a closed loop returns to its start
    assert np.all(seg["to"][:-1] == seg["from"][1:])  # no gaps (no repeated points on this loop)
    step = points[seg["to"]] - points[seg["from"]]
    assert np.allclose(seg["direction"], step / np.linalg.norm(step, axis=1, keepdims=True))
    # both ends on the closed triangle: barycentric coordinates in [0, 1], off the plane by ~0
    corners = surface.vertices[surface.triangles[seg["triangle"]]]
    for end in (seg["from"], seg["to"]):
        p = points[end]
        a, b = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        n = np.cross(a, b)
        d = p - corners[:, 0]
        area2 = np.sum(n * n, axis=1)
        beta = np.sum(np.cross(d, b) * n, axis=1) / area2
        gamma = np.sum(np.cross(a, d) * n, axis=1) / area2
        assert np.all(np.abs(np.sum(d * n, axis=1)) / np.sqrt(area2) < 1e-9)
        assert np.all((beta > -1e-9) & (gamma > -1e-9) & (beta + gamma < 1 + 1e-9))


def test_field_outputs_are_well_formed(torus_design):
    surface, _, _, field = torus_design
    nt, ne = len(surface.triangles), len(surface.edges)
    assert field["theta"].shape == (nt,) and field["direction"].shape == (nt, 3)
    assert field["strength"].shape == (nt,) and field["constrained"].dtype == np.uint8
    assert field["matching"].shape == (ne,) and field["matching"].dtype == np.int8
    assert np.all((field["theta"] >= 0) & (field["theta"] < math.pi / 2))
    assert np.allclose(np.linalg.norm(field["direction"], axis=1), 1)
    assert np.abs(np.sum(field["direction"] * triangle_normals(surface), axis=1)).max() < 1e-9
    assert np.all((field["matching"] >= 0) & (field["matching"] <= 3))
    assert np.all((field["strength"] >= 0) & (field["strength"] <= 1))
    assert np.all(field["strength"][field["constrained"] == 1] == pytest.approx(1))
    assert field["solve_ms"] > 0


def test_torus_without_loops_follows_the_principal_directions():
    """No constraint at all: the weak curvature prior alone fixes the field."""
    surface = sw.from_shape(torus(10, 3), **SIZE)
    session = LoopSession(surface)
    field = native.cross_field(session.native, [])
    assert field["singularities"] == []
    # The field's own rotation around every vertex: none anywhere.
    assert assert_singularities_are_the_fields_rotation(surface, field["direction"], field["singularities"]) == {}
    assert not field["constrained"].any()
    c = centroids(surface)
    parallel = np.stack([-c[:, 1], c[:, 0], np.zeros(len(c))], axis=1)
    assert cross_deviation_deg(field["direction"], parallel).max() < 3.0


# --- cube with its three belts ------------------------------------------------------

CUBE_BELTS = [(5, 5, 10, 1, 0, 0), (5, 3, 0, 0, 1, 0), (3, 0, 5, 1, 0, 0)]


@pytest.fixture(scope="module")
def cube_design():
    surface = sw.from_shape(box(10), **SIZE)
    session = LoopSession(surface)
    loops = loops_through(session, CUBE_BELTS)
    return surface, session, loops, native.cross_field(session.native, loops)


def test_cube_has_a_quarter_singularity_at_each_corner(cube_design):
    surface, _, _, field = cube_design
    assert indices(field) == [0.25] * 8
    corners = np.array([(x, y, z) for x in (0, 10) for y in (0, 10) for z in (0, 10)], dtype=float)
    # Counted independently, from the field's turns around each vertex: +1/4 exactly at the
    # eight corner vertices (angle defect pi/2, the field aligned with the faces), 0 elsewhere.
    count = assert_singularities_are_the_fields_rotation(surface, field["direction"], field["singularities"])
    at_corner = np.linalg.norm(surface.vertices[:, None, :] - corners[None], axis=2).min(axis=1) < 1e-6
    assert count == {int(v): 1 for v in np.flatnonzero(at_corner)} and at_corner.sum() == 8
    positions = np.array([s["position"] for s in field["singularities"]])
    distance = np.linalg.norm(positions[:, None, :] - corners[None, :, :], axis=2)
    tolerance = 0.01 * surface.bbox_diagonal
    assert np.all(distance.min(axis=1) < tolerance)  # every singularity at a corner ...
    assert np.all(distance.min(axis=0) < tolerance)  # ... and every corner has one


def test_cube_features_alone_align_the_field_with_the_face_axes(cube_design):
    surface, session, _, _ = cube_design
    field = native.cross_field(session.native, [])
    in_plane_axis = np.eye(3)[np.argmin(np.abs(triangle_normals(surface)), axis=1)]
    assert field["constrained"].any() and not field["constrained"].all()
    assert cross_deviation_deg(field["direction"], in_plane_axis).max() < 0.1
    assert indices(field) == [0.25] * 8


def test_cube_belts_alone_give_the_corner_singularities_too(cube_design):
    _, session, loops, _ = cube_design
    field = native.cross_field(session.native, loops, features=False)
    assert indices(field) == [0.25] * 8


def test_cube_field_with_belts_deviates_from_the_face_axes_only_as_much_as_the_belts(cube_design):
    """Loops override features; the embedded belts are polylines within a few degrees of
    straight, and the field follows them there and nowhere deviates more."""
    surface, session, loops, field = cube_design
    in_plane_axis = np.eye(3)[np.argmin(np.abs(triangle_normals(surface)), axis=1)]
    belt_deviation = max(cross_deviation_deg(s["direction"], in_plane_axis[s["triangle"]]).max()
                         for s in (native.loop_segments(session.native, loop) for loop in loops))
    deviation = cross_deviation_deg(field["direction"], in_plane_axis)
    assert deviation.max() < belt_deviation + 0.1
    assert np.median(deviation) < 0.5


def test_cube_belt_crossing_a_feature_keeps_the_loop_direction(cube_design):
    _, session, loops, field = cube_design
    for loop in loops:
        seg = native.loop_segments(session.native, loop)
        assert cross_deviation_deg(field["direction"][seg["triangle"]], seg["direction"]).max() < 1.0


# --- sphere with three great circles ------------------------------------------------

def test_sphere_three_great_circles_give_one_quarter_singularity_per_octant():
    surface = sw.from_shape(sphere(5), **SIZE)
    session = LoopSession(surface)
    loops = loops_through(session, [(5, 0, 0, 0, 1, 0), (0, 5, 0, 0, 0, 1), (0, 0, 5, 1, 0, 0)])
    field = native.cross_field(session.native, loops)
    assert indices(field) == [0.25] * 8
    positions = np.array([s["position"] for s in field["singularities"]])
    assert np.all(np.abs(positions) > 1.0)  # well inside an octant, off the circles
    octants = {tuple(np.sign(p).astype(int)) for p in positions}
    assert len(octants) == 8


def test_sphere_without_loops_takes_the_smoothest_field():
    """Umbilic and unconstrained: no curvature direction to follow; the field is the
    smoothest unit field (Knöppel et al.), which on a sphere has 8 quarter singularities."""
    surface = sw.from_shape(sphere(5), **SIZE)
    field = native.cross_field(LoopSession(surface).native, [])
    assert indices(field) == [0.25] * 8
    assert np.median(field["strength"]) > 0.3


# --- Poincaré-Hopf ---------------------------------------------------------------------

@pytest.mark.parametrize("name, make, anchors, chi", [
    ("torus", lambda: torus(10, 3), [(13, 0, 0, 0, 0, 1)], 0),
    ("cube", lambda: box(10), CUBE_BELTS, 2),
    ("sphere", lambda: sphere(5), [(5, 0, 0, 0, 1, 0)], 2),
    ("capped cylinder", lambda: capped_cylinder(5, 20), [(5, 0, 10, 0, 1, 0)], 2),
    ("open cylinder shell", lambda: open_cylinder_shell(5, 20), [(5, 0, 10, 0, 1, 0)], 0),
    ("open cylinder shell, axial dual curve", lambda: open_cylinder_shell(5, 20), [(5, 0, 10, 0, 0, 1)], 0),
    ("filleted box", lambda: filleted_box(10, 2), [], 2),
])
def test_indices_sum_to_the_euler_characteristic(name, make, anchors, chi):
    surface = sw.from_shape(make(), **SIZE)
    session = LoopSession(surface)
    field = native.cross_field(session.native, loops_through(session, anchors))
    assert field["euler_characteristic"] == chi
    assert sum(s["index"] for s in field["singularities"]) == field["index_sum"] == chi
    # The sum holds by construction of the native index; each index is checked against the
    # field's own rotation around its vertex, and so is every vertex left out of the list.
    count = assert_singularities_are_the_fields_rotation(surface, field["direction"], field["singularities"])
    index, _ = rotation_indices(surface.vertices, surface.triangles, field["direction"])
    assert sum(count.values()) == 4 * chi and index.sum() == pytest.approx(chi, abs=1e-9)


def test_open_cylinder_shell_with_aligned_boundary_needs_no_singularity():
    surface = sw.from_shape(open_cylinder_shell(5, 20), **SIZE)
    field = native.cross_field(LoopSession(surface).native, [])
    assert field["singularities"] == []
    assert field["constrained"].any()  # the two boundary circles


def test_organic_blob_with_two_loops_satisfies_poincare_hopf():
    """A scanned-like blob (smooth bumps, no features): many singularities, their indices
    still sum to the Euler characteristic, and the field follows both loops."""
    vertices, triangles = bumpy_sphere_mesh(5.0)
    surface = sw.from_mesh(vertices, triangles, **SIZE)
    v = surface.vertices
    band = v[np.abs(v[:, 2]) < 0.3]  # around the equator
    back, side = band[np.argmax(band[:, 1])], band[np.argmax(band[:, 0])]
    session = LoopSession(surface)
    loops = loops_through(session, [(*back, 1, 0, 0), (*side, 0, 0, 1)])
    field = native.cross_field(session.native, loops)
    assert field["euler_characteristic"] == 2
    assert field["index_sum"] == 2
    assert sum(s["index"] for s in field["singularities"]) == pytest.approx(2, abs=1e-9)
    assert sum(assert_singularities_are_the_fields_rotation(surface, field["direction"],
                                                            field["singularities"]).values()) == 8
    segments = [native.loop_segments(session.native, loop) for loop in loops]
    # Where the two loops cross, a triangle holds both directions: the field is aligned
    # with each loop everywhere else.
    crossing = set(segments[0]["triangle"]) & set(segments[1]["triangle"])
    for seg in segments:
        alone = np.array([t not in crossing for t in seg["triangle"]])
        assert alone.sum() > 0.9 * len(alone)
        deviation = cross_deviation_deg(field["direction"][seg["triangle"][alone]], seg["direction"][alone])
        assert deviation.max() < 1.0
