"""Issue 7 end to end: model -> surface -> design -> layout -> patch network -> B-spline
patches, shell/solid and STEP (stripweave.surfacing.refit_design), on analytic cases.

Figures are in model units; the tolerance defaults to 1e-3 of the bbox diagonal.
"""
import math
import os
import re

import numpy as np
import pytest

import FreeCAD  # noqa: F401  (before Part)
import Part
from FreeCAD import Vector

import stripweave as sw
from models import box, capped_cylinder, square_u_tube
from stripweave.design import Design
from stripweave.strips import DesignSession
from stripweave.surfacing import DESIGN_FIT_KEYS, FIT_KEYS, fit_report, format_fit, refit_design

CUBE_BELTS = [[(5, 5, 10, 1, 0, 0)], [(5, 3, 0, 0, 1, 0)], [(3, 0, 5, 1, 0, 0)]]
CYLINDER_BOX = [[(5, 0, 10, 0, 1, 0)], [(-5, 0, 10, 0, 0, 1)], [(0, 5, 10, 0, 0, 1)]]


def step_faces(path):
    """Faces of a STEP file as FreeCAD reads it."""
    shape = Part.read(str(path))
    return len(shape.Faces)


def check_shell(result, diagonal):
    assert result["valid_shell"] and result["shells"] == 1 and result["free_edges"] == 0
    assert result["max_seam_gap"] < 1e-6 * diagonal


@pytest.fixture(scope="module")
def cube_fit(tmp_path_factory):
    ds = DesignSession(sw.from_shape(box(10), target_triangles=12000), Design(CUBE_BELTS))
    step = tmp_path_factory.mktemp("cube") / "patches.step"
    return ds, refit_design(ds, step_path=str(step)), step


def test_cube_three_belts(cube_fit):
    ds, r, step = cube_fit
    diagonal = 10 * math.sqrt(3)
    assert len(r["per_patch"]) == 6 and r["faces"] == 6
    assert r["max_deviation"] <= 1e-4 * diagonal
    # Two-sided and covering: the tolerance is met on an honest measure.
    assert r["max_deviation_source_to_patches"] <= 1e-4 * diagonal
    assert r["max_deviation_patches_to_source"] <= 1e-4 * diagonal
    assert r["coverage"] >= 0.999 and r["tolerance_met"]
    check_shell(r, diagonal)
    assert r["closed"] and r["volume"] == pytest.approx(1000, rel=1e-3)
    assert r["sharp_seams"] == 12 and r["smooth_seams"] == 0
    # STEP round trip: the native read-back and FreeCAD's.
    assert r["step_faces_read_back"] == 6
    assert step_faces(step) == 6


def test_fit_report_block(cube_fit):
    """fit_report() holds every fit key of design.md (floats in model units, tolerance_met
    a bool), both directions per patch, and no per-triangle array (that is for
    deviation.png only); it is plain JSON."""
    import json
    _, r, _ = cube_fit
    fit = fit_report(r)
    design_keys = ("max_deviation", "rms_deviation", "max_seam_gap", "max_seam_angle_deg",
                   "max_deviation_source_to_patches", "max_deviation_patches_to_source",
                   "rms_deviation_source_to_patches", "rms_deviation_patches_to_source", "tolerance", "coverage",
                   "uncovered_area", "tolerance_met", "max_regular_seam_angle_deg")
    assert set(design_keys) == set(DESIGN_FIT_KEYS)
    for k in design_keys + ("per_patch", "tolerance", "valid_shell", "closed", "volume", "faces"):
        assert k in fit
    assert isinstance(fit["tolerance_met"], bool) and fit["tolerance_met"]
    assert fit["max_deviation"] == max(fit["max_deviation_source_to_patches"], fit["max_deviation_patches_to_source"])
    assert fit["max_regular_seam_angle_deg"] == r["max_seam_angle_deg_regular"]
    assert fit["coverage"] >= 0.999
    for p in fit["per_patch"]:
        for k in ("max_deviation", "max_deviation_source_to_patch", "max_deviation_patch_to_source",
                  "rms_deviation_source_to_patch", "rms_deviation_patch_to_source"):
            assert isinstance(p[k], float)
    assert "triangle_uncovered" in r and "triangle_uncovered" not in fit
    json.dumps(fit)
    assert fit["tolerance"] == pytest.approx(1e-3 * 10 * math.sqrt(3))
    assert len(fit["per_patch"]) == 6 and fit["faces"] == 6 and fit["closed"] and fit["valid_shell"]
    assert all(isinstance(fit[k], float) for k in FIT_KEYS)
    assert "6 patches" in format_fit(fit)


