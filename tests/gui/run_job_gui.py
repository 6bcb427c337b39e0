"""GUI scenario of the main job driven by REAL input (xdotool under Xvfb),
executed by FreeCAD's GUI (started by tests/gui/test_job_gui.py):

    generated rounded box -> click it, Y P (Prepare surface) -> Y N (New design)
    -> Y A (Auto weave), Cancel clicked in the task panel: stops within 1 s,
       the design unchanged
    -> Y A again, to the end -> Y L (Show layout) -> Y F (Fit patches)
    -> Y S (Export STEP...), the path typed into the file dialog, Return
    -> the STEP reloads with the same face count, a valid solid
    -> Undo / Redo of Fit patches -> save, close, reopen: design, layout and
       patches as they were.

The document is checked after each step; screenshots layout.png,
patches.png and reopened.png go to $STRIPWEAVE_GUI_WORKDIR.
"""

import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import FreeCAD as App  # noqa: E402
import FreeCADGui as Gui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

import gui_harness as h  # noqa: E402
import job_part  # noqa: E402
from gui_harness import check  # noqa: E402

WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or "/tmp"


def shortcut(*keys):
    for k in keys:
        h.key(k)


def undo_top(doc):
    return (doc.UndoNames or [None])[0]


def objects(doc, test):
    return [o for o in doc.Objects if test(o)]


def wait_tasks(timeout=240):
    from freecad.stripweave_wb import builder, derive_async, tasks
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        h.pump(0.1)
        if not tasks.running() and not builder.active_builds() and not derive_async.pending():
            h.pump(0.3)
            if not tasks.running() and not builder.active_builds() and not derive_async.pending():
                return True
    return False


def cancel_button():
    """The Cancel button of the open task dialog (the progress panel)."""
    for b in Gui.getMainWindow().findChildren(QtGui.QPushButton):
        if b.isVisible() and b.text().replace("&", "") == "Cancel":
            return b
    return None


click_widget = h.click_widget


def type_into_dialog(path, out, tries=40):
    """Polled from a timer, which the modal file dialog's own event loop
    runs: once the dialog is up, real keys select its file name, type
    ``path`` and press Return (xdotool in the background: the dialog's loop
    must stay free to take them)."""
    w = QtGui.QApplication.activeModalWidget()
    if w is None:
        if tries > 0:
            QtCore.QTimer.singleShot(250, lambda: type_into_dialog(path, out, tries - 1))
        return
    out["dialog"] = type(w).__name__
    script = "sleep 0.5; xdotool key ctrl+a; xdotool type --delay 20 '{}'; sleep 0.3; xdotool key Return".format(path)
    out["typist"] = subprocess.Popen(["sh", "-c", script])


def select_part_by_click(view, part):
    Gui.Selection.clearSelection()
    centre = part.Shape.BoundBox.Center
    top = (centre.x, centre.y, part.Shape.BoundBox.ZMax)
    pos = h.screen_position(view, top)
    h.mouse_move(view, *pos)
    h.mouse_click(1)
    h.pump(0.3)
    return [o.Name for o in Gui.Selection.getSelection()] == [part.Name]


def cancel_auto_weave(doc, design):
    from freecad.stripweave_wb import tasks
    strips_before = design.DesignJson
    shortcut("y", "a")
    h.wait_until(lambda: any(t.key[-1:] == ("weave",) for t in tasks.running()), 30)
    running = [t for t in tasks.running() if t.key[-1:] == ("weave",)]
    if not check("Y A: Auto weave running in the background", running, tasks.running()):
        return
    task = running[0]
    h.wait_until(lambda: task.stage.startswith("weaving") or task.done(), 60)
    # Click soon: the weave of this small part takes under 2 s in all (1.6 s headless).
    h.pump(0.2)
    button = cancel_button()
    if not check("Auto weave: the progress panel has a Cancel button", button is not None and not task.done(),
                 (button, task.done())):
        return
    check("Auto weave: the GUI answers while weaving (progress shown)", "weaving" in task.stage, task.stage)
    click_widget(button)
    h.wait_until(task.done, 10)
    wait_tasks(30)
    seconds = task.cancel_seconds()
    h.result["info"]["cancel_seconds"] = seconds
    check("Cancel (real click): the weave stopped within 1 s", seconds is not None and seconds <= 1.0, seconds)
    check("Cancel: the design is unchanged", design.DesignJson == strips_before)
    check("Cancel: nothing to undo from the weave", undo_top(doc) != "Auto weave", doc.UndoNames)
    check("Cancel: the task panel closed", not Gui.Control.activeDialog())


