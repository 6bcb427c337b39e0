"""An independent count of a cross field's singularities, in numpy, from the mesh geometry.

rotation_indices(vertices, triangles, direction) -> (index (V,), margin)
  Input : a triangle mesh (consistently oriented) and one unit tangent direction of the
          cross field per triangle (T, 3).
  Method: walk counter-clockwise around each vertex v through its triangles. In each
          triangle the cross's angle is measured against the edges at v (atan2 about the
          triangle's normal). Crossing the edge (v, b) from one triangle into the next, the
          discrete Levi-Civita transport keeps the angle to that edge, so the field's turn
          there is the difference of the two angles to (v, b), taken modulo a quarter turn
          into [-pi/4, pi/4]. The index of v is (A(v) + sum of the turns) / 2 pi, A(v) the
          angle defect (2 pi - angle sum inside, pi - angle sum on the boundary).
          Nothing is taken from the native field but its per-triangle directions: not its
          frames, connection, matchings nor singularity list.
  Output: index[v] (real: a multiple of 1/4 inside, up to rounding), and margin: the
          largest |turn| met, below pi/4 when every quarter-turn choice is unambiguous.
"""
import math

import numpy as np

QUARTER = math.pi / 2


def _angle(edge, direction, normal):
    """Counter-clockwise angle about normal from edge to direction, per row."""
    return np.arctan2(np.sum(np.cross(edge, direction) * normal, axis=1), np.sum(edge * direction, axis=1))


def rotation_indices(vertices, triangles, direction):
    vertices, triangles, direction = np.asarray(vertices, float), np.asarray(triangles), np.asarray(direction, float)
    p = vertices[triangles]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    nv = len(vertices)
    angle_sum = np.zeros(nv)
    turn = np.zeros(nv)
    # Corner k of triangle t: v = t[k], the walk around v enters t over (v, a) and leaves it over (v, b).
    entering = {}  # directed edge (v, a) -> the angle of the field to it in the triangle it enters
    leaving = []
    for k in range(3):
        v, a, b = triangles[:, k], triangles[:, (k + 1) % 3], triangles[:, (k + 2) % 3]
        to_a, to_b = vertices[a] - vertices[v], vertices[b] - vertices[v]
        cos = np.sum(to_a * to_b, axis=1) / (np.linalg.norm(to_a, axis=1) * np.linalg.norm(to_b, axis=1))
        np.add.at(angle_sum, v, np.arccos(np.clip(cos, -1, 1)))
        for vi, ai, alpha in zip(v.tolist(), a.tolist(), _angle(to_a, direction, normal).tolist()):
            entering[(vi, ai)] = alpha
        leaving.append((v, b, _angle(to_b, direction, normal)))
    boundary = np.zeros(nv, bool)
    margin = 0.0
    for v, b, alpha_out in leaving:
        for vi, bi, out in zip(v.tolist(), b.tolist(), alpha_out.tolist()):
            into = entering.get((vi, bi))
            if into is None:  # (v, b) is a boundary edge: the walk around v ends here
                boundary[vi] = True
                continue
            d = (into - out + QUARTER / 2) % QUARTER - QUARTER / 2
            margin = max(margin, abs(d))
            turn[vi] += d
    defect = np.where(boundary, math.pi, 2 * math.pi) - angle_sum
    return (defect + turn) / (2 * math.pi), margin


def singular_quarters(vertices, triangles, direction):
    """{vertex: quarter index} of the vertices whose independent index is non-zero, and the margin."""
    index, margin = rotation_indices(vertices, triangles, direction)
    quarters = np.rint(4 * index).astype(int)
    return {int(v): int(quarters[v]) for v in np.flatnonzero(quarters)}, margin


def assert_singularities_are_the_fields_rotation(surface, direction, singularities):
    """The native singularity list is exactly the vertices of non-zero independent index, with
    those indices, at those vertices' positions (model units). Returns {vertex: quarter index}."""
    count, margin = singular_quarters(surface.vertices, surface.triangles, direction)
    assert margin < math.pi / 4 - 1e-9  # every quarter-turn choice unambiguous
    assert {s["vertex"]: 4 * s["index"] for s in singularities} == count
    for s in singularities:
        assert np.allclose(s["position"], surface.vertices[s["vertex"]], atol=1e-9 * surface.bbox_diagonal)
    return count
