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
        cold = native.project_to_face(surface, 0, points, -1.0)     # the global search alone
        warm = native.project_to_face(surface, 0, points, 5e-3 * diag)
        assert np.abs(warm - cold).max() <= 1e-9 * diag
        # Past the borders the foot point lies on the border (not on the continuation).
        bb = shape.Faces[0].BoundBox
        assert cold[:, 0].min() >= bb.XMin - 1e-6 and cold[:, 0].max() <= bb.XMax + 1e-6


def test_cold_projection_starts_in_the_nearest_basin():
    """Without a warm start (near 0: the deviation's second look) a foot point is searched
    from the face's start-grid sample nearest the point, and OCCT's global search (near < 0)
    is the fallback. On a lofted face the answers are the global ones. On a thread's helical
    face (6 turns, grooves 0.7 wide) a start grid of 16 x 16 put 477 of 3,000 points near
    the surface in another turn's basin, up to 3.7 farther than the global answer; with the
    grid following the normals' turn and the face's size, the rare point that lies almost
    equally near two walls of a groove can land on the other wall (4 of 3,000, at most 0.02
    farther on a 0.9 tube), never nearer than the surface allows."""
    shape = models.lofted_face()
    surface = sw.from_shape(shape)
    diag = shape.BoundBox.DiagonalLength
    points = serpentine(np.linspace(-3, 23, 53), np.linspace(-3, 19, 45), lambda x, y: 0.4 * np.sin(x) + 1.0)
    cold, reference = native.project_to_face(surface, 0, points, 0.0), native.project_to_face(surface, 0, points, -1.0)
    # The same foot points (the global search settles to 1e-9 in distance, its position along
    # the surface to about 1e-7), past the borders too; where they differ the start grid's
    # is a nearer point of the surface (a corner the global search's grid missed).
    d_cold, d_reference = np.linalg.norm(cold - points, axis=1), np.linalg.norm(reference - points, axis=1)
    assert np.all(d_cold <= d_reference + 1e-9 * diag)
    assert (np.abs(cold - reference).max(axis=1) <= 1e-6 * diag).mean() >= 0.99

    thread = models.helical_tube()
    surface = sw.from_shape(thread)
    face = max(range(len(thread.Faces)), key=lambda i: thread.Faces[i].Area)
    f = thread.Faces[face]
    u0, u1, v0, v1 = f.ParameterRange
    rng = np.random.default_rng(1)
    points = []
    for _ in range(3000):
        u, v = rng.uniform(u0, u1), rng.uniform(v0, v1)
        p = f.valueAt(u, v) + f.normalAt(u, v) * rng.uniform(-0.8, 0.8)
        points.append((p.x, p.y, p.z))
    points = np.array(points)
    cold = np.linalg.norm(native.project_to_face(surface, face, points, 0.0) - points, axis=1)
    reference = np.linalg.norm(native.project_to_face(surface, face, points, -1.0) - points, axis=1)
    farther = cold - reference
    assert (farther <= 1e-9).mean() >= 0.995
    assert farther.max() <= 0.05 * 0.9


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


def test_a_gap_in_the_source_tessellation_makes_no_miss(tmp_path):
    """The patches-to-source distance of a sample is the distance to the nearest point of the
    part: where the dense source tessellation leaves a sliver of a B-rep face uncovered, the
    foot on the face of the nearest source triangle lies far, and every face whose box is
    nearer gets a second look. The shipped handle's 88-patch layout (its design stored in
    tests/data) has such a sample 0.008 from one face, whose tessellation there lay 0.14
    away: it was reported at 0.133 from the neighbour face, 1.4 tolerances, and the fit
    "missed" on two patches it fits within 0.06."""
    import json
    import os
    import subprocess
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = str(tmp_path / "out")
    run = subprocess.run([os.path.join(repo, "build", "stripweave"), "weave",
                          os.path.join(repo, "examples", "handle.step"), "--design",
                          os.path.join(repo, "tests", "data", "handle-88-patches.design.json"),
                          "--step", "--out", out], capture_output=True, text=True, cwd=repo)
    assert run.returncode == 0, run.stderr[-2000:]
    fit = json.load(open(os.path.join(out, "report.json")))["fit"]
    assert len(fit["per_patch"]) == 88
    assert fit["max_deviation_patches_to_source"] <= fit["tolerance"]
    assert fit["tolerance_met"]


ROUNDED_BOX_FIT = r"""
import sys
import FreeCAD, Part
import stripweave as sw
from stripweave.design import Design
from stripweave.strips import DesignSession
from stripweave.surfacing import refit_design
box = Part.makeBox(20.0, 14.0, 10.0)
s = sw.from_shape(box.makeFillet(3.0, box.Edges), target_triangles=3000)
# The three belts (a fixed design: the test is about the projection, not about weaving).
ds = DesignSession(s, Design([[(20.0, 7.0, 5.0, 0, 0, 1)], [(12.55, 14.0, 4.84, 0.0047, 0, 1.0)],
                              [(3.46, 0.0, 5.57, -0.9949, 0, 0.1009)]]))
r = refit_design(ds, split_patches=False)
print(r["max_deviation"], r["tolerance"])
"""


def test_warm_projection_on_closed_faces_stays_in_one_period(tmp_path):
    """On a rounded box's fillet faces (periodic surfaces: cylinders, tori), the warm-started
    projection wraps a periodic parameter into its first period. Left free, it drifted by
    whole periods from sample to sample, and the trim classifier took minutes per point so
    far outside the face's parameter range: the refit of this box never ended."""
    import os
    import subprocess
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    script = tmp_path / "fit.py"
    script.write_text(ROUNDED_BOX_FIT)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        ["/usr/lib/freecad-python3/lib", os.path.join(repo, "workbench"), os.path.join(repo, "build")]))
    run = subprocess.run(["/usr/bin/python3", str(script)], capture_output=True, text=True, timeout=180, env=env)
    assert run.returncode == 0, run.stderr[-2000:]
    deviation, tolerance = map(float, run.stdout.split()[-2:])
    assert deviation <= tolerance
