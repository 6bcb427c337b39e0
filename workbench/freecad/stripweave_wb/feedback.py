"""Warnings about a derived design that is not an error but is likely not
what the user wants (issue 20 item 4): an empty strip, a sliver strip, and
fold-overs that the last change added.  Pure Python (no FreeCAD, no Qt).

    warnings = strip_warnings(summary, total_area, mean_edge, previous_fold_overs)

``summary`` is the Design's Summary dict (design_session.Derived.summary):
per strip ``length`` and ``area_fraction``; ``fold_overs``.  Lengths in
model units, ``total_area`` the solver mesh's area, ``mean_edge`` its mean
edge length.  Returns one line per warning, the strip numbered from 1.
"""

# A strip whose mean width (its area over its loop's length) is below this
# many solver edges has no mesh vertex inside it across its width: the
# parameterization cannot resolve it, and it shows as a line, not a band.
SLIVER_EDGES = 2.0


def strip_warnings(summary, total_area, mean_edge, previous_fold_overs=None):
    out = []
    for i, s in enumerate(summary.get("strips", [])):
        fraction = float(s.get("area_fraction", 0.0))
        length = float(s.get("length", 0.0))
        if fraction <= 0.0:
            out.append("strip {} is empty (0% of the area): the strips around it leave it no room; "
                       "remove it or move its anchors".format(i + 1))
            continue
        width = fraction * total_area / length if length > 0 else 0.0
        if width < SLIVER_EDGES * mean_edge:
            out.append("strip {} is a sliver: {:.3g} wide on average ({:.2f}% of the area), under {:g} "
                       "solver edges ({:.3g}); it will give thin patches".format(
                           i + 1, width, 100 * fraction, SLIVER_EDGES, SLIVER_EDGES * mean_edge))
    folds = int(summary.get("fold_overs", 0))
    if previous_fold_overs is not None and folds > int(previous_fold_overs):
        out.append("fold-overs rose from {} to {}: the parameterization folds over there (the last change "
                   "crowds singularities or strips)".format(int(previous_fold_overs), folds))
    return out


def mesh_scale(vertices, triangles):
    """(total area, mean edge length) of a triangle mesh (numpy arrays)."""
    import numpy as np
    v = np.asarray(vertices, dtype=float)
    t = np.asarray(triangles, dtype=np.int64)
    if not len(t):
        return 0.0, 0.0
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()
    edges = np.concatenate([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                            np.linalg.norm(a - c, axis=1)])
    return float(area), float(edges.mean())
