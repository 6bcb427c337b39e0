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
# first fourteen strips, the fifteenth strip's loop (SEARCHED) meets an earlier loop running
# in the same direction of the cross field, and the design refused it ("loops i and j
# meet ..."); two more strips follow it. Recorded again when the command line began reading
# STEP as FreeCAD hands it over, which meshes the star otherwise (the earlier ten anchors'
# tenth loop then met one the search again could not part). Some of the weave's strips
# conquer nothing under the paper's whole-strip compatibility: the test is about the loops.
STAR_STRIPS = [
    (10.078801683510049, 16.64288449207971, 1.5013227513227512, 0.11551270390784636, -0.9933053316277634, 0.0011547275684056057),
    (-9.376240079365179, -17.05101209824091, 1.5013227513227512, 0.0008260138661483896, 0.0003568799579321269, -0.9999995951688125),
    (-5.994744530972634, 9.903175615620915, 8.0, -0.9948276223594306, 0.10157756539060425, 0.0),
    (10.943747686899705, -9.205127018920141, 1.4999999999999996, -7.047377320601456e-09, -6.060110480099468e-08, 0.9999999999999982),
    (19.726822820287452, 0.2031250000000193, 1.75, -1.2486749645379547e-07, 9.284710472678981e-08, 0.9999999999999878),
    (7.717466213139936, 2.0714371359382677, 8.0, 0.6107882779020337, -0.7917939628321676, 0.0),
    (-4.927095451987983, 0.8507234609432954, 3.9875991568148006, 0.015258022176726838, 0.08836917650058035, 0.9959709239751249),
    (4.027766618809242, -2.962616422084703, 3.5489623048007726, 0.5924618885161841, 0.805469854178086, -0.014395300141693879),
    (-8.637181295525563, 3.421866327614114, 8.0, 0.6009869141796588, 0.7992588623123371, -0.0),
    (4.910462966105388, -2.8099323238765583, 8.0, 0.5285271989583368, 0.848916368060632, 0.0),
    (-5.5830673899342536, -3.5305599237996677, 8.0, 0.8918302657372876, 0.45237017708394406, 0.0),
    (-1.4641138563827591, 4.780833673696253, 8.0, 0.12126404562033255, -0.7075103144630472, -0.6962213629070785),
    (2.335460297023657, 4.4210434516102834, 6.995316343032207, -0.8839970267937868, 0.46698024603487587, 0.021879360889930755),
    (1.464113856382767, -4.78083367369625, 0.0, -0.12856840346113912, 0.7061669547369441, 0.6962746567763358),
    (1.8642823889015387, 4.639445136482548, 0.0, 0.4626471661583843, 0.566366217703348, -0.6820461180081739),
    (3.9745069824853534, 3.033693169418287, 0.5098120542421949, -0.6067386075242329, 0.7949013619630192, -0.00029476921806412953),
    (3.1699779126197773, -5.3612263856568125, 0.0, 0.48448885177575474, -0.8747974351271331, 0.0),
]
SEARCHED = 14


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
    # Without the search again this raises "strip 15: loops 14 and ... meet ... running in
    # the same direction of the cross field".
    ds = DesignSession(surface, Design(strips))
    # Every strip derived and closed; the fifteenth loop, found again, crossing every loop
    # transversally, conquers part of the plate and still passes its anchor.
    for i in range(len(STAR_STRIPS)):
        strip = ds.strip(i)
        assert strip["closed"] and strip["length"] > 0
    assert ds.strip(SEARCHED)["area_fraction"] > 0
    loop = ds.strip(SEARCHED)["points"]
    anchor = STAR_STRIPS[SEARCHED][:3]
    nearest = min(math.dist(p, anchor) for p in loop)
    assert nearest < 0.02 * surface.bbox_diagonal
