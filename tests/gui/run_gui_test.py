"""GUI scenario for the StripWeave workbench, executed by the FreeCAD GUI:

    xvfb-run -a -s "-screen 0 1280x800x24" freecad tests/gui/run_gui_test.py

(normally started by tests/gui/test_gui.py).  Environment:

    STRIPWEAVE_GUI_RESULT      JSON result file to write (required)
    STRIPWEAVE_GUI_SCREENSHOT  PNG screenshot to save (required)
    STRIPWEAVE_GUI_WORKDIR     scratch directory (default: next to the result)
    STRIPWEAVE_GUI_TIMEOUT     seconds before the watchdog gives up (default 150)
    STRIPWEAVE_REPO            repo under test (checked against the loaded workbench)

It activates the workbench, builds four generated parts (a box, a box with a
hole, an open box, a mesh box), runs *Prepare surface* on each through the command,
checks the overlay nodes in the scene graph, the progress panel, Cancel,
undo, bad input (empty shape, wire without faces), save/reload, saves a
screenshot, writes the JSON result and exits with os._exit.
"""

import json
import os
import shutil
import sys
import tempfile
import threading
import time

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import gui_harness as h  # noqa: E402
from gui_harness import check, pump, report_view_text, result  # noqa: E402,F401

RESULT = os.environ.get("STRIPWEAVE_GUI_RESULT") or os.path.join(tempfile.gettempdir(), "stripweave_gui_result.json")
SCREENSHOT = os.environ.get("STRIPWEAVE_GUI_SCREENSHOT") or os.path.join(tempfile.gettempdir(), "stripweave_gui_test.png")
WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or os.path.dirname(os.path.abspath(RESULT))
TIMEOUT = float(os.environ.get("STRIPWEAVE_GUI_TIMEOUT", "150"))
HUMAN_COPY = "/tmp/stripweave_gui.png"

WB = "StripWeaveWorkbench"
CMD = "StripWeave_PrepareSurface"



def surface_models(doc):
    from freecad.stripweave_wb.surface_model import is_surface_model
    return [o for o in doc.Objects if is_surface_model(o)]


def overlay_counts(root):
    """(#feature polylines, #boundary polylines) found by node name below root."""
    from freecad.stripweave_wb import overlay
    counts = []
    for name in (overlay.FEATURES_NODE, overlay.BOUNDARIES_NODE):
        nodes = overlay.find_nodes(root, name)
        if len(nodes) != 1:
            counts.append(None)
            continue
        ls = overlay.line_set_of(nodes[0])
        counts.append(ls.numVertices.getNum() if ls is not None else None)
    return tuple(counts)


def close_message_boxes():
    from freecad.stripweave_wb import messages
    texts = []
    for box in messages.open_message_boxes():
        texts.append(box.text())
        box.done(0)
    pump(0.1)
    return texts


def run_prepare(doc, obj, expect_model=True):
    """Select obj, run the command, check the progress panel, wait."""
    from freecad.stripweave_wb import builder
    before = set(o.Name for o in surface_models(doc))
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(obj)
    Gui.runCommand(CMD)
    running = builder.active_builds()
    if expect_model:
        check("{}: build started".format(obj.Label), len(running) == 1, len(running))
        if running:
            panel = running[0].panel
            check("{}: progress task panel shown".format(obj.Label),
                  panel is not None and Gui.Control.activeDialog(), panel)
    t0 = time.monotonic()
    finished = builder.wait_for_builds(TIMEOUT / 2)
    check("{}: build finished".format(obj.Label), finished, "{:.2f} s".format(time.monotonic() - t0))
    pump(0.2)
    new = [o for o in surface_models(doc) if o.Name not in before]
    return new[0] if len(new) == 1 else None


PREFERRED_TRIANGLES = 8000


