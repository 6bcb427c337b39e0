"""Symmetric primal vertices (paper §5.8, issue 21; native layout/primal_vertex_symmetry.cpp):
regions that are images of each other under the design's symmetries get vertices that are
images of each other, so the layout's vertex set maps to itself and the refit can pair it.

Generated models: the box with two mirrored bosses of test_symmetry.py (plane x = 0), woven
with its symmetry detected: placed region by region, the layout put a primal vertex at a
different base corner of each boss (15% of the diagonal off its image); the ellipsoid of
test_symmetric_fit.py with its principal ellipses and the plane x = 0 given, for pins.
"""
import json

import numpy as np
import pytest

import FreeCAD  # noqa: F401  (before Part, which models imports)

import stripweave as sw
from stripweave.design import Design
from stripweave.strips import DesignSession
from stripweave.symmetry import symmetric_surface

from models import mirrored_box, turned_box
from test_symmetric_fit import MIRROR_X, ellipsoid, principal_ellipses


def reflect(sym, points):
    """The points mirrored in the symmetry's plane (design.md dict, model units), in numpy:
    not the native map the layout used."""
    n = np.asarray(sym["normal"], dtype=float)
    n /= np.linalg.norm(n)
    p = np.asarray(points, dtype=float)
    return p - 2.0 * ((p - np.asarray(sym["point"], dtype=float)) @ n)[:, None] * n


def image_gaps(positions, sym):
    """Per vertex, the distance from its mirror image to the nearest vertex."""
    p = np.asarray(positions, dtype=float)
    q = reflect(sym, p)
    return np.sqrt(((q[:, None, :] - p[None, :, :]) ** 2).sum(axis=2)).min(axis=1)


@pytest.fixture(scope="module")
def woven(tmp_path_factory):
    out = tmp_path_factory.mktemp("symlayout")
    surface = sw.from_shape(mirrored_box(), target_triangles=8000)
    sw.weave(surface, out=str(out), symmetry="auto", max_strips=12, step=True)
    return surface, out, json.loads((out / "report.json").read_text()), json.loads((out / "layout.json").read_text())


def test_every_vertex_has_its_mirror_image(woven):
    _, _, report, layout = woven
    diagonal = report["bbox_diagonal"]
    sym = report["symmetry"][0]
    assert sym["kind"] == "reflection" and report["valid"]
    vertices = layout["vertices"]
    assert len(vertices) >= 4
    gaps = image_gaps([v["position"] for v in vertices], sym)
    assert gaps.max() <= 1e-3 * diagonal, gaps / diagonal
    assert sym["layout_max_error"] <= 1e-3 * diagonal
    # The images say whose image they are, and are exactly that vertex mirrored.
    images = [(i, v["image_of"]) for i, v in enumerate(vertices) if v["image_of"] is not None]
    assert images
    for i, j in images:
        assert vertices[j]["image_of"] is None          # a representative
        mirrored = reflect(sym, [vertices[j]["position"]])[0]
        assert np.linalg.norm(mirrored - vertices[i]["position"]) <= 1e-3 * diagonal
        assert vertices[i]["placement"] == vertices[j]["placement"]   # a corner's image is a corner


def test_the_refit_pairs_the_layout(woven):
    _, _, report, _ = woven
    fit = report["fit"]
    assert fit["symmetric"] is True, fit.get("symmetry_problem")
    assert fit["symmetry_error"] <= 1e-9 * report["bbox_diagonal"]


def rotate(sym, points, k=1):
    """The points turned by k / order of a full turn about the symmetry's axis (numpy)."""
    axis = np.asarray(sym["axis"], dtype=float)
    axis /= np.linalg.norm(axis)
    angle = 2.0 * np.pi * k / sym["order"]
    c, s = np.cos(angle), np.sin(angle)
    p = np.asarray(points, dtype=float) - np.asarray(sym["point"], dtype=float)
    turned = p * c + np.cross(axis, p) * s + np.outer(p @ axis, axis) * (1.0 - c)
    return turned + np.asarray(sym["point"], dtype=float)