def cancel_fit(doc, patches):
    """A tighter tolerance refits in the background: a real click on Cancel
    is taken (the result is dropped, Status says so; the native refit has no
    cancellation point, so it runs to its end first); the tolerance set
    back, the patches come back."""
    from freecad.stripweave_wb import tasks
    faces = len(patches.Shape.Faces)
    tolerance = json.loads(patches.FitJson)["tolerance"]
    patches.Tolerance = tolerance / 20   # a fit that takes a while
    doc.recompute()
    key = (doc.Name, patches.Name)
    h.wait_until(lambda: tasks.running(key), 10)
    running = tasks.running(key)
    if not check("tolerance changed: the fit runs again in the background", running, patches.Status):
        return
    task = running[0]
    h.wait_until(lambda: task.panel is not None or task.done(), 10)
    h.pump(0.5)   # the task view swaps dialogs: take the button of this one
    button = cancel_button()
    buttons = [b for b in Gui.getMainWindow().findChildren(QtGui.QPushButton)
               if b.isVisible() and b.text().replace("&", "") == "Cancel"]
    h.result["info"]["fit_panel"] = [task.panel is not None, task.done(), len(buttons),
                                     str(Gui.Control.activeDialog()),
                                     task.panel.form.isVisible() if task.panel is not None else None,
                                     task.panel.title.text() if task.panel is not None else None]
    if check("Fit patches: Cancel while fitting", button is not None and not task.done(), task.done()):
        click_widget(button)
        h.wait_until(task.done, 10)
        wait_tasks(30)
        seconds = task.cancel_seconds()
        h.result["info"]["fit_cancel_seconds"] = seconds
        h.result["info"]["fit_task_seconds"] = task.seconds
        # The native refit has no cancellation point: the Cancel is taken and the result
        # dropped, but the refit runs to its end (fit_cancel_seconds says how long after).
        check("Cancel (real click): taken, the refit's result dropped", seconds is not None, seconds)
        check("Cancel: Status says so", patches.Status.startswith("cancelled"), patches.Status)
    patches.Tolerance = 0.0
    doc.recompute()
    wait_tasks()
    check("tolerance back: the patches refitted", len(patches.Shape.Faces) == faces and patches.Shape.isValid(),
          (len(patches.Shape.Faces), patches.Status))