def test_capped_cylinder_box_design(tmp_path):
    shape = capped_cylinder(5, 20)
    bb = shape.BoundBox
    assert (bb.ZMin, bb.ZMax) == (0, 20)  # the anchors assume the axis z from 0 to 20
    ds = DesignSession(sw.from_shape(shape, target_triangles=12000), Design(CYLINDER_BOX))
    step = tmp_path / "cylinder.step"
    r = refit_design(ds, step_path=str(step))
    diagonal = math.sqrt(10 ** 2 + 10 ** 2 + 20 ** 2)
    assert len(r["per_patch"]) == 6
    # The patch corners sit on the rims, so the rims are patch borders (sharp seams).
    L = ds.native.layout()
    assert all(v["placement"] == "feature" for v in L["vertices"])
    assert all(abs(v["position"][2]) < 1e-9 or abs(v["position"][2] - 20) < 1e-9 for v in L["vertices"])
    assert r["sharp_seams"] == 8 and r["smooth_seams"] == 4
    assert r["max_deviation"] <= 1e-3 * diagonal and r["tolerance_met"]
    assert max(r["max_deviation_source_to_patches"], r["max_deviation_patches_to_source"]) <= r["tolerance"]
    assert r["coverage"] >= 0.999 and r["uncovered_area"] <= 1e-3 * r["source_area"]
    check_shell(r, diagonal)
    assert r["closed"] and r["volume"] == pytest.approx(500 * math.pi, rel=5e-3)
    assert r["max_seam_angle_deg"] < 1.0
    assert r["step_faces_read_back"] == 6 and step_faces(step) == 6


def lofted_solid():
    """A freeform closed part: a loft through four twisted ellipses, capped."""
    def section(z, a, b, turn_deg):
        w = Part.Wire(Part.Ellipse(Vector(0, 0, z), a, b).toShape())
        w.rotate(Vector(0, 0, z), Vector(0, 0, 1), turn_deg)
        return w
    return Part.makeLoft([section(0, 8, 5, 0), section(8, 6, 4, 20), section(16, 7, 6, 40), section(24, 5, 4, 60)],
                         True, False)


def side_point(shape, theta, z):
    ray = Part.makeLine(Vector(0, 0, z), Vector(30 * math.cos(theta), 30 * math.sin(theta), z))
    return tuple(Part.Compound(shape.Faces).distToShape(ray)[1][0][0])


def test_freeform_loft_box_design(tmp_path):
    """A box design on a lofted part: one loop around the side, two over the caps. The
    layout's 8 vertices are valence 3 (no regular vertex, so no regular seam figure); the
    4 side seams are smooth."""
    shape = lofted_solid()
    anchors = [[side_point(shape, 0.3, 12) + (-math.sin(0.3), math.cos(0.3), 0)],
               [side_point(shape, 0, 12) + (0, 0, 1)], [side_point(shape, math.pi / 2, 12) + (0, 0, 1)]]
    ds = DesignSession(sw.from_shape(shape, target_triangles=15000), Design(anchors))
    step = tmp_path / "loft.step"
    r = refit_design(ds, step_path=str(step))
    diagonal = ds.native.patch_network()["bbox_diagonal"]  # exact (FreeCAD's BoundBox is the control net's)
    assert diagonal == pytest.approx(shape.optimalBoundingBox().DiagonalLength, rel=1e-3)
    assert len(r["per_patch"]) == 6
    assert r["tolerance"] == pytest.approx(1e-3 * diagonal, rel=1e-3)
    assert r["tolerance_met"] and r["max_deviation"] <= r["tolerance"]
    check_shell(r, diagonal)
    assert r["closed"] and r["volume"] == pytest.approx(shape.Volume, rel=1e-3)
    # Smooth seams: the normal jump over the middle of each seam (G1 is impossible at
    # the valence-3 corners themselves).
    assert r["smooth_seams"] == 4 and r["max_seam_angle_deg"] < 1.0
    assert r["step_faces_read_back"] == 6 and step_faces(step) == 6


def two_belt_loft_design(shape):
    """The lofted part's design with regular vertices: two belts around the side (z 8 and
    16; parallel loops, allowed by a compatibility band) and the two loops over the caps."""
    belts = [[side_point(shape, 0.3, z) + (-math.sin(0.3), math.cos(0.3), 0)] for z in (8, 16)]
    caps = [[side_point(shape, 0, 12) + (0, 0, 1)], [side_point(shape, math.pi / 2, 12) + (0, 0, 1)]]
    return Design(belts + caps, options={"compatibility_band": 2.0})


