"""Generate examples/handle.step: the freeform part the README's main job runs on.

A lofted, tapering handle: an elliptic foot blending into a rounded-rectangle
waist and a circular top, closed by planar caps, with a fillet around the foot.
Freeform B-spline side faces, a toroidal-like blend and sharp cap edges: the
mix a re-surfacing job meets on real parts.

    /usr/bin/python3 examples/make_example_part.py   (FreeCAD's Python)
"""
import math
import os
import sys

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402
import Part  # noqa: E402
from FreeCAD import Vector  # noqa: E402


def rounded_rectangle(w, h, r, z):
    """A closed wire: w x h rectangle with corner radius r at height z."""
    edges = []
    x, y = w / 2 - r, h / 2 - r
    corners = [(x, y, 0), (-x, y, 90), (-x, -y, 180), (x, -y, 270)]
    arcs = []
    for cx, cy, a in corners:
        c = Part.Circle(Vector(cx, cy, z), Vector(0, 0, 1), r)
        arcs.append(Part.ArcOfCircle(c, math.radians(a), math.radians(a + 90)))
    for i, arc in enumerate(arcs):
        edges.append(arc.toShape())
        nxt = arcs[(i + 1) % 4]
        edges.append(Part.LineSegment(arc.EndPoint, nxt.StartPoint).toShape())
    return Part.Wire(edges)


def make_handle():
    foot = Part.Wire(Part.Ellipse(Vector(0, 0, 0), 30, 18).toShape())
    waist = rounded_rectangle(24, 16, 5, 35)
    top = Part.Wire(Part.Circle(Vector(2, 0, 70), Vector(0.15, 0, 1), 14).toShape())
    solid = Part.makeLoft([foot, waist, top], True, False)
    foot_edges = [e for e in solid.Edges if abs(e.BoundBox.ZMax) < 1e-6]
    return solid.makeFillet(4.0, foot_edges)


if __name__ == "__main__":
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "handle.step")
    shape = make_handle()
    assert shape.isValid(), "the generated handle is not a valid solid"
    shape.exportStep(out)
    print(f"wrote {out}: {len(shape.Faces)} faces, volume {shape.Volume:.1f}")
