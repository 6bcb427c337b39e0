"""What the design tool's panel lists about a design's layout (paper §4.2,
§7): its regions by colour, each with where it is, and the layout's defects.

Input: a DesignSession (on the design tool's worker thread, under the
SessionCache lock).  Output (:func:`compute`) a JSON-safe dict::

    {"valid": bool, "clean": bool,
     "counts": {"red": n, "crease": n, "orange": n, "yellow": n, "none": n},
     "regions": [{"colour", "position": [x, y, z], "text"}],   # the coloured ones
     "defects": ["patch 3: patch without 4 corners at (..)", ...]}   # when valid

A region's position is a point on it: of its triangles' centroids the
one nearest their mean (the mean itself may lie off the region, e.g. of
a ring).  No document access and no Qt here.
"""

import numpy as np

COLOURS = ("red", "crease", "orange", "yellow")   # worst first; "none" regions are fine
WHY = {"red": "not a disc: add strips that split it",
       "crease": "a crease runs through it",
       "orange": "several curvature extrema: more strips there would help",
       "yellow": "valence off its curvature's ideal by more than 1"}


def region_positions(raw, surface):
    """Per region of the native layout dict a point on it (model units), or
    None: of the surface triangles its refined triangles come from, the
    centroid nearest their mean."""
    vertices = np.asarray(surface.vertices, dtype=float).reshape(-1, 3)
    triangles = np.asarray(surface.triangles, dtype=np.int64).reshape(-1, 3)
    parent = np.asarray(raw["parent_triangle"], dtype=np.int64)
    region = np.asarray(raw["triangle_region"], dtype=np.int64)
    centroids = vertices[triangles[parent]].mean(axis=1) if len(parent) else np.zeros((0, 3))
    out = []
    for r in range(len(raw["regions"])):
        mine = centroids[region == r]
        if not len(mine):
            out.append(None)
            continue
        mean = mine.mean(axis=0)
        out.append([float(c) for c in mine[int(np.argmin(np.linalg.norm(mine - mean, axis=1)))]])
    return out


def _point(p):
    return "(" + ", ".join("{:.4g}".format(c) for c in p) + ")" if p is not None else "(?)"


def compute(ds):
    from stripweave.layout import layout_json
    from .layout_model import defect_lines, region_counts
    raw = ds.native.layout(True)
    layout = layout_json(raw)
    counts = {c: 0 for c in COLOURS + ("none",)}
    counts.update(region_counts(layout))
    regions = []
    for r, position in zip(layout["regions"], region_positions(raw, ds.surface)):
        if r["colour"] in COLOURS:
            why = r.get("crease_problem") if r["colour"] == "crease" and r.get("crease_problem") else WHY[r["colour"]]
            regions.append({"colour": r["colour"], "position": position,
                            "text": "{} at {}: valence {}, {}".format(r["colour"], _point(position),
                                                                       r.get("valence"), why)})
    regions.sort(key=lambda x: COLOURS.index(x["colour"]))
    return {"valid": layout["valid"], "clean": layout["clean"], "counts": counts, "regions": regions,
            # an invalid layout has no patches: its "defects" would only say so
            "defects": defect_lines(layout) if layout["valid"] else []}
