"""The workbench's preferences under ``freecadcmd`` (run by
tests/gui/test_preferences.py, FREECAD_USER_HOME a throw-away folder): the
defaults written to FreeCAD's parameter tree are what the commands' code
uses: Prepare surface's SurfaceModel (target triangles, feature angle), New
design's boundary mode, the fitting tolerance.  Writes JSON to
$STRIPWEAVE_HEADLESS_RESULT and exits with os._exit."""

import json
import os
import traceback

result = {"error": None}
try:
    import FreeCAD as App
    from freecad.stripweave_wb import design_model, preferences, surface_model

    result["defaults"] = [preferences.target_triangles(), preferences.feature_angle(), preferences.tolerance(),
                          preferences.boundary_mode(), preferences.auto_weave_max_strips(),
                          preferences.auto_weave_crease_pairs()]
    grp = App.ParamGet("User parameter:BaseApp/Preferences/Mod/StripWeave")
    grp.SetInt("TargetTriangles", 3000)      # as the preferences page writes them
    grp.SetFloat("FeatureAngle", 40.0)
    grp.SetFloat("Tolerance", 0.02)
    grp.SetString("BoundaryMode", "trimmed")
    doc = App.newDocument("Preferences")
    box = doc.addObject("Part::Box", "Box")
    doc.recompute()
    sm = surface_model.create(box)           # what Prepare surface makes
    doc.recompute()
    result["surface_model"] = [int(sm.TargetTriangles), float(sm.FeatureAngle),
                               int(json.loads(sm.Report).get("triangles", 0))]
    design = design_model.create(sm)         # what New design makes
    doc.recompute()
    result["design"] = [json.loads(design.DesignJson)["options"]["boundary"], design.Boundary]
    result["tolerance"] = preferences.tolerance()
    preferences.save(max_strips=12)
    result["max_strips"] = preferences.auto_weave_max_strips()
    grp.SetBool("AutoWeaveCreasePairs", True)  # as the page's check box writes it
    from freecad.stripweave_wb import weave_job
    result["crease_pairs"] = weave_job.weave_options(crease_pairs=preferences.auto_weave_crease_pairs()).crease_pairs
    try:
        preferences.save(boundary_mode="sideways")
    except ValueError as exc:
        result["bad_mode"] = str(exc)
except Exception:
    result["error"] = traceback.format_exc()
with open(os.environ["STRIPWEAVE_HEADLESS_RESULT"], "w") as f:
    json.dump(result, f, indent=1)
os._exit(0)