def scenario():
    from freecad.stripweave_wb import design_model, layout_model, patches_model, preferences
    from freecad.stripweave_wb.surface_model import is_surface_model
    Gui.activateWorkbench("StripWeaveWorkbench")
    preferences.save(target_triangles=job_part.TRIANGLES, max_strips=job_part.WEAVE_OPTIONS["max_strips"])
    doc = App.newDocument("StripWeaveJob")
    part = job_part.make(doc)
    view = Gui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    h.pump(0.5)

    check("click selects the part", select_part_by_click(view, part), Gui.Selection.getSelection())
    shortcut("y", "p")
    wait_tasks()
    models = objects(doc, is_surface_model)
    if not check("Y P: one SurfaceModel", len(models) == 1, [o.Name for o in doc.Objects]):
        return
    sm = models[0]
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(sm)
    shortcut("y", "n")
    wait_tasks()
    designs = design_model.designs_of(sm)
    if not check("Y N: one Design", len(designs) == 1 and undo_top(doc) == "New design", doc.UndoNames):
        return
    design = designs[0]
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(design)

    cancel_auto_weave(doc, design)

    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(design)
    t0 = time.monotonic()
    shortcut("y", "a")
    wait_tasks()
    h.result["info"]["auto_weave_seconds"] = time.monotonic() - t0
    strips = len(json.loads(design.DesignJson)["strips"])
    check("Y A: Auto weave added strips", strips > 0 and design.StripCount == strips, (strips, design.Status))
    check("Y A: one undoable 'Auto weave'", undo_top(doc) == "Auto weave", doc.UndoNames)
    h.result["info"]["design_status"] = design.Status

    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(design)
    shortcut("y", "l")
    wait_tasks()
    layouts = layout_model.layouts_of(design)
    if not check("Y L: one Layout", len(layouts) == 1, [o.Name for o in doc.Objects]):
        return
    layout = layouts[0]
    check("Show layout: valid, with patches", layout.Valid and layout.PatchCount > 0, layout.Status)
    check("Show layout: one undoable 'Show layout'", "Show layout" in doc.UndoNames[:2], doc.UndoNames)
    check("Show layout: edges and vertices in the Shape",
          len(layout.Shape.Edges) > 0 and len(layout.Shape.Vertexes) > 0, len(layout.Shape.Edges))
    check("Show layout: the tinted patches drawn", layout.ViewObject.Proxy.overlay.face_set.coordIndex.getNum() > 0)
    h.result["info"]["layout_status"] = layout.Status
    view.fitAll()
    Gui.Selection.clearSelection()   # the selection highlight would cover the tints
    shot = os.path.join(WORKDIR, "layout.png")
    check("screenshot layout.png", h.save_screenshot(view, shot), shot)

    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(layout)
    shortcut("y", "f")
    wait_tasks()
    found = patches_model.patches_of(layout)
    if not check("Y F: one Patches object", len(found) == 1, [o.Name for o in doc.Objects]):
        return
    patches = found[0]
    shape = patches.Shape
    check("Fit patches: a valid solid of B-spline faces",
          shape.ShapeType == "Solid" and shape.isValid() and len(shape.Faces) == layout.PatchCount,
          (shape.ShapeType, shape.isValid(), len(shape.Faces), layout.PatchCount, patches.Status))
    check("Fit patches: every face coloured by deviation",
          len(patches.ViewObject.DiffuseColor) == len(shape.Faces), len(patches.ViewObject.DiffuseColor))
    wires = patches_model.wires_of(patches)
    check("Fit patches: the patch wires as a compound", wires is not None and len(wires.Shape.Wires) == len(shape.Faces))
    check("Fit patches: one undoable 'Fit patches'", "Fit patches" in doc.UndoNames[:2], doc.UndoNames)
    h.result["info"]["patches_status"] = patches.Status
    Gui.Selection.clearSelection()
    shot = os.path.join(WORKDIR, "patches.png")
    check("screenshot patches.png", h.save_screenshot(view, shot), shot)

    # Export STEP through its shortcut and the file dialog, typed as a user would
    step = os.path.join(WORKDIR, "job.step")
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(patches)
    # The dialog is modal (a nested event loop): a timer in that loop types, as a user would.
    typed = {}
    QtCore.QTimer.singleShot(300, lambda: type_into_dialog(step, typed))
    shortcut("y", "s")
    h.wait_until(lambda: "typist" in typed and typed["typist"].poll() is not None, 30)
    check("Y S: the file dialog took the typed path", typed.get("dialog") == "QFileDialog", typed)
    wait_tasks(60)
    check("Export STEP: the file written", os.path.isfile(step), step)
    if os.path.isfile(step):
        import Part
        back = Part.Shape()
        back.read(step)
        check("STEP reloads with the same face count and a valid solid",
              len(back.Faces) == len(shape.Faces) and back.isValid() and len(back.Solids) == 1,
              (len(back.Faces), len(shape.Faces), back.isValid(), len(back.Solids)))

    # Undo / Redo of Fit patches
    doc.undo()
    h.pump(0.3)
    check("Undo: the patches go", not patches_model.patches_of(layout), [o.Name for o in doc.Objects])
    doc.redo()
    h.pump(0.3)
    check("Redo: the patches come back", len(patches_model.patches_of(layout)) == 1)

    cancel_fit(doc, patches)

    # save, close, reopen
    before = {"design": design.DesignJson, "layout": layout.LayoutJson, "faces": len(shape.Faces),
              "fit": patches.FitJson}
    names = (design.Name, layout.Name, patches.Name)
    fcstd = os.path.join(WORKDIR, "job.FCStd")
    doc.saveAs(fcstd)
    App.closeDocument(doc.Name)
    h.pump(0.5)
    doc = App.openDocument(fcstd)
    h.pump(1.0)
    design, layout, patches = (doc.getObject(n) for n in names)
    check("reopen: the design", design is not None and design.DesignJson == before["design"])
    check("reopen: the layout", layout is not None and layout_model.is_layout(layout)
          and layout.LayoutJson == before["layout"])
    check("reopen: the patches", patches is not None and patches_model.is_patches(patches)
          and len(patches.Shape.Faces) == before["faces"] and patches.FitJson == before["fit"]
          and patches.Shape.isValid())
    check("reopen: the patch colours", patches is not None
          and len(patches.ViewObject.DiffuseColor) == before["faces"], len(patches.ViewObject.DiffuseColor))
    view = Gui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    h.pump(0.5)
    shot = os.path.join(WORKDIR, "reopened.png")
    check("screenshot reopened.png", h.save_screenshot(view, shot), shot)
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
