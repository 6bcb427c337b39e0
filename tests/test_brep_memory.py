"""A B-rep source holds a bounded number of OCCT global-search grids (issue 22, memory: an
assembly of 618 faces, projected from two threads, held 400 MB of them at the refit's
peak). The least recently searched face's analyser goes, and a rebuilt one answers alike:
the foot points of a part with more B-spline faces than the bound are those of a fresh
analyser per face.
Memory itself is measured by `stripweave bench --job`, never asserted here."""
import numpy as np

import FreeCAD  # noqa: F401  (before Part)
import Part
from FreeCAD import Vector

import stripweave as sw
from stripweave._native import native


def bumpy_tiles(count, pitch=12.0):
    """`count` disjoint B-spline faces (10 x 10, height 0.3 sin x cos y, each offset), in one
    compound: as many faces as a B-spline assembly has, each needing its own analyser."""
    faces = []
    for k in range(count):
        ox, oy = pitch * (k % 10), pitch * (k // 10)
        grid = [[Vector(ox + x, oy + y, 0.3 * np.sin(x + k) * np.cos(y)) for y in np.linspace(0, 10, 6)]
                for x in np.linspace(0, 10, 6)]
        s = Part.BSplineSurface()
        s.interpolate(grid)
        faces.append(s.toShape())
    return Part.makeCompound(faces)


def test_a_part_with_more_faces_than_the_bound_projects_alike_with_few_search_grids():
    shape = bumpy_tiles(90)
    surface = sw.from_shape(shape)
    n = len(shape.Faces)
    rng = np.random.default_rng(2)
    centres = np.array([[f.CenterOfMass.x, f.CenterOfMass.y, 1.0] for f in shape.Faces])
    # Which B-rep face is which tile: the source numbers its faces itself.
    order = [int(np.argmin(np.linalg.norm(native.project_to_face(surface, i, centres, -1.0) - centres, axis=1)))
             for i in range(n)]
    # Twice round all faces, a few points each: every analyser is built, dropped and rebuilt.
    faces = [i for _ in range(2) for i in range(n) for _ in range(3)]
    points = centres[[order[i] for i in faces]] + rng.uniform(-4, 4, (len(faces), 3)) * [1, 1, 0.2]
    bounded, held = native.project_to_faces(surface, faces, points, -1.0)
    assert held < n and held <= 64
    fresh = np.array([native.project_to_face(surface, f, p[None, :], -1.0)[0] for f, p in zip(faces, points)])
    assert np.abs(bounded - fresh).max() <= 1e-12 * shape.BoundBox.DiagonalLength