def test_freeform_loft_regular_seams():
    """The lofted part with two belts around the side and two loops over the caps: the
    belts (parallel loops, allowed by a compatibility band) leave a middle band of 4
    regions of valence 4, so the layout has 4 regular vertices, and the seams between
    them must be tangent continuous (the issue: under 1 degree at regular vertices, whole
    seam), with the tolerance met and the shell closed."""
    shape = lofted_solid()
    ds = DesignSession(sw.from_shape(shape, target_triangles=15000), two_belt_loft_design(shape))
    L = ds.native.layout()
    assert sorted(v["valence"] for v in L["vertices"]) == [3] * 8 + [4] * 4
    r = refit_design(ds)
    diagonal = ds.native.patch_network()["bbox_diagonal"]
    assert len(r["per_patch"]) == len(L["patches"]) == 10
    assert r["tolerance_met"] and r["max_deviation"] <= r["tolerance"]
    check_shell(r, diagonal)
    assert r["closed"] and r["volume"] == pytest.approx(shape.Volume, rel=1e-3)
    # Seams between two regular vertices exist (the figure is 0 without any) and are G1.
    assert 0 < r["max_seam_angle_deg_regular"] < 1.0


def u_tube_design(R=20.0, L=20.0, w=8.0):
    """Two loops along each of the tube's 4 sides, at a third of its width from each crease
    (open curves from end to end: each crease then runs inside a chain of regions, whose
    primal edges follow it), and 4 rings around it (two on the half circle, one on each
    leg). Patches lie within one side each; the regions between two curves on one side
    have regular vertices with four smooth seams."""
    a = w / 6
    along = [[(R, L + R + y, z, 1, 0, 0)] for y, z in ((a, w / 2), (-a, w / 2), (a, -w / 2), (-a, -w / 2),
                                                         (w / 2, a), (w / 2, -a), (-w / 2, a), (-w / 2, -a))]
    rings = [[(0, L / 2, w / 2, 1, 0, 0)], [(2 * R, 0.7 * L, w / 2, 1, 0, 0)]]
    for degrees in (60, 120):
        t = math.radians(degrees)
        rings.append([(R - R * math.cos(t), L + R * math.sin(t), w / 2, -math.cos(t), math.sin(t), 0)])
    return Design(along + rings, options={"compatibility_band": 1.0})


def test_square_u_tube_corners_and_regular_seams(tmp_path):
    """An open, creased tube like the shared ubend2.stp (tests/models.py): each crease ends
    in a corner of the open boundary, where a patch corner belongs. Open dual curves must
    not end at such corners (loop_search.cpp): before, one curve ended on a corner of the
    skewed end, neither region took the corner, the primal edge turned it inside a patch
    side, and three patches lay over a crease (deviation 2.5 tolerances). Now all 8 corners
    are primal vertices, no patch is creased, the tolerance is met, and the seams between
    regular vertices are G1 under 1 degree."""
    shape = square_u_tube()
    ds = DesignSession(sw.from_shape(shape, target_triangles=15000), u_tube_design())
    L = ds.native.layout()
    assert L["valid"] and not L["problems"]
    corners = [v for v in L["vertices"] if v["placement"] == "corner"]
    assert len(corners) == 8 and all(v["boundary"] for v in corners)
    step = tmp_path / "tube.step"
    r = refit_design(ds, step_path=str(step))
    diagonal = ds.native.patch_network()["bbox_diagonal"]
    assert len(r["per_patch"]) == len(L["patches"])
    assert r["creased_patches"] == 0 and r["folded_patches"] == 0
    assert r["tolerance_met"] and r["max_deviation"] <= r["tolerance"]
    # One valid open shell: its free edges are exactly the layout's boundary edges.
    assert r["valid_shell"] and r["shells"] == 1 and not r["closed"]
    assert r["free_edges"] == r["boundary_edges"] == 16 and r["sharp_seams"] == 16
    assert r["max_seam_gap"] < 1e-6 * diagonal
    assert 0 < r["max_seam_angle_deg_regular"] < 1.0
    assert r["step_faces_read_back"] == len(L["patches"]) == step_faces(step)


def test_invalid_design_has_nothing_to_fit():
    ds = DesignSession(sw.from_shape(box(10), target_triangles=6000), Design(CUBE_BELTS[:1]))
    with pytest.raises(sw.InputError, match="no patches to fit"):
        refit_design(ds)


def test_user_tolerance_and_options(cube_fit):
    ds, _, _ = cube_fit
    r = refit_design(ds, tolerance=0.5, max_spans=4)
    assert r["tolerance"] == 0.5 and r["tolerance_met"]
    with pytest.raises(sw.InputError):
        refit_design(ds, no_such_option=1)


