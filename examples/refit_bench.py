"""Refit benchmark: the surfacing stage (issue 7) on real layouts, with figures.

    /usr/bin/python3 examples/refit_bench.py [--only NAME ...]

Cases (each: model -> surface -> design -> layout -> patch network -> refit):
  screw     /work/shared/models/step/screw.step (outside the repo; skipped when
            absent) with a hand-made "box" design: one loop around the shank, two
            through the axis over the head.
  ubend2    /work/shared/models/step/ubend2.stp (outside the repo; skipped when absent),
            an open square tube bent into a U, with a hand-made design: two curves
            along each of its 4 B-spline faces (at a third of the face's width), and
            4 rings around it; every crease runs through regions, so the primal edges
            follow it, and each patch lies within one face.
  sphere96  the 96-patch cube-sphere network of the tests: refit time at ~100 patches.
  loft      the lofted part of tests/test_refit.py (box design).
  loft4     the same part with two belts and the two cap loops (4 regular vertices).
  utube     the square U-tube of tests/models.py (open, creased, a skewed end) with the
            design of tests/test_refit.py: two curves along each side, 4 rings.
  cylinder  the capped cylinder's box design (the test case), for reference.
Prints per case: patches, max/rms deviation against the tolerance, seam gap, seam
angle (middle of smooth seams; regular seams), volume, refit time and setup time.
"""
import argparse
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
for path in ("/usr/lib/freecad-python3/lib", os.path.join(REPO, "workbench"), os.path.join(REPO, "build")):
    if path not in sys.path:
        sys.path.append(path)

import numpy as np  # noqa: E402

import FreeCAD  # noqa: E402,F401  (before Part)
import Part  # noqa: E402

import stripweave as sw  # noqa: E402
from stripweave.design import Design  # noqa: E402
from stripweave.strips import DesignSession  # noqa: E402
from stripweave.surfacing import refit_design  # noqa: E402

SCREW = "/work/shared/models/step/screw.step"
UBEND2 = "/work/shared/models/step/ubend2.stp"


def screw_case():
    if not os.path.exists(SCREW):
        return None
    shape = Part.read(SCREW)
    ax, ay = -17.8981, -0.8263  # the shank's axis (z), radius 5, from z = -33.6 to 0.4
    anchors = [[(ax + 5, ay, -16, 0, 1, 0)], [(ax + 5, ay, -16, 0, 0, 1)], [(ax, ay + 5, -16, 0, 0, 1)]]
    return shape, anchors, None


def ubend2_case():
    if not os.path.exists(UBEND2):
        return None
    shape = Part.read(UBEND2)
    along, rings = [], []
    for face in shape.Faces:
        u0, u1, v0, v1 = face.ParameterRange
        S = face.Surface

        def extent(du, dv):  # polyline length through the middle, along u (du) or v (dv)
            pts = [S.value(u0 + (u1 - u0) * (0.5 * dv + du * k / 20), v0 + (v1 - v0) * (0.5 * du + dv * k / 20))
                   for k in range(21)]
            return sum((b - a).Length for a, b in zip(pts, pts[1:]))
        long_u = extent(1, 0) > extent(0, 1)
        for w in (1 / 3, 2 / 3):   # curves along the face, a third of its width from each crease
            u, v = ((u0 + u1) / 2, v0 + (v1 - v0) * w) if long_u else (u0 + (u1 - u0) * w, (v0 + v1) / 2)
            p, d = S.value(u, v), S.getDN(u, v, 1, 0) if long_u else S.getDN(u, v, 0, 1)
            along.append([(p.x, p.y, p.z, d.x, d.y, d.z)])
        if not rings:              # rings across the first face (normal x the face's long direction)
            for t in (0.2, 0.4, 0.6, 0.8):
                u, v = (u0 + (u1 - u0) * t, (v0 + v1) / 2) if long_u else ((u0 + u1) / 2, v0 + (v1 - v0) * t)
                du, dv = S.getDN(u, v, 1, 0), S.getDN(u, v, 0, 1)
                p, d = S.value(u, v), du.cross(dv).cross(du if long_u else dv)
                rings.append([(p.x, p.y, p.z, d.x, d.y, d.z)])
    diagonal = shape.BoundBox.DiagonalLength
    return shape, along + rings, {"compatibility_band": 0.03 * diagonal}


def sphere96_case():
    """The 96-patch cube-sphere network of tests/test_surfacing.py (each cube face split
    4 x 4, projected onto the sphere): a hand-built network, since the design's
    compatibility mask refuses most further strips on a sphere past a few."""
    sys.path.append(os.path.join(REPO, "tests"))
    from test_surfacing import cube_network
    R = 5.0
    net = cube_network(lambda p: R * p / np.linalg.norm(p), grid=4, sharp=False, split=4)
    return Part.makeSphere(R), net, None