def preferences_page():
    """Edit > Preferences lists the StripWeave page (FreeCAD loads its
    settings); set on the page, a default is what Prepare surface uses."""
    from freecad.stripweave_wb import preferences
    seen = {}

    def inspect_dialog():
        dialog = QtGui.QApplication.activeModalWidget()
        if dialog is None:
            QtCore.QTimer.singleShot(100, inspect_dialog)
            return
        page = dialog.findChild(QtGui.QWidget, "StripWeavePreferences")
        spin = page.findChild(QtGui.QSpinBox, "TargetTriangles") if page is not None else None
        seen["page"] = page is not None
        seen["loaded"] = spin.value() if spin is not None else None
        dialog.reject()

    QtCore.QTimer.singleShot(300, inspect_dialog)
    Gui.runCommand("Std_DlgPreferences")
    pump(0.3)
    check("preferences: the StripWeave page is in Edit > Preferences", seen.get("page"), seen)
    check("preferences: the page shows the stored default", seen.get("loaded") == 30000, seen)
    page = preferences._page_class()()
    page.loadSettings()
    page.triangles.setValue(PREFERRED_TRIANGLES)
    page.saveSettings()
    check("preferences: saved in the parameter tree",
          App.ParamGet(preferences.PARAM_PATH).GetInt("TargetTriangles") == PREFERRED_TRIANGLES)
    check("preferences: Auto weave's pairs of loops are off by default", not page.crease_pairs.isChecked())
    page.crease_pairs.setChecked(True)
    page.saveSettings()
    check("preferences: the pairs check box is saved", preferences.auto_weave_crease_pairs() is True)
    page.crease_pairs.setChecked(False)
    page.saveSettings()


def prepare_again(doc, box, sm):
    """Prepare surface on a prepared part: the SurfaceModel is reused (up to
    date), or rebuilt in place when other parameters are given."""
    from freecad.stripweave_wb import builder, commands
    if not check("prepare again: the box has a SurfaceModel", sm is not None):
        return
    n_models = len(surface_models(doc))
    before = len(report_view_text())
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(box)
    Gui.runCommand(CMD)
    pump(0.2)
    check("prepare again: no build, no second SurfaceModel",
          not builder.active_builds() and len(surface_models(doc)) == n_models,
          (len(builder.active_builds()), len(surface_models(doc))))
    check("prepare again: reported as reused", "reused" in report_view_text()[before:],
          report_view_text()[before:][-300:])
    check("prepare again: the SurfaceModel selected", Gui.Selection.getSelection() == [sm])
    ctl = commands.prepare_surface(box, target_triangles=6000)
    builder.wait_for_builds(TIMEOUT / 2)
    pump(0.2)
    check("prepare again with other parameters: the same SurfaceModel rebuilt",
          ctl is not None and len(surface_models(doc)) == n_models and sm.TargetTriangles == 6000
          and sm.Proxy.is_up_to_date(sm), (ctl, len(surface_models(doc)), sm.TargetTriangles))
    check("prepare again: undoable", (doc.UndoNames or [None])[0] == "Prepare surface", doc.UndoNames)


def make_parts(doc):
    import Part
    parts = {}
    box = doc.addObject("Part::Box", "Box")
    box.Length = box.Width = box.Height = 10
    parts["box"] = box
    holed = Part.makeBox(10, 10, 10, App.Vector(15, 0, 0)).cut(
        Part.makeCylinder(3, 10, App.Vector(20, 5, 0)))
    obj = doc.addObject("Part::Feature", "HoledBox")
    obj.Shape = holed
    parts["holed"] = obj
    faces = Part.makeBox(10, 10, 10, App.Vector(30, 0, 0)).Faces
    top = [f for f in faces if abs(f.CenterOfMass.z - 10) < 1e-9]
    open_box = Part.Shell([f for f in faces if not any(f.isSame(t) for t in top)])
    obj = doc.addObject("Part::Feature", "OpenBox")
    obj.Shape = open_box
    parts["open"] = obj
    import Mesh
    mesh = Mesh.createBox(10, 10, 10)
    mesh.translate(50, 5, 5)  # createBox is centred on the origin
    obj = doc.addObject("Mesh::Feature", "MeshBox")
    obj.Mesh = mesh
    parts["mesh"] = obj
    doc.recompute()
    return parts