def test_refit_reports_stages_and_stops_on_cancel(cube_fit):
    """The workbench's Cancel of Fit patches (issue 20): a Progress passed to the refit sees
    its stages, and a cancelled one stops it with Cancelled at the next stage or patch."""
    import threading
    ds, _, _ = cube_fit
    progress = sw.Progress()
    r = refit_design(ds, progress=progress)
    assert r["tolerance_met"] and progress.fraction() == pytest.approx(0.93, abs=1e-9)
    assert progress.stage() == "sewing the shell"
    stopped = sw.Progress()
    stopped.cancel()
    with pytest.raises(sw.Cancelled):
        refit_design(ds, progress=stopped)
    # Cancelled from another thread while the fit runs: it ends with Cancelled, not a result.
    running, outcome = sw.Progress(), {}

    def fit():
        try:
            outcome["result"] = refit_design(ds, progress=running)
        except sw.Cancelled:
            outcome["cancelled"] = True
    worker = threading.Thread(target=fit)
    worker.start()
    while running.fraction() < 0.1 and worker.is_alive():
        threading.Event().wait(0.001)
    at_cancel = running.fraction()
    running.cancel()
    worker.join(60)
    if at_cancel < 0.9:            # before the last stage: a check lies ahead, so it must stop
        assert outcome == {"cancelled": True}


def test_refit_same_on_one_and_two_cores():
    """The refit solves independent patches side by side on the cores the process may use
    (core/parallel.h): the result must not depend on how many that is. The lofted part's
    two-belt design, fitted pinned to one core and then on all the process may use (two on
    our machines), gives identical patches."""
    shape = lofted_solid()
    ds = DesignSession(sw.from_shape(shape, target_triangles=6000), two_belt_loft_design(shape))
    cores = os.sched_getaffinity(0)
    try:
        os.sched_setaffinity(0, {min(cores)})
        one = refit_design(ds)
    finally:
        os.sched_setaffinity(0, cores)
    two = refit_design(ds)
    for key in ("max_deviation", "rms_deviation", "max_seam_angle_deg", "rounds", "uncoupled_patches"):
        assert one[key] == two[key]
    assert [p["max_deviation"] for p in one["per_patch"]] == [p["max_deviation"] for p in two["per_patch"]]


def test_weave_step_writes_the_deviation_picture(tmp_path):
    """`weave --step` also renders deviation.png: each patch coloured by its fit's
    deviation over the tolerance (preview.patch_deviation_tints). The cube's belts fit
    exactly: every patch green; patches three tolerances off are red."""
    from stripweave.preview import DEVIATION_SCALE, NOT_FITTED, deviation_colour, patch_deviation_tints
    from test_weave import read_png
    assert deviation_colour(0) == DEVIATION_SCALE[0][1] and deviation_colour(5) == DEVIATION_SCALE[-1][1]
    assert deviation_colour(1.0) == pytest.approx(DEVIATION_SCALE[1][1])
    out = tmp_path / "cube"
    r = sw.weave(box(10), design=Design(CUBE_BELTS), auto=False, out=str(out), step=True, target_triangles=8000)
    assert r["paths"]["deviation"] == str(out / "deviation.png")
    w, h, rgb = read_png(out / "deviation.png")
    assert (w, h) == read_png(out / "preview.png")[:2]
    green, red = np.array(DEVIATION_SCALE[0][1]), np.array(DEVIATION_SCALE[-1][1])
    # Shaded pixels are the tint over the base colour times a Lambert factor: compare hues
    # (the colour direction), on pixels that are not background or edge lines.
    px = rgb.reshape(-1, 3).astype(float)
    px = px[(px.sum(1) < 3 * 250) & (px.max(1) > 60)]
    hue = px / np.linalg.norm(px, axis=1, keepdims=True)

    def share(colour):
        base = np.array([0.80, 0.82, 0.85])
        c = 0.45 * base + 0.55 * colour
        return np.mean(hue @ (c / np.linalg.norm(c)) > 0.995)
    assert share(green) > 0.9 and share(red) < 0.01
    # The same layout with every patch three tolerances off: all red; one not fitted.
    ds = DesignSession(r["surface"], r["design"])
    fit = fit_report(refit_design(ds))
    for p in fit["per_patch"]:
        p["max_deviation"] = 3 * fit["tolerance"]
    details = ds.native.layout(True)
    tints = patch_deviation_tints(details, fit, len(ds.surface.triangles))
    covered = ~np.isnan(tints[:, 0])
    assert covered.all() and np.allclose(tints, red)
    details["patches"][0]["quad"] = False
    fit["per_patch"].pop(0)
    tints = patch_deviation_tints(details, fit, len(ds.surface.triangles))
    assert 0.1 < np.mean(np.all(np.isclose(tints, NOT_FITTED), axis=1)) < 0.25


