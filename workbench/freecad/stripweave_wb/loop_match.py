"""Whether two loops are the same loop on the surface.

Input: two polylines as dense (n, 3) point arrays in model units (a loop
embedded in the solver mesh has a point per mesh edge it crosses).  Output:
``loop_gap`` is their symmetric distance: the farthest any point of one lies
from the nearest point of the other (0 for the same loop, whatever point a
closed loop starts at; about a mesh edge or more for a neighbouring loop).
No Qt, no document: used on the design tool's worker thread.
"""

import numpy as np

# A loop the design derives again is the same chain of graph nodes, so it
# lies within rounding of the one shown; a neighbouring loop differs by at
# least a fraction of a mesh edge (about diag / 150 at 30K triangles).  A
# thousandth of the diagonal separates the two at every mesh density used.
SAME_LOOP_FRACTION = 1e-3

_CHUNK = 2048


def _farthest_nearest(a, b):
    """max over points of a of the distance to the nearest point of b."""
    worst = 0.0
    for start in range(0, len(a), _CHUNK):
        block = a[start:start + _CHUNK]
        d2 = ((block[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)
        worst = max(worst, float(np.sqrt(d2.min(axis=1).max())))
    return worst


def loop_gap(a, b):
    """Symmetric distance between polylines ``a`` and ``b`` (inf if one is empty)."""
    a = np.asarray(a, dtype=float).reshape(-1, 3)
    b = np.asarray(b, dtype=float).reshape(-1, 3)
    if not len(a) or not len(b):
        return float("inf")
    return max(_farthest_nearest(a, b), _farthest_nearest(b, a))


def same_loop_tolerance(vertices):
    """The largest gap between two polylines that are the same loop on a
    surface with these vertices."""
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    return SAME_LOOP_FRACTION * float(np.linalg.norm(np.ptp(v, axis=0))) if len(v) else 0.0
