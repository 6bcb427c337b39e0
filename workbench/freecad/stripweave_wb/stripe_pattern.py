"""Colours of the strip visualization (paper §4.2, §6): pure numpy, no Coin.

A dual strip is shown as "a pattern of quasi-parallel loops": a regular
sampling of its continuum of u-isocurves.  Per solver-mesh vertex, each strip
contributes a periodic function of its ``across`` coordinate (signed distance
from the strip's loop; the loop itself is a stripe crest), tinted in the
strip's hue and blended over a neutral base.  Where two strips cross, both
patterns show: a grid, the doubly covered region the layout wants.
"""

import colorsys
import math

import numpy as np

BASE_COLOR = (0.80, 0.80, 0.80)       # FreeCAD's default shape grey
POSITIVE_COLOR = (0.10, 0.35, 1.00)   # singularity index +1/4 (valence 3 region corner)
NEGATIVE_COLOR = (0.95, 0.10, 0.10)   # index -1/4 (valence 5)
OTHER_COLOR = (0.10, 0.75, 0.20)      # any other index
PREVIEW_COLOR = (1.00, 0.90, 0.00)    # the proposed loop under the cursor

GOLDEN = 0.6180339887498949
STRIPES_PER_PERIOD_EDGES = 7.0        # a stripe period spans ~7 mesh edges: smooth per-vertex colours
COVERAGE_TINT = 0.12                  # weight of a strip between its stripes (shows what it covers)


def strip_hue(i):
    """Distinct, reproducible hue of strip ``i`` (golden-ratio sequence)."""
    return (0.58 + i * GOLDEN) % 1.0


def strip_color(i, value=0.92, saturation=0.85):
    return colorsys.hsv_to_rgb(strip_hue(i), saturation, value)


def loop_color(i):
    """The loop (spine) in a darker shade of its strip's hue."""
    return strip_color(i, value=0.55, saturation=0.95)


def singularity_color(index):
    if abs(index - 0.25) < 1e-6:
        return POSITIVE_COLOR
    if abs(index + 0.25) < 1e-6:
        return NEGATIVE_COLOR
    return OTHER_COLOR


def mean_edge_length(vertices, triangles):
    if len(triangles) == 0:
        return 0.0
    v = vertices[triangles]
    return float(np.mean(np.linalg.norm(v[:, [1, 2, 0]] - v, axis=2)))


def auto_period(vertices, triangles):
    """Stripe period (model units) that the per-vertex colours resolve well."""
    return max(STRIPES_PER_PERIOD_EDGES * mean_edge_length(vertices, triangles), 1e-9)


def stripe_colors(vertex_count, across_list, period, strength=0.85, base=BASE_COLOR):
    """Per-vertex RGB ((n,3) float) and the mask of vertices in any strip.

    ``across_list``: per strip the (n,) ``across`` array (NaN outside).  A
    strip's weight at a covered vertex is a faint coverage tint plus a
    stripe ``((1 + cos(2 pi across / period)) / 2)^3`` (crests narrower than
    troughs: lines rather than waves).  The strips' hues are summed by
    weight, not layered, so no strip hides another and crossings show both.
    """
    n = vertex_count
    total = np.zeros(n)
    mixed = np.zeros((n, 3))
    covered = np.zeros(n, dtype=bool)
    for i, across in enumerate(across_list):
        across = np.asarray(across, dtype=float)
        inside = np.isfinite(across)
        if not inside.any():
            continue
        wave = 0.5 + 0.5 * np.cos(2.0 * math.pi * across[inside] / period)
        w = strength * (COVERAGE_TINT + (1.0 - COVERAGE_TINT) * wave ** 3)
        total[inside] += w
        mixed[inside] += w[:, None] * np.asarray(strip_color(i))
        covered |= inside
    over = total > 1.0
    mixed[over] /= total[over, None]
    total = np.minimum(total, 1.0)
    colors = (1.0 - total)[:, None] * np.asarray(base, dtype=float) + mixed
    return colors, covered


def covered_triangles(triangles, covered):
    """The triangles with at least one covered vertex."""
    if len(triangles) == 0:
        return triangles
    return triangles[covered[triangles].any(axis=1)]
