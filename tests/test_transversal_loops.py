"""A loop found under the compatibility mask can still meet an earlier loop too
tangentially (where a strip stops short of its loop at a crease, or an embedded g-edge
turns away from its nodes' directions); the design then searches it again with the g'
nodes it departed from there disabled (native strips/design_state.cpp, transversal_loop;
the meeting test is the parameterization's own, contradicting_meetings)."""
import math

import pytest

import stripweave as sw
from stripweave.design import Design
from stripweave.strips import DesignSession

# The anchors an automatic weave of the star below placed, one directional anchor per
# strip (model units, the point then its direction). Under the compatibility mask of the
# first nine strips, the tenth strip's loop meets an earlier loop running in the same
# direction of the cross field, and the design refused it ("loops i and j meet ...").
STAR_STRIPS = [
    (10.15729128114744, 15.967944566227603, 2.0, 0.11551278091999805, -0.9933059938629831, 1.1285442191866224e-08),
    (-10.157291281140436, -15.967944566219034, 2.0, 1.0630659311172685e-08, -9.141410611812617e-08, -0.9999999999999957),
    (-5.454769175759865, 9.501367061198316, 8.0, 0.9989352928543886, 0.04613329264118354, 0.0),
    (-17.541405382585623, -1.8281250000012546, 1.75, 0.0, 0.0, 1.0),
    (19.726822820287452, 0.2031250000000193, 1.75, 3.6976205430860887e-09, -2.7494213572509807e-09, -0.9999999999999999),
    (-8.295733094967323, -5.375747438859406, 8.0, 0.45904835587533066, -0.8884112825533877, 0.0),
    (4.940716687153884, 0.7676709042807024, 4.032388135224972, 0.01081579437960888, -0.06961026590714584, -0.9975156286857235),
    (-4.3400367837418194, 2.4827566767140032, 4.031564447254966, -0.49652971972874166, -0.8679695711042856, -0.009330651806799595),
    (4.999999999999141, 15.160254037846489, 8.0, 0.25623755516356783, -0.6593082537670713, 0.7068627461101715),
    (4.8296291314453415, 1.2940952255126037, 8.0, 0.679976634875739, -0.5290313356632856, 0.507698357205719),
]


def star_plate(path):
    """A 12-pointed star plate (radii 20 and 13, 8 thick) with a bore of radius 5, as STEP."""
    import FreeCAD
    import Part
    V = FreeCAD.Vector
    points = []
    for k in range(12):
        r = 20 if k % 2 == 0 else 13
        a = 2 * math.pi * k / 12
        points.append(V(r * math.cos(a), r * math.sin(a), 0))
    points.append(points[0])
    solid = Part.Face(Part.makePolygon(points)).extrude(V(0, 0, 8))
    solid = solid.cut(Part.makeCylinder(5, 10, V(0, 0, -1))).removeSplitter()
    solid.exportStep(str(path))
    return path


def test_a_loop_meeting_an_earlier_one_tangentially_is_searched_again(tmp_path):
    surface = sw.load(str(star_plate(tmp_path / "star.step")))
    strips = [[tuple(row)] for row in STAR_STRIPS]
    # Without the search again this raises "strip 10: loops 9 and 6 meet ... running in
    # the same direction of the cross field".
    ds = DesignSession(surface, Design(strips))
    # Every strip derived, closed and conquering part of the plate: the tenth loop found
    # again, crossing every loop transversally.
    for i in range(len(STAR_STRIPS)):
        strip = ds.strip(i)
        assert strip["closed"] and strip["length"] > 0 and strip["area_fraction"] > 0
    # The loop still passes its anchor.
    loop = ds.strip(len(STAR_STRIPS) - 1)["points"]
    anchor = STAR_STRIPS[-1][:3]
    nearest = min(math.dist(p, anchor) for p in loop)
    assert nearest < 0.02 * surface.bbox_diagonal