def cylinder_case():
    anchors = [[(5, 0, 10, 0, 1, 0)], [(-5, 0, 10, 0, 0, 1)], [(0, 5, 10, 0, 0, 1)]]
    return Part.makeCylinder(5, 20), anchors, None


def loft_case():
    """The lofted part of tests/test_refit.py with its box design."""
    sys.path.append(os.path.join(REPO, "tests"))
    from test_refit import lofted_solid, side_point
    shape = lofted_solid()
    anchors = [[side_point(shape, 0.3, 12) + (-math.sin(0.3), math.cos(0.3), 0)],
               [side_point(shape, 0, 12) + (0, 0, 1)], [side_point(shape, math.pi / 2, 12) + (0, 0, 1)]]
    return shape, anchors, None


def loft4_case():
    """The lofted part with two belts around the side (z 8 and 16) and the two cap loops."""
    sys.path.append(os.path.join(REPO, "tests"))
    from test_refit import lofted_solid, two_belt_loft_design
    shape = lofted_solid()
    d = two_belt_loft_design(shape)
    return shape, d.anchor_lists(), d.options


def utube_case():
    sys.path.append(os.path.join(REPO, "tests"))
    from models import square_u_tube
    from test_refit import u_tube_design
    d = u_tube_design()
    return square_u_tube(), d.anchor_lists(), d.options


TRIANGLES = {"ubend2": 30000}
CASES = {"screw": screw_case, "ubend2": ubend2_case, "loft": loft_case, "loft4": loft4_case, "utube": utube_case, "sphere96": sphere96_case, "cylinder": cylinder_case}


def run(name, make, triangles, step_dir):
    case = make()
    if case is None:
        print(f"{name}: skipped (model not found)")
        return
    shape, anchors, options = case
    t0 = time.perf_counter()
    surface = sw.from_shape(shape, target_triangles=triangles)
    if isinstance(anchors, dict):  # a ready patch network
        network = anchors
        refit_call = lambda **kw: sw._native.refit(surface, network, **kw)  # noqa: E731
    else:
        try:
            ds = DesignSession(surface, Design(anchors, options=options))
            network = ds.native.patch_network()
        except sw.InputError as exc:
            print(f"{name}: design failed: {exc}")
            return
        refit_call = lambda **kw: refit_design(ds, **kw)  # noqa: E731
    setup = time.perf_counter() - t0
    if not network["patches"]:
        print(f"{name}: layout not valid (red regions)")
        return
    step = os.path.join(step_dir, f"{name}.step") if step_dir else None
    t0 = time.perf_counter()
    r = refit_call(step_path=step)
    refit = time.perf_counter() - t0
    vol = r["volume"]
    vol_s = f"{vol:.6g}" if vol is not None else "-"
    if vol is not None:
        vol_s += f" (source {shape.Volume:.6g}, error {vol / shape.Volume - 1:+.2e})"
    diag = network.get("bbox_diagonal") or shape.BoundBox.DiagonalLength
    print(f"{name}: {len(network['patches'])} patches, {r['smooth_seams']} smooth / {r['sharp_seams']} sharp seams")
    print(f"  deviation max {r['max_deviation']:.3g} rms {r['rms_deviation']:.3g} (tolerance {r['tolerance']:.3g}, "
          f"met: {r['tolerance_met']}; edges {r['max_edge_deviation']:.3g}); diagonal {diag:.4g}")
    print(f"  seam gap {r['max_seam_gap']:.2g} ({r['max_seam_gap'] / diag:.1e} of the diagonal); seam angle "
          f"{r['max_seam_angle_deg']:.3f} deg (middle), {r['max_seam_angle_deg_regular']:.3f} deg (regular seams), "
          f"{r['max_seam_angle_deg_full']:.3f} deg (whole seams)")
    print(f"  shell: valid {r['valid_shell']}, closed {r['closed']}, volume {vol_s}; STEP faces read back "
          f"{r['step_faces_read_back']}")
    print(f"  refit {refit:.2f} s (native {r['time_s']:.2f} s: "
          + ", ".join(f"{k} {v / 1000:.2f}" for k, v in r["timings_ms"].items())
          + f"); setup (surface, design, layout) {setup:.2f} s")
    sys.stdout.flush()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", choices=sorted(CASES), help="cases to run (default: all)")
    ap.add_argument("--triangles", type=int, default=None,
                    help="solver mesh size (default 20000; ubend2 30000, where its rings cross the curves cleanly)")
    ap.add_argument("--step-dir", default=None, help="write each case's STEP here")
    args = ap.parse_args(argv)
    for name in args.only or CASES:
        run(name, CASES[name], args.triangles or TRIANGLES.get(name, 20000), args.step_dir)


if __name__ == "__main__":
    main()
