"""The refit's shortcuts change no answer (issue 19, item 5): the warm-started projection
onto a B-rep face (occt/brep_source.h: a local Newton from the previous foot point, kept
within the surface's bounds) finds the foot points the global search finds, by a face
border too; and a split round that does not help is undone, the fit left exactly as it was
before the round (the samples the round's trial refit shared with it, sample_memo.h,
change nothing). Speed itself is measured by `stripweave bench`, never asserted here."""
import numpy as np

import stripweave as sw
from stripweave._native import native

import models
import test_split_strip


def serpentine(xs, ys, z):
    """Grid points row by row, every other row backwards: consecutive points are neighbours
    (the order the refit samples a patch in)."""
    rows = [[(x, y, z(x, y)) for x in (xs if i % 2 == 0 else xs[::-1])] for i, y in enumerate(ys)]
    return np.array([p for row in rows for p in row], float)


def test_warm_projection_finds_the_global_foot_points():
    """A lofted B-spline face (x in [0, 20], y in [0, 16], z within 3 of 0): points above and
    below it, and past its borders (x and y up to 3 beyond), where the foot point is on the
    surface's border: warm and cold answers agree within 1e-9 of the size."""
    shape = models.lofted_face()
    surface = sw.from_shape(shape)
    diag = shape.BoundBox.DiagonalLength
    for z in (lambda x, y: 0.4 * np.sin(x), lambda x, y: -1.5 + 0.1 * y, lambda x, y: 2.0):
        points = serpentine(np.linspace(-3, 23, 53), np.linspace(-3, 19, 45), z)
        cold = native.project_to_face(surface, 0, points, 0.0)
        warm = native.project_to_face(surface, 0, points, 5e-3 * diag)
        assert np.abs(warm - cold).max() <= 1e-9 * diag
        # Past the borders the foot point lies on the border (not on the continuation).
        bb = shape.Faces[0].BoundBox
        assert cold[:, 0].min() >= bb.XMin - 1e-6 and cold[:, 0].max() <= bb.XMax + 1e-6


def test_a_split_round_that_does_not_help_is_undone():
    """The bumpy box of test_split_strip at one span per patch: the first round's split
    halves the bump's patch and helps; the second round's cannot bring a one-span piece
    nearer to half a bump, and is undone: reported in rejected_splits, and the fit is the
    one after the first round, figure for figure."""
    surface, net = test_split_strip.part()
    r = native.refit(surface, net, max_spans=1, return_network=True)
    one = native.refit(surface, net, max_spans=1, split_rounds=1, return_network=True)
    assert [s["round"] for s in r["splits"]] == [1] and one["rejected_splits"] == []
    assert r["rejected_splits"] and all(s["round"] == 2 for s in r["rejected_splits"])
    for s in r["rejected_splits"]:
        assert s["deviation_before"] > r["tolerance"] and s["reason"].startswith("accuracy")
    assert [s["strip"] for s in r["splits"]] == [s["strip"] for s in one["splits"]]
    assert len(r["network"]["patches"]) == len(one["network"]["patches"]) == len(r["per_patch"])
    for key in ("max_deviation", "fit_max_deviation", "max_deviation_patch_to_source", "nu", "nv"):
        assert [p[key] for p in r["per_patch"]] == [p[key] for p in one["per_patch"]], key
    assert r["max_deviation"] == one["max_deviation"] and r["coverage"] == one["coverage"]