def scenario():
    result["info"]["freecad"] = ".".join(App.Version()[:3])
    # 1. workbench
    check("workbench registered", WB in Gui.listWorkbenches(), sorted(Gui.listWorkbenches()))
    Gui.activateWorkbench(WB)
    pump(0.2)
    check("workbench active", Gui.activeWorkbench().name() == WB, Gui.activeWorkbench().name())
    check("command registered", CMD in Gui.listCommands())
    tb = [t for t in Gui.getMainWindow().findChildren(QtGui.QToolBar) if t.windowTitle() == "StripWeave"]
    check("toolbar present", len(tb) == 1 and tb[0].isVisible(), len(tb))

    import freecad.stripweave_wb as wb
    repo = os.environ.get("STRIPWEAVE_REPO")
    if repo:
        check("workbench loaded from the repo under test",
              os.path.realpath(wb.REPO_ROOT) == os.path.realpath(repo), wb.REPO_ROOT)
    import stripweave
    result["info"]["stripweave"] = getattr(stripweave, "__file__", "?")
    from freecad.stripweave_wb import builder, overlay

    preferences_page()
    doc = App.newDocument("StripWeaveGuiTest")
    parts = make_parts(doc)
    Gui.activeDocument().activeView().viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    pump(0.3)

    # 2. prepare surface on each part
    models = {}
    for key in ("box", "holed", "open", "mesh"):
        src = parts[key]
        sm = run_prepare(doc, src)
        if not check("{}: SurfaceModel created".format(src.Label), sm is not None):
            continue
        models[key] = sm
        check("{}: Source link".format(src.Label), sm.Source == src)
        report = json.loads(sm.Report) if sm.Report else {}
        result["info"]["report_" + key] = report
        feats, bounds = overlay_counts(sm.ViewObject.RootNode)
        result["info"]["overlay_" + key] = [feats, bounds]
        check("{}: overlay feature curves match report".format(src.Label),
              feats is not None and feats == report.get("feature_curves"), (feats, report.get("feature_curves")))
        check("{}: overlay boundary loops match report".format(src.Label),
              bounds is not None and bounds == report.get("boundary_loops"), (bounds, report.get("boundary_loops")))
        if key == "box":
            check("box: built at the preferred target triangles",
                  sm.TargetTriangles == PREFERRED_TRIANGLES, sm.TargetTriangles)
            check("box: 12 feature curves", feats == 12, feats)
            check("box: no boundary loop", bounds == 0, bounds)
        if key == "mesh":
            check("mesh box: 12 feature curves", feats == 12, feats)
        if key == "open":
            check("open box: one boundary loop", bounds == 1, bounds)
            check("open box: 8 feature curves", feats == 8, feats)
        check("{}: report printed".format(src.Label),
              "surface model '{}'".format(sm.Label) in report_view_text())

    sg = Gui.activeDocument().activeView().getSceneGraph()
    n_feat = len(overlay.find_nodes(sg, overlay.FEATURES_NODE))
    n_bound = len(overlay.find_nodes(sg, overlay.BOUNDARIES_NODE))
    check("overlay nodes in the 3D view's scene graph", n_feat == len(models) == n_bound == 4, (n_feat, n_bound))
    check("undo entry 'Prepare surface'", (doc.UndoNames or [None])[0] == "Prepare surface", doc.UndoNames)
    # undo removes the last SurfaceModel, redo restores it with its overlay
    n_models = len(surface_models(doc))
    doc.undo()
    pump(0.1)
    check("undo removes the SurfaceModel", len(surface_models(doc)) == n_models - 1)
    doc.redo()
    pump(0.1)
    redone = [o for o in surface_models(doc) if o.Source == parts["mesh"]]
    check("redo restores it with its overlay",
          len(redone) == 1 and overlay_counts(redone[0].ViewObject.RootNode)[0] == 12,
          [overlay_counts(o.ViewObject.RootNode) for o in redone])
    check("no message box after good input", not close_message_boxes())

    # 3. screenshot (before the error cases: nothing but the parts and overlays)
    view = Gui.activeDocument().activeView()
    Gui.Selection.clearSelection()
    view.viewIsometric()
    view.fitAll()
    pump(0.5)
    view.saveImage(SCREENSHOT, 1024, 768, "White")
    check("screenshot saved", os.path.isfile(SCREENSHOT) and os.path.getsize(SCREENSHOT) > 5000,
          os.path.getsize(SCREENSHOT) if os.path.isfile(SCREENSHOT) else None)
    try:
        shutil.copyfile(SCREENSHOT, HUMAN_COPY)
    except OSError:
        pass

    # 4. prepare again: the part keeps its one SurfaceModel
    prepare_again(doc, parts["box"], models.get("box"))

    # cancel: press Cancel in the progress panel right away (a part not prepared yet)
    import Part
    cyl = doc.addObject("Part::Feature", "Cylinder")
    cyl.Shape = Part.makeCylinder(4, 12, App.Vector(0, 30, 0))
    doc.recompute()
    n_models = len(surface_models(doc))
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(cyl)
    Gui.runCommand(CMD)
    running = builder.active_builds()
    cancel_button = None
    for bb in Gui.getMainWindow().findChildren(QtGui.QDialogButtonBox):
        btn = bb.button(QtGui.QDialogButtonBox.Cancel)
        if btn is not None:  # not shown yet: no events processed since runCommand
            cancel_button = btn
    check("cancel: Cancel button found in the task panel", cancel_button is not None)
    t_cancel = time.monotonic()
    if cancel_button is not None:
        cancel_button.click()
    elif running and running[0].panel is not None:
        running[0].panel.reject()
    check("cancel: progress.cancel() called", bool(running) and running[0].job.cancelled)
    if running and not running[0].job.done():
        check("cancel: the panel stays open while the build stops",
              bool(Gui.Control.activeDialog()) and "cancelling" in running[0].panel.stage.text(),
              running[0].panel.stage.text())
    builder.wait_for_builds(TIMEOUT / 2)
    result["info"]["cancel_to_stopped_s"] = round(time.monotonic() - t_cancel, 3)
    pump(0.3)
    check("cancel: the build thread stopped", bool(running) and running[0].job.done())
    check("cancel: no SurfaceModel added", len(surface_models(doc)) == n_models)
    check("cancel: reported", "cancelled" in report_view_text())
    check("cancel: task panel closed", not Gui.Control.activeDialog())

    # restart right after a cancel: the new build waits for the old one, never two at once
    from freecad.stripweave_wb import commands
    first = commands.prepare_surface(cyl)
    first.cancel()
    second = commands.prepare_surface(cyl)
    most = 0
    while builder.active_builds():
        most = max(most, sum(1 for t in threading.enumerate() if t.name == "StripWeave surface build"))
        pump(0.02)
    pump(0.3)
    result["info"]["restart_builds_at_once"] = most
    check("restart: never two builds of the part at once", most == 1, most)
    check("restart: the second build made the one SurfaceModel",
          second is not first and len([o for o in surface_models(doc) if o.Source == cyl]) == 1,
          [o.Label for o in surface_models(doc)])

    # 5. bad input: an empty shape and a wire (no faces)
    import Part
    empty = doc.addObject("Part::Feature", "Empty")
    empty.Shape = Part.Shape()
    wire = doc.addObject("Part::Feature", "JustAWire")
    wire.Shape = Part.Wire(Part.makeCircle(5, App.Vector(0, 30, 0)))
    doc.recompute()
    for bad in (empty, wire):
        n_models = len(surface_models(doc))
        before = len(report_view_text())
        run_prepare(doc, bad, expect_model=False)
        new_text = "\n".join(l for l in report_view_text()[before:].splitlines()
                             if "StripWeave:" in l and "GUITEST" not in l)
        boxes = close_message_boxes()
        result["info"]["error_" + bad.Name] = {"report_view": new_text.strip(), "message_boxes": boxes}
        check("{}: error in report view".format(bad.Label), bad.Label in new_text, new_text.strip())
        check("{}: message box shown".format(bad.Label), len(boxes) == 1, boxes)
        check("{}: no SurfaceModel added".format(bad.Label), len(surface_models(doc)) == n_models)
    check("nothing selected: error",
          _run_without_selection(), "")
    close_message_boxes()

    # 6. save, close, reopen: overlay restored from the stored curves
    path = os.path.join(WORKDIR, "stripweave_gui_test.FCStd")
    doc.saveAs(path)
    App.closeDocument(doc.Name)
    pump(0.3)
    doc = App.openDocument(path)
    pump(0.5)
    restored = {o.Source.Name: o for o in surface_models(doc) if o.Source}
    sm = restored.get("Box")
    if check("reload: SurfaceModel restored", sm is not None, sorted(restored)):
        feats, bounds = overlay_counts(sm.ViewObject.RootNode)
        check("reload: overlay restored (12 feature curves)", feats == 12, feats)
        check("reload: display mode", sm.ViewObject.DisplayMode == "Overlay", sm.ViewObject.DisplayMode)
        # changing a parameter rebuilds on a worker thread
        sm.TargetTriangles = 5000
        doc.recompute()
        pump(0.1)
        check("recompute after parameter change starts a rebuild", len(builder.active_builds()) == 1,
              len(builder.active_builds()))
        builder.wait_for_builds(TIMEOUT / 2)
        pump(0.2)
        check("rebuild: surface cached and up to date", sm.Proxy.is_up_to_date(sm))
        check("rebuild: overlay still 12 feature curves", overlay_counts(sm.ViewObject.RootNode)[0] == 12)
    App.closeDocument(doc.Name)


def _run_without_selection():
    Gui.Selection.clearSelection()
    before = len(report_view_text())
    Gui.runCommand(CMD)
    pump(0.2)
    return "Select exactly one" in report_view_text()[before:]


h.run(scenario)
