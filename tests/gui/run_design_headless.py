"""App-side checks of the Design object without the GUI, run by
tests/gui/test_design_headless.py under ``freecadcmd`` (FreeCAD.GuiUp is 0:
recompute derives synchronously, no view provider).  A torus, its
SurfaceModel, a Design with a meridian strip: the Shape, undo/redo of an
added strip, a failing strip (design kept, error reported), save/reopen,
export/import.  Writes JSON to $STRIPWEAVE_HEADLESS_RESULT and exits with
os._exit."""

import json
import math
import os
import traceback

result = {"ok": False, "error": None}
WORKDIR = os.environ.get("STRIPWEAVE_HEADLESS_WORKDIR", "/tmp")


def wires_of(obj):
    return [{"closed": w.isClosed(), "length": w.Length} for w in obj.Shape.Wires]


try:
    import FreeCAD as App
    import Part
    from freecad.stripweave_wb import design_model, surface_model

    doc = App.newDocument("DesignHeadless")
    doc.UndoMode = 1  # freecadcmd documents start without undo
    torus = doc.addObject("Part::Feature", "Torus")
    torus.Shape = Part.makeTorus(10, 3)
    doc.recompute()
    sm = surface_model.create(torus, target_triangles=16000)
    doc.recompute()
    design = design_model.create(sm)
    doc.recompute()
    result["empty"] = {"wires": wires_of(design), "state": list(design.State), "status": design.Status}

    # a meridian strip through the API: one transaction
    design_model.add_strip(design, [(13, 0, 0, 0, 0, 1)])
    result["meridian"] = {"wires": wires_of(design), "strip_count": design.StripCount,
                          "state": list(design.State), "status": design.Status,
                          "undo_names": list(doc.UndoNames),
                          "summary": json.loads(design.Summary)}
    derived = design.Proxy.derived(design)
    result["meridian"]["derived_strips"] = len(derived.strips) if derived else None
    result["meridian"]["stripe_vertices"] = (int(sum(~(derived.strips[0]["across"] != derived.strips[0]["across"])))
                                             if derived and derived.strips else 0)
    result["expected_length"] = 2 * math.pi * 3

    # a second strip (the compatible loop through the outer equator), then undo / redo
    design_model.add_strip(design, [(0, 13, 0)])
    result["two"] = {"wires": wires_of(design), "strips_in_json": len(json.loads(design.DesignJson)["strips"])}
    doc.undo()
    result["after_undo"] = {"strips_in_json": len(json.loads(design.DesignJson)["strips"]),
                            "wires_restored": len(design.Shape.Wires)}
    doc.recompute()
    result["after_undo"]["wires_after_recompute"] = len(design.Shape.Wires)
    doc.redo()
    doc.recompute()
    result["after_redo"] = {"strips_in_json": len(json.loads(design.DesignJson)["strips"]),
                            "wires": len(design.Shape.Wires)}
    doc.undo()
    doc.recompute()

    # a strip no loop can make (along the meridian strip): add_strip refuses it ...
    try:
        design_model.add_strip(design, [(-13, 0, 0, 0, 0, 1)])
        result["refused"] = None
    except Exception as exc:
        result["refused"] = "{}: {}".format(type(exc).__name__, exc)
    result["after_refusal"] = {"strips_in_json": len(json.loads(design.DesignJson)["strips"]),
                               "undo_names": list(doc.UndoNames)}
    # ... and a design file holding it recomputes to an error that keeps the design
    data = json.loads(design.DesignJson)
    good = json.loads(design.DesignJson)
    data["strips"].append({"anchors": [{"point": [-13, 0, 0], "direction": [0, 0, 1]}], "note": "kept"})
    design_model.write_design(design, data, "Bad strip")
    result["bad"] = {"state": list(design.State), "status": design.Status,
                     "strips_in_json": len(json.loads(design.DesignJson)["strips"]),
                     "unknown_key_kept": json.loads(design.DesignJson)["strips"][-1].get("note"),
                     "wires": len(design.Shape.Wires), "strip_count": design.StripCount,
                     "summary_error": json.loads(design.Summary).get("error")}
    design_model.write_design(design, good, "Good again")
    result["repaired_state"] = list(design.State)

    # Boundary mirrors options.boundary
    design.Boundary = "trimmed"
    result["boundary_in_json"] = json.loads(design.DesignJson)["options"]["boundary"]
    design.Boundary = "aligned"
    doc.recompute()
    # Features off: a new field over the same loop engine
    engine = design.Proxy.cache().session.loop_session
    design.Features = False
    doc.recompute()
    result["features_off"] = {"state": list(design.State), "strip_count": design.StripCount,
                              "same_loop_engine": design.Proxy.cache().session.loop_session is engine}
    design.Features = True
    doc.recompute()

    # edit_strip: the meridian moved to phi = 90 degrees (one transaction), undone
    def anchors_in_json():
        return [[a["point"] + (a["direction"] or []) for a in st["anchors"]]
                for st in json.loads(design.DesignJson)["strips"]]
    before = anchors_in_json()
    design_model.edit_strip(design, 0, [(0, 13, 0, 0, 0, 1)])
    loop = design.Proxy.derived(design).strips[0]["points"]
    result["edited"] = {"anchors": anchors_in_json(), "undo": (doc.UndoNames or [None])[0],
                        "wires": len(design.Shape.Wires),
                        "max_abs_x": float(max(abs(p[0]) for p in loop))}
    doc.undo()
    doc.recompute()
    result["edit_undone"] = anchors_in_json() == before
    # an edit the design refuses (strip 2 made parallel to strip 1): the document unchanged
    design_model.add_strip(design, [(0, 13, 0)])
    two = design.DesignJson
    try:
        design_model.edit_strip(design, 1, [(0, 13, 0, 0, 0, 1)])
        result["edit_refused"] = None
    except Exception as exc:
        result["edit_refused"] = "{}: {}".format(type(exc).__name__, exc)
    result["edit_refused_unchanged"] = design.DesignJson == two and (doc.UndoNames or [None])[0] == "Add strip"
    doc.undo()
    doc.recompute()

    # set_options: the band in one transaction, the session takes it at the recompute
    design_model.set_options(design, compatibility_band=2.5)
    doc.recompute()
    session = design.Proxy.cache().session
    result["band"] = {"json": json.loads(design.DesignJson)["options"]["compatibility_band"],
                      "undo": (doc.UndoNames or [None])[0], "native": session.native.compatibility_band,
                      "strip_count": design.StripCount}
    try:
        design_model.set_options(design, compatibility_band=-1.0)
        result["bad_band"] = None
    except Exception as exc:
        result["bad_band"] = "{}: {}".format(type(exc).__name__, exc)
    result["bad_band_unchanged"] = json.loads(design.DesignJson)["options"]["compatibility_band"] == 2.5
    design_model.set_options(design, compatibility_band=None)
    doc.recompute()
    result["band_back"] = design.Proxy.cache().session.native.compatibility_band

    # export / import
    path = os.path.join(WORKDIR, "torus_design.json")
    design_model.export_design(design, path)
    exported = json.load(open(path))
    result["exported"] = {"strips": len(exported["strips"]), "model": exported.get("model")}
    design_model.remove_strip(design, 0)
    result["after_remove"] = len(design.Shape.Wires)
    design_model.import_design(design, path)
    result["after_import"] = {"wires": wires_of(design), "undo": (doc.UndoNames or [None])[0]}

    # save, reopen: the JSON and the strip come back; the session is rebuilt on demand
    json_before = design.DesignJson
    name = design.Name
    fcstd = os.path.join(WORKDIR, "design_headless.FCStd")
    doc.saveAs(fcstd)
    App.closeDocument(doc.Name)
    doc = App.openDocument(fcstd)
    design = doc.getObject(name)
    result["reopened"] = {
        "json_equal": design.DesignJson == json_before,
        "wires": wires_of(design),
        "derived_before": design.Proxy.derived(design) is not None,
        "is_design": design_model.is_design(design),
    }
    session = design.Proxy.session(design)
    result["reopened"]["session_strips"] = len(session.strips())
    result["reopened"]["session_length"] = session.strip(0)["length"] if session.strips() else None
    result["reopened"]["derived_after"] = design.Proxy.derived(design) is not None
    result["ok"] = True
except Exception:
    result["error"] = traceback.format_exc()
with open(os.environ["STRIPWEAVE_HEADLESS_RESULT"], "w") as f:
    json.dump(result, f, indent=1)
os._exit(0)
