"""Lifting drawings off the surface along its normals (pure numpy).

Stripes, loops, markers and the preview all lie on the solver mesh, while
FreeCAD shades the part with its own, coarser tessellation that cuts through
it.  Each layer is therefore drawn a small distance out along the surface
normal (stripes lowest, lines above them), so none hides in the part or in
the layer below.  A point gets the normal of its nearest solver-mesh vertex.
"""

import numpy as np

try:  # fast nearest-vertex search when SciPy is installed (Debian: python3-scipy)
    from scipy.spatial import cKDTree
except ImportError:  # pragma: no cover - brute force below
    cKDTree = None

CHUNK = 256


class NormalLift:
    """``lift(points, distance)`` for a mesh given by vertices and unit normals."""

    def __init__(self, vertices, normals):
        self.vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
        self.normals = np.asarray(normals, dtype=float).reshape(-1, 3)
        self.diagonal = (float(np.linalg.norm(self.vertices.max(axis=0) - self.vertices.min(axis=0)))
                         if len(self.vertices) else 1.0)
        self._tree = cKDTree(self.vertices) if cKDTree is not None and len(self.vertices) else None

    def nearest(self, points):
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        if len(points) == 0 or len(self.vertices) == 0:
            return np.zeros(len(points), dtype=np.int64)
        if self._tree is not None:
            return self._tree.query(points)[1]
        out = np.empty(len(points), dtype=np.int64)
        for s in range(0, len(points), CHUNK):
            block = points[s:s + CHUNK]
            d = ((block[:, None, :] - self.vertices[None, :, :]) ** 2).sum(axis=2)
            out[s:s + CHUNK] = d.argmin(axis=1)
        return out

    def lift(self, points, fraction):
        """``points`` moved out by ``fraction`` of the model's diagonal."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        if len(points) == 0 or len(self.vertices) == 0 or fraction == 0:
            return points
        return points + (fraction * self.diagonal) * self.normals[self.nearest(points)]
