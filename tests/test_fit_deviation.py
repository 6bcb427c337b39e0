"""The fit's deviation is two-sided and its coverage is reported (issue 16, item 2):
dense samples of the source against every fitted patch and of every patch against the
source (native surfacing/fit_deviation.h), on generated models with known answers."""
import math

import numpy as np
import pytest

import models
import stripweave as sw
from stripweave._native import native
from test_surfacing import CUBE_FACES, box_face_index, cube_network


def plane_patch(corner, a, b):
    """The square corner + s a + t b (s, t in [0, 1]) as a one-span bicubic: a uniform
    4 x 4 control grid (a Bezier patch with linear precision)."""
    corner, a, b = (np.asarray(x, dtype=float) for x in (corner, a, b))
    control = [corner + (i / 3) * a + (j / 3) * b for i in range(4) for j in range(4)]
    return {"nu": 1, "nv": 1, "control": np.array(control)}


def box_face_patches(size):
    """The 6 faces of the box [0, size]^3 as exact planar patches, with their outward normals."""
    patches, normals = [], []
    for centre, a, b in CUBE_FACES:
        c, a, b = (np.array(x, dtype=float) for x in (centre, a, b))
        h = size / 2
        patches.append(plane_patch(h + h * (c - a - b), 2 * h * a, 2 * h * b))
        normals.append(c)
    return patches, normals


def test_exact_patches_meet_the_tolerance():
    """The box's own faces as patches: both directions zero (up to rounding), the whole
    part covered."""
    size = 10.0
    surf = sw.from_shape(models.box(size))
    patches, _ = box_face_patches(size)
    r = native.fit_deviation(surf, patches, 1e-3 * size * math.sqrt(3))
    assert r["max_deviation_source_to_patches"] < 1e-9 and r["max_deviation_patches_to_source"] < 1e-9
    assert r["coverage"] == pytest.approx(1.0) and r["uncovered_area"] < 1e-9
    assert r["source_area"] == pytest.approx(6 * size ** 2, rel=1e-6)
    assert np.all(r["triangle_uncovered"] == 0)
    assert len(r["triangle_uncovered"]) == len(surf.triangles)


@pytest.mark.parametrize("d", [0.05, 0.4])
def test_offset_patch_reports_the_offset_both_ways(d):
    """One face's patch moved out by d along its normal: the source under it is d from
    the network, and the patch is d from the source, in both directions and on that
    patch only; the RMS of the moved patch against the source is d too."""
    size = 10.0
    surf = sw.from_shape(models.box(size))
    patches, normals = box_face_patches(size)
    moved = 1
    patches[moved]["control"] = patches[moved]["control"] + d * normals[moved]
    tol = 1e-3 * size * math.sqrt(3)
    r = native.fit_deviation(surf, patches, tol)
    assert r["max_deviation_source_to_patches"] == pytest.approx(d, rel=1e-3)
    assert r["max_deviation_patches_to_source"] == pytest.approx(d, rel=1e-3)
    assert r["max_deviation"] == pytest.approx(d, rel=1e-3)
    p = r["per_patch"][moved]
    assert p["max_deviation_patch_to_source"] == pytest.approx(d, rel=1e-3)
    assert p["rms_deviation_patch_to_source"] == pytest.approx(d, rel=1e-3)
    assert p["max_deviation_source_to_patch"] == pytest.approx(d, rel=1e-3)
    others = [q for i, q in enumerate(r["per_patch"]) if i != moved]
    assert all(q["max_deviation_patch_to_source"] < 1e-9 for q in others)
    # The moved face's source lies off every patch but for a band along its border
    # (within the tolerance of the neighbours' edges): uncovered, the rest covered.
    assert r["uncovered_area"] == pytest.approx(size ** 2, rel=0.02 + 4 * tol / size)


def test_fitted_sphere_offset_by_d():
    """Curved: the cube sphere fitted to a sphere of radius R, then measured against a
    sphere of radius R + d: both directions report d, within the fit's own deviation."""
    R, d = 5.0, 0.3
    net = cube_network(lambda p: R * p / np.linalg.norm(p), grid=10, sharp=False)
    fit = native.refit(sw.from_shape(models.sphere(R)), net, return_patches=True)
    own = fit["max_deviation"]
    assert own <= fit["tolerance"]
    r = native.fit_deviation(sw.from_shape(models.sphere(R + d)), fit["patches"], fit["tolerance"])
    for key in ("max_deviation_source_to_patches", "max_deviation_patches_to_source"):
        assert abs(r[key] - d) <= own + 1e-3 * d
    # Every patch is about d off: both directions, on every patch.
    for p in r["per_patch"]:
        assert abs(p["max_deviation_patch_to_source"] - d) <= own + 1e-3 * d
        assert abs(p["rms_deviation_patch_to_source"] - d) <= own + 1e-3 * d
    assert r["coverage"] < 1e-3  # d is far beyond the tolerance everywhere


def test_left_out_patch_coverage():
    """The box's 6 face patches fitted with one left out: coverage 5/6 within 1 %, the
    uncovered area the missing face's within 1 %, and the tolerance not met, though the
    5 fitted patches lie exactly on the box."""
    size = 10.0
    shape = models.box(size)
    net = cube_network(lambda p: size / 2 * (1 + p), grid=6, sharp=True, face_of=box_face_index(shape))
    net["patches"].pop(2)
    r = native.refit(sw.from_shape(shape), net)
    assert r["max_deviation_patches_to_source"] < 1e-6 * size
    assert r["coverage"] == pytest.approx(5 / 6, rel=0.01)
    assert r["uncovered_area"] == pytest.approx(size ** 2, rel=0.01)
    assert r["source_area"] == pytest.approx(6 * size ** 2, rel=1e-6)
    assert r["max_deviation_source_to_patches"] > size / 3  # the missing face's centre
    assert not r["tolerance_met"]
    # Per solver triangle: the missing face's triangles are uncovered, the others not.
    u = r["triangle_uncovered"]
    assert np.mean(u > 0.5) == pytest.approx(1 / 6, abs=0.02)
    assert np.mean(u == 0) > 0.8


