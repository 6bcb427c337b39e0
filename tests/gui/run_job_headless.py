"""The main job's macro functions under freecadcmd (no GUI), run by
tests/gui/test_job_headless.py: on a generated part (job_part.py), Prepare
surface, a Design with one user strip, ``auto_weave(design)`` (the user's
strip kept first), ``layout_model.create(design)``,
``patches_model.create(layout)``, ``export_step(patches, path)`` (read back),
an input change (a strip removed) recomputing the layout, bad options, and
save / close / reopen.  Writes JSON to $STRIPWEAVE_HEADLESS_RESULT and exits
with os._exit."""

import json
import os
import sys
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

result = {"ok": False, "error": None}
WORKDIR = os.environ.get("STRIPWEAVE_HEADLESS_WORKDIR", "/tmp")


def shape_facts(shape):
    return {"faces": len(shape.Faces), "valid": bool(shape.isValid()) if not shape.isNull() else False,
            "type": shape.ShapeType if not shape.isNull() else None, "solids": len(shape.Solids),
            "volume": shape.Volume if not shape.isNull() and shape.Solids else None}


try:
    import FreeCAD as App
    import freecad.stripweave_wb as wb
    from freecad.stripweave_wb import design_model, layout_model, patches_model, surface_model
    import job_part

    doc = App.newDocument("JobHeadless")
    doc.UndoMode = 1
    part = job_part.make(doc)
    sm = surface_model.create(part, target_triangles=job_part.TRIANGLES)
    doc.recompute()
    design = design_model.create(sm)
    doc.recompute()
    design_model.add_strip(design, [job_part.USER_ANCHOR])
    user_anchors = json.loads(design.DesignJson)["strips"][0]["anchors"]

    # bad options: one line naming the option, nothing changed
    try:
        wb.auto_weave(design, max_stripz=3)
        result["bad_option"] = None
    except Exception as exc:
        result["bad_option"] = "{}: {}".format(type(exc).__name__, exc)
    result["after_bad_option"] = {"strips": len(json.loads(design.DesignJson)["strips"]),
                                  "undo": (doc.UndoNames or [None])[0]}

    weave = wb.auto_weave(design, **job_part.WEAVE_OPTIONS)
    data = json.loads(design.DesignJson)
    result["weave"] = {"strips": len(data["strips"]), "first_anchors": data["strips"][0]["anchors"],
                       "user_anchors": user_anchors, "stopped": weave.stopped,
                       "red": weave.assessment["colours"]["red"], "undo": (doc.UndoNames or [None])[0],
                       "state": list(design.State), "strip_count": design.StripCount, "status": design.Status}

    layout = layout_model.create(design)
    lj = json.loads(layout.LayoutJson)
    result["layout"] = {"valid": layout.Valid, "clean": layout.Clean, "patches": layout.PatchCount,
                        "edges": len(lj["edges"]), "vertices": len(lj["vertices"]),
                        "shape_edges": len(layout.Shape.Edges), "shape_vertices": len(layout.Shape.Vertexes),
                        "status": layout.Status, "regions": layout.Regions, "defects": list(layout.Defects),
                        "undo": (doc.UndoNames or [None])[0], "state": list(layout.State)}

    patches = patches_model.create(layout)
    wires = patches_model.wires_of(patches)
    fit = json.loads(patches.FitJson)
    result["patches"] = {**shape_facts(patches.Shape), "wires": len(wires.Shape.Wires) if wires else None,
                         "closed": patches.Closed, "max_deviation": float(patches.MaxDeviation),
                         "coverage": patches.Coverage, "tolerance": fit["tolerance"],
                         "colours": len(json.loads(patches.FaceColours)), "status": patches.Status,
                         "undo": (doc.UndoNames or [None])[0], "state": list(patches.State)}

    step = os.path.join(WORKDIR, "patches.step")
    result["step"] = wb.export_step(patches, step)
    try:
        wb.export_step(layout, step)
        result["step_of_layout"] = None
    except Exception as exc:
        result["step_of_layout"] = "{}: {}".format(type(exc).__name__, exc)

    # save, close, reopen: the design, the layout and the patches come back as saved
    before = {"design": design.DesignJson, "layout": layout.LayoutJson, "patch_faces": len(patches.Shape.Faces),
              "fit": patches.FitJson}
    names = (design.Name, layout.Name, patches.Name)
    fcstd = os.path.join(WORKDIR, "job_headless.FCStd")
    doc.saveAs(fcstd)
    App.closeDocument(doc.Name)
    doc = App.openDocument(fcstd)
    design, layout, patches = (doc.getObject(n) for n in names)
    result["reopened"] = {"design": design.DesignJson == before["design"],
                          "layout": layout.LayoutJson == before["layout"],
                          "layout_type": layout_model.is_layout(layout),
                          "patch_faces": len(patches.Shape.Faces) == before["patch_faces"],
                          "patches_type": patches_model.is_patches(patches),
                          "fit": patches.FitJson == before["fit"], "valid": patches.Shape.isValid()}

    # an input change recomputes the layout and the patches
    doc.UndoMode = 1
    n = len(json.loads(design.DesignJson)["strips"])
    design_model.remove_strip(design, n - 1)
    doc.recompute()
    result["after_change"] = {"strips": len(json.loads(design.DesignJson)["strips"]),
                              "layout_changed": layout.LayoutJson != before["layout"],
                              "layout_state": list(layout.State), "patches_state": list(patches.State),
                              "patches_status": patches.Status}
    result["ok"] = True
except Exception:
    result["error"] = traceback.format_exc()
with open(os.environ["STRIPWEAVE_HEADLESS_RESULT"], "w") as f:
    json.dump(result, f, indent=1, default=str)
os._exit(0)