def test_a_rotation_maps_the_vertex_set_onto_itself_and_the_refit_pairs_it(tmp_path):
    """Placed region by region the layout was 17% of the diagonal off its half turn. The
    refit pairs the layout under the half turn and writes exactly symmetric nets: paired by
    the symmetry's tolerance alone, the edges (routed over a mesh the half turn does not map
    onto itself) found no image ("layout edge 0 has no image")."""
    surface = sw.from_shape(turned_box(), target_triangles=8000)
    sw.weave(surface, out=str(tmp_path), symmetry="auto", max_strips=12, step=True)
    report = json.loads((tmp_path / "report.json").read_text())
    layout = json.loads((tmp_path / "layout.json").read_text())
    diagonal = report["bbox_diagonal"]
    assert [(s["kind"], s["order"]) for s in report["symmetry"]] == [("rotation", 2)]
    sym = report["symmetry"][0]
    assert report["valid"]
    p = np.array([v["position"] for v in layout["vertices"]], dtype=float)
    assert len(p) >= 4
    q = rotate(sym, p)
    gaps = np.sqrt(((q[:, None, :] - p[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
    assert gaps.max() <= 1e-3 * diagonal, gaps / diagonal
    assert sym["layout_max_error"] <= 1e-3 * diagonal
    assert any(v["image_of"] is not None for v in layout["vertices"])
    fit = report["fit"]
    assert fit["symmetric"] is True, fit.get("symmetry_problem")
    assert fit["symmetry_error"] <= 1e-9 * diagonal
    assert fit["valid_shell"]


@pytest.fixture(scope="module")
def octants():
    """The ellipsoid's principal ellipses (test_symmetric_fit.py) with the plane x = 0 given:
    eight octant regions, each the mirror image of another, their vertices at centres."""
    surface = symmetric_surface(sw.from_shape(ellipsoid(), target_triangles=8000), [MIRROR_X])
    design = principal_ellipses()
    design.symmetry = [MIRROR_X]
    return DesignSession(surface, design)


def test_a_pin_wins_and_its_image_gets_the_pin_mirrored(octants):
    ds = octants
    diagonal = ds.surface.bbox_diagonal
    vertices = ds.native.layout()["vertices"]
    assert len(vertices) == 8
    assert image_gaps([v["position"] for v in vertices], MIRROR_X).max() <= 1e-3 * diagonal
    # Pin the vertex of the octant x, y, z > 0 towards x: wherever it moves, its image follows.
    pinned = next(i for i, v in enumerate(vertices) if min(v["position"]) > 0)
    pin = np.asarray(vertices[pinned]["position"]) + [3.0, 0.0, 0.0]
    ds.design.pins = [pin.tolist()]
    ds.apply_layout_inputs()
    try:
        after = ds.native.layout()["vertices"]
    finally:
        ds.design.pins = []
        ds.apply_layout_inputs()
    moved = np.asarray(after[pinned]["position"])
    assert after[pinned]["placement"] == "pinned" and after[pinned]["image_of"] is None
    assert np.linalg.norm(moved - vertices[pinned]["position"]) > 1.0     # the pin moved it
    image = next(i for i, v in enumerate(after) if v["image_of"] == pinned)
    assert after[image]["placement"] == "pinned"                           # the mapped pin
    assert np.linalg.norm(reflect(MIRROR_X, [moved])[0] - after[image]["position"]) <= 1e-3 * diagonal
    assert image_gaps([v["position"] for v in after], MIRROR_X).max() <= 1e-3 * diagonal


def test_without_symmetries_a_pin_moves_its_vertex_alone(octants):
    ds = octants
    vertices = ds.native.layout()["vertices"]
    pinned = next(i for i, v in enumerate(vertices) if min(v["position"]) > 0)
    ds.design.pins = [(np.asarray(vertices[pinned]["position"]) + [3.0, 0.0, 0.0]).tolist()]
    ds.native.vertex_pins = ds.design.pins
    ds.native.layout_symmetries = []
    try:
        after = ds.native.layout()["vertices"]
    finally:
        ds.design.pins = []
        ds.apply_layout_inputs()
    assert all(v["image_of"] is None for v in after)
    assert image_gaps([v["position"] for v in after], MIRROR_X).max() > 1e-2 * ds.surface.bbox_diagonal