def test_result_does_not_depend_on_the_thread_count():
    import os
    size = 10.0
    surf = sw.from_shape(models.box(size))
    patches, normals = box_face_patches(size)
    patches[0]["control"] = patches[0]["control"] + 0.1 * normals[0]
    cores = os.sched_getaffinity(0)
    try:
        os.sched_setaffinity(0, {min(cores)})
        one = native.fit_deviation(surf, patches, 0.01)
    finally:
        os.sched_setaffinity(0, cores)
    two = native.fit_deviation(surf, patches, 0.01)
    for key in ("max_deviation_source_to_patches", "max_deviation_patches_to_source", "rms_deviation_source_to_patches",
                "rms_deviation_patches_to_source", "coverage", "uncovered_area"):
        assert one[key] == two[key]
    assert np.array_equal(one["triangle_uncovered"], two["triangle_uncovered"])


def test_bad_patches():
    surf = sw.from_shape(models.box(10.0))
    patches, _ = box_face_patches(10.0)
    with pytest.raises(sw.InputError):
        native.fit_deviation(surf, [], 0.01)
    with pytest.raises(sw.InputError):
        native.fit_deviation(surf, [dict(patches[0], nu=2)], 0.01)
    with pytest.raises(sw.InputError):
        native.fit_deviation(surf, patches, -1.0)


def rippled_patch(corner, a, b, normal, spans, amplitude):
    """The square corner + s a + t b as a bicubic of spans x spans, its inner control
    points pushed alternately +-amplitude along the normal: a patch that ripples at the
    span scale, as a fit far off its source does."""
    corner, a, b, normal = (np.asarray(x, dtype=float) for x in (corner, a, b, normal))
    n = spans + 3
    control = []
    for i in range(n):
        for j in range(n):
            inner = 0 < i < n - 1 and 0 < j < n - 1
            control.append(corner + (i / (n - 1)) * a + (j / (n - 1)) * b
                           + (amplitude * (-1) ** (i + j) if inner else 0.0) * normal)
    return {"nu": spans, "nv": spans, "control": np.array(control)}


def test_the_default_cap_keeps_the_patch_tessellation_within_the_jobs_memory():
    """Twelve rippling patches, each asking for the densest grid (200 x 200 cells, 80K
    triangles): uncapped, near a million triangles; under the default cap at most 600K, the
    tessellation and its tree about 63 MB, what the main job's 400 MB on a 30K-triangle part
    leaves them (issue 22; at the old 1.2M cap an assembly's job peaked at 437 MB)."""
    size = 10.0
    surf = sw.from_shape(models.box(size))
    h = size / 2
    patches = []
    for centre, a, b in CUBE_FACES:
        c, a, b = (np.array(x, dtype=float) for x in (centre, a, b))
        for half in (0.0, 0.5):    # two overlapping rippled patches per face
            patches.append(rippled_patch(h + h * (c - a - b) + half * h * a, 1.5 * h * a, 2 * h * b, c, 12, 0.3))
    tol = 1e-3 * size * math.sqrt(3)
    wide = native.fit_deviation(surf, patches, tol, max_patch_triangles=4_000_000)
    assert wide["patch_triangles"] > 800_000
    default = native.fit_deviation(surf, patches, tol)
    assert 400_000 < default["patch_triangles"] <= 600_000
    assert default["measurement_error"] >= wide["measurement_error"]
    assert abs(default["max_deviation"] - wide["max_deviation"]) <= default["measurement_error"]


def test_patch_tessellation_is_capped_and_its_error_reported():
    """A rippling patch would need the densest grid (200 x 200 cells) for its chord of
    tolerance / 10; under max_patch_triangles the tessellation stays within the cap, the
    coarsening falls on the rippling patch (the exact planar ones still measure zero),
    measurement_error grows with the chord it then has, and no figure drops below the
    uncapped one by more than that bound (every distance is to a point of a patch)."""
    size = 10.0
    surf = sw.from_shape(models.box(size))
    patches, normals = box_face_patches(size)
    c, a, b = (np.array(x, dtype=float) for x in CUBE_FACES[0])
    h = size / 2
    patches[0] = rippled_patch(h + h * (c - a - b), 2 * h * a, 2 * h * b, normals[0], 12, 0.3)
    tol = 1e-3 * size * math.sqrt(3)
    free = native.fit_deviation(surf, patches, tol)
    cap = 5000
    capped = native.fit_deviation(surf, patches, tol, max_patch_triangles=cap)
    assert free["patch_triangles"] > 10 * cap  # the cap binds
    assert capped["patch_triangles"] <= cap
    assert capped["patch_chord"] > free["patch_chord"]
    assert capped["measurement_error"] >= 3 * capped["patch_chord"] - 1e-12
    assert capped["measurement_error"] > free["measurement_error"]
    for i in range(1, 6):
        assert capped["per_patch"][i]["max_deviation"] < 1e-9
    for key in ("max_deviation_source_to_patches", "max_deviation_patches_to_source"):
        assert capped[key] >= free[key] - free["measurement_error"]
        assert capped[key] <= free[key] + capped["measurement_error"]
    assert capped["max_deviation"] > 0.05  # the ripple is seen
