"""App-side checks of a design's symmetry (paper §5.8) without the GUI, run by
tests/gui/test_symmetry_headless.py under ``freecadcmd``.  A 40 x 20 x 8 slab with an
off-centre boss and its mirror image in x (tests/models.py mirrored_box): detection, accepting
the reflection (design.symmetry, one transaction, round-trips through design.json), a strip
added with the reflection accepted comes with its mirror image, turning symmetry off clears
design.symmetry and a strip is then added alone, a refused image keeps the design, and
Auto weave mirrors every strip it adds.  Writes JSON to $STRIPWEAVE_HEADLESS_RESULT
and exits with os._exit."""

import json
import os
import sys
import traceback

result = {"ok": False, "error": None}
WORKDIR = os.environ.get("STRIPWEAVE_HEADLESS_WORKDIR", "/tmp")
# A loop around the slab in the plane x = 16 (beside the boss at x in [7, 13]): not its own mirror image.
ANCHOR = (16.0, 0.0, 8.0, 0.0, 1.0, 0.0)


def strips_in(obj):
    return len(json.loads(obj.DesignJson)["strips"])


try:
    import FreeCAD as App
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    from models import mirrored_box
    from freecad.stripweave_wb import design_model, surface_model
    from stripweave.design import Design
    from stripweave.symmetry import loops_symmetry_error

    doc = App.newDocument("SymmetryHeadless")
    doc.UndoMode = 1
    part = doc.addObject("Part::Feature", "MirroredBox")
    part.Shape = mirrored_box()
    doc.recompute()
    sm = surface_model.create(part, target_triangles=8000)
    doc.recompute()
    design = design_model.create(sm)
    doc.recompute()
    diagonal = part.Shape.BoundBox.DiagonalLength
    result["diagonal"] = diagonal

    found = design_model.detect_symmetry(design)
    result["found"] = found
    mirror = [s for s in found if s["kind"] == "reflection" and abs(abs(s["normal"][0]) - 1) < 1e-6]
    result["mirror_found"] = bool(mirror)

    # accept: stored in the design, one transaction, round-trips through design.json
    result["set_changed"] = design_model.set_symmetry(design, mirror)
    result["undo_after_set"] = list(doc.UndoNames)[:1]
    result["stored"] = json.loads(design.DesignJson).get("symmetry")
    path = os.path.join(WORKDIR, "symmetric.design.json")
    design_model.export_design(design, path)
    result["round_trip"] = Design.load(path).symmetry == result["stored"]

    # a strip added with the reflection accepted comes with its mirror image
    design_model.add_strip(design, [ANCHOR])
    derived = design.Proxy.derived(design)
    loops = [s["points"] for s in derived.strips]
    result["with_mirror"] = {"strips": strips_in(design), "wires": len(design.Shape.Wires),
                             "image_of": [s.get("image_of") for s in json.loads(design.DesignJson)["strips"]],
                             "mirror_error": loops_symmetry_error(loops, mirror[0]) if mirror else None,
                             "x_means": [float(p[:, 0].mean()) for p in loops],
                             "undo": list(doc.UndoNames)[:1]}
    doc.undo()   # one step removes the strip and its image
    doc.recompute()
    result["after_undo"] = strips_in(design)

    # turn off: design.symmetry cleared (the key dropped), a strip is then added alone
    result["off_changed"] = design_model.set_symmetry(design, [])
    result["off_stored"] = "symmetry" in json.loads(design.DesignJson)
    result["off_undo"] = list(doc.UndoNames)[:1]
    design_model.add_strip(design, [ANCHOR])
    result["alone"] = strips_in(design)
    # a refused image: with a finite compatibility band, a strip near one end (symmetry off)
    # refuses the image of a strip near the other end; the design keeps neither, one line says why
    doc.undo()   # the strip added alone
    doc.recompute()
    design_model.set_options(design, compatibility_band=3.0)
    design_model.add_strip(design, [(-18.0, 0.0, 8.0, 0.0, 1.0, 0.0)])
    design_model.set_symmetry(design, mirror)
    before = design.DesignJson
    try:
        design_model.add_strip(design, [(15.5, 0.0, 8.0, 0.0, 1.0, 0.0)])
        result["refused"] = None
    except Exception as exc:
        result["refused"] = "{}: {}".format(type(exc).__name__, exc)
    result["refused_kept"] = design.DesignJson == before and strips_in(design) == 1

    # Auto weave takes the accepted reflection: every strip it adds comes with its mirror image
    import time
    from freecad.stripweave_wb import weave_job
    woven = design_model.create(sm, name="Woven")
    doc.recompute()
    design_model.set_symmetry(woven, mirror)
    t0 = time.time()
    weave_job.run(woven, max_strips=6)
    derived = woven.Proxy.derived(woven)
    loops = [s["points"] for s in derived.strips]
    result["woven"] = {"strips": len(loops), "seconds": time.time() - t0,
                       "mirror_error": loops_symmetry_error(loops, mirror[0]) if loops else None}
    result["ok"] = True
except Exception:
    result["error"] = traceback.format_exc()

with open(os.environ.get("STRIPWEAVE_HEADLESS_RESULT", "/tmp/stripweave_symmetry_headless.json"), "w") as f:
    json.dump(result, f, indent=1, default=str)
os._exit(0)
