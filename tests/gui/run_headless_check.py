"""App-side checks of the SurfaceModel object without the GUI, run by
tests/gui/test_headless.py under ``freecadcmd`` (FreeCAD.GuiUp is 0: execute
builds synchronously, no view provider).  Writes JSON to
$STRIPWEAVE_HEADLESS_RESULT and exits with os._exit."""

import json
import os
import traceback

result = {"ok": False, "error": None}
try:
    import FreeCAD as App
    import Part
    from freecad.stripweave_wb import surface_model

    doc = App.newDocument("Headless")
    box = doc.addObject("Part::Box", "Box")
    doc.recompute()
    sm = surface_model.create(box, target_triangles=3000)
    doc.recompute()
    report = json.loads(sm.Report)
    result["report"] = report
    result["feature_counts"] = len(sm.FeatureCounts)
    result["up_to_date"] = sm.Proxy.is_up_to_date(sm)
    result["has_view_object"] = sm.ViewObject is not None
    # the source changes: recompute rebuilds
    box.Length = 20
    doc.recompute()
    result["diag_after_change"] = json.loads(sm.Report)["bbox_diagonal"]
    # bad input: recompute marks the object invalid instead of crashing
    empty = doc.addObject("Part::Feature", "Empty")
    empty.Shape = Part.Shape()
    bad = surface_model.create(empty)
    doc.recompute()
    result["bad_state"] = list(bad.State)
    result["bad_report"] = bad.Report
    # save + reload: proxy state is JSON, the native surface is rebuilt on demand
    path = os.path.join(os.environ.get("STRIPWEAVE_HEADLESS_WORKDIR", "/tmp"), "headless.FCStd")
    name = sm.Name
    doc.saveAs(path)
    App.closeDocument(doc.Name)
    doc = App.openDocument(path)
    sm = doc.getObject(name)
    result["reloaded_counts"] = len(sm.FeatureCounts)
    result["reloaded_cached"] = sm.Proxy.is_up_to_date(sm)
    surf = sm.Proxy.surface(sm)  # rebuilds (blocking) after a restore
    result["rebuilt_triangles"] = int(surf.report()["triangles"])
    result["ok"] = True
except Exception:
    result["error"] = traceback.format_exc()
with open(os.environ["STRIPWEAVE_HEADLESS_RESULT"], "w") as f:
    json.dump(result, f, indent=1)
os._exit(0)