def test_no_clean_quad_to_fit_is_named():
    """A valid layout none of whose patches reads as a clean quad (trj5's single patch, over
    its creases) has nothing to fit: the error says so, for one patch and for several."""
    class Native:
        def __init__(self, made):
            self.made = made

        def patch_network(self, set_aside_red=False):
            return {"patches": [], "layout_patches": self.made}

    class Session:
        def __init__(self, made):
            self.native = Native(made)
    with pytest.raises(sw.InputError, match="the layout's only patch is not a clean quad"):
        refit_design(Session(1))
    with pytest.raises(sw.InputError, match="none of the layout's 3 patches is a clean quad"):
        refit_design(Session(3))
    with pytest.raises(sw.InputError, match="has no patch"):
        refit_design(Session(0))


def test_a_two_solid_file_gives_two_solids_with_their_volumes_named_and_coloured_faces(tmp_path):
    """An assembly's solids stay one solid each (issue 19): a cube and a flat box in one STEP
    file weave clean, and patches.step holds two solids of 1000 and 240 (the sewn shells are
    two, each closed; one compound of both), which FreeCAD reads back as such."""
    import FreeCAD
    import Part
    path = str(tmp_path / "two.step")
    Part.makeCompound([Part.makeBox(10, 10, 10), Part.makeBox(10, 6, 4, FreeCAD.Vector(20, 0, 0))]).exportStep(path)
    report = sw.weave(path, target_triangles=8000, out=str(tmp_path / "out"), step=True)
    fit = report["fit"]
    assert fit["solids"] == 2 and fit["shells"] == 2 and fit["closed"] and fit["valid_shell"]
    assert fit["volume"] == pytest.approx(1240.0, rel=1e-3)
    back = Part.Shape()
    back.read(str(tmp_path / "out" / "patches.step"))
    assert sorted(round(s.Volume, 1) for s in back.Solids) == [240.0, 1000.0]
    assert len(back.Faces) == 12
    # Each face is named after its patch (fit["per_patch"] index) and coloured by its deviation
    # as deviation.png draws it: every patch fits well within the tolerance here, so green.
    text = open(tmp_path / "out" / "patches.step").read()
    names = re.findall(r"ADVANCED_FACE\('patch (\d+)'", text)
    assert sorted(map(int, names)) == list(range(12))
    assert text.count("STYLED_ITEM") == 12
    (rgb,) = set(re.findall(r"COLOUR_RGB\('',([^)]*)\)", text))
    assert [float(x) for x in rgb.split(",")] == pytest.approx([0.15, 0.65, 0.3], abs=1e-6)


def test_the_main_job_on_a_boss_on_a_plate_is_clean_within_tolerance_and_one_solid(tmp_path):
    """The chain on a machined part (issues 17 to 19): a cylinder boss on a plate, from STEP,
    woven automatically. Its two rims are closed creases the weave crosses once the crease
    phase stalls (weave.rim_lack), so the layout is clean and crease-conforming; every patch is
    fitted, the two-sided deviation is within the default tolerance (1e-3 of the diagonal) with
    the whole part covered, and patches.step reads back as one solid of the part's volume."""
    import FreeCAD
    import Part
    path = str(tmp_path / "boss.step")
    Part.makeBox(40, 40, 4).fuse(Part.makeCylinder(6, 6, FreeCAD.Vector(20, 20, 4))).removeSplitter().exportStep(path)
    volume = 40 * 40 * 4 + math.pi * 36 * 6
    report = sw.weave(path, target_triangles=15000, out=str(tmp_path / "out"), step=True)
    assert report["clean"] and report["crease_conforming"]
    fit = report["fit"]
    assert fit["tolerance_met"] and fit["coverage"] >= 0.999
    assert fit["max_deviation"] <= fit["tolerance"] <= 1e-3 * report["bbox_diagonal"] * (1 + 1e-9)
    assert len(fit["per_patch"]) == report["patches"]          # every patch fitted
    assert fit["solids"] == 1 and fit["closed"] and fit["valid_shell"]
    back = Part.Shape()
    back.read(str(tmp_path / "out" / "patches.step"))
    assert len(back.Solids) == 1 and back.Volume == pytest.approx(volume, rel=5e-3)
