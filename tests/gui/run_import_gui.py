"""GUI scenario: Import design of a design the `stripweave weave` command
wrote, while the Design strips tool runs on a design with other options;
executed by FreeCAD's GUI (normally started by tests/gui/test_import_gui.py):

    xvfb-run -a -s "-screen 0 1280x800x24" freecad tests/gui/run_import_gui.py

Environment: that of gui_harness.py, plus STRIPWEAVE_GUI_DESIGN (the woven
design.json), STRIPWEAVE_GUI_MODEL (the model file it was woven on),
STRIPWEAVE_GUI_TRIANGLES (the solver mesh size it was woven at).

A filleted box: Prepare surface, a design with one hand-made strip (default
compatibility options), the tool started; Import design (the command, its
file dialog answered with the woven file): every woven strip is derived, the
session takes the file's compatibility options, the panel lists them all.
Then the saved Status is made stale, the document saved and reopened: after
the background derivation Status and StripCount are the derived ones again.
Last, the SurfaceModel is deleted (Std_Delete, its dependency question
answered Yes): a one-line message, the Design's Status says what to do, no
traceback.
"""

import json
import os
import sys

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import FreeCAD as App  # noqa: E402
import FreeCADGui as Gui  # noqa: E402
from PySide import QtCore  # noqa: E402

import gui_harness as h  # noqa: E402
from gui_harness import check  # noqa: E402

DESIGN = os.environ.get("STRIPWEAVE_GUI_DESIGN", "")
MODEL = os.environ.get("STRIPWEAVE_GUI_MODEL", "")
TRIANGLES = int(os.environ.get("STRIPWEAVE_GUI_TRIANGLES", "4000"))
WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or "/tmp"
HAND_STRIP = {"anchors": [{"point": [5, 5, 10], "direction": [1, 0, 0]}]}


def import_while_the_tool_runs(doc, design, woven):
    from freecad.stripweave_wb import design_commands, design_tool
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(design)
    Gui.runCommand("StripWeave_DesignStrips")
    tool = design_tool.active_tool()
    if not check("tool started and derived", tool is not None and tool.wait_idle(90), design.Status):
        return None
    angle_before = tool.cache.session.native.compatibility_angle
    design_commands._file_dialog = lambda *args, **kwargs: DESIGN  # what the user picks
    Gui.runCommand("StripWeave_ImportDesign")
    h.pump(0.3)
    tool.wait_idle(120)
    n = len(woven["strips"])
    h.result["info"]["import"] = {"strips": n, "StripCount": design.StripCount, "Status": design.Status,
                                  "angle_before": angle_before}
    check("import: undoable 'Import design'", (doc.UndoNames or [None])[0] == "Import design", doc.UndoNames)
    check("import: every woven strip derived", design.StripCount == n, (design.StripCount, n, design.Status))
    check("import: no error", not design.Status.startswith("error") and "Invalid" not in design.State,
          design.Status)
    native = tool.cache.session.native
    check("import: the running session took the file's compatibility options",
          abs(native.compatibility_angle - woven["options"]["compatibility_angle_deg"]) < 1e-9
          and abs(native.compatibility_band - woven["options"]["compatibility_band"]) < 1e-9,
          (angle_before, native.compatibility_angle, native.compatibility_band))
    check("import: the panel lists every strip", tool.panel.row_count() == n, tool.panel.row_count())
    tool.close()
    return design.Status


def reopen_refreshes_status(doc, design, status):
    from freecad.stripweave_wb import builder, derive_async
    name, strips = design.Name, design.StripCount
    design.Status = "error: stale status saved with the document"
    path = os.path.join(WORKDIR, "imported.FCStd")
    doc.saveAs(path)
    App.closeDocument(doc.Name)
    h.pump(0.3)
    doc = App.openDocument(path)
    h.pump(0.3)
    done = h.wait_until(lambda: not derive_async.pending() and not builder.active_builds(), 120)
    h.pump(0.3)
    d = doc.getObject(name)
    check("reopen: background derivation finished", done)
    check("reopen: Status refreshed after the derivation", d.Status == status, d.Status)
    check("reopen: StripCount as derived", d.StripCount == strips, d.StripCount)
    delete_surface_model(doc, d)
    App.closeDocument(doc.Name)


def answer_yes_to_modal_dialogs():
    from PySide import QtGui
    box = QtGui.QApplication.activeModalWidget()
    if isinstance(box, QtGui.QMessageBox):
        h.result["info"].setdefault("delete_dialog", []).append(box.text()[:200])
        yes = box.button(QtGui.QMessageBox.Yes)
        (yes or box.defaultButton()).click()
    QtCore.QTimer.singleShot(100, answer_yes_to_modal_dialogs)


def delete_surface_model(doc, design):
    sm = design.Surface
    before = len(h.report_view_text())
    QtCore.QTimer.singleShot(100, answer_yes_to_modal_dialogs)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(sm)
    Gui.runCommand("Std_Delete")
    h.pump(0.3)
    doc.recompute()
    h.pump(0.3)
    text = h.report_view_text()[before:]
    h.result["info"]["delete_report"] = text[-800:]
    check("delete SurfaceModel: deleted", design.Surface is None)
    check("delete SurfaceModel: the design says it has no surface model",
          design.Status.startswith("error: no SurfaceModel linked") and design.Surface is None, design.Status)
    check("delete SurfaceModel: a message names the design", design.Label in text and "no surface model" in text,
          text[-400:])
    check("delete SurfaceModel: no traceback", "Traceback" not in text, text[-800:])


def scenario():
    from freecad.stripweave_wb import design_commands
    Gui.activateWorkbench("StripWeaveWorkbench")
    with open(DESIGN) as f:
        woven = json.load(f)
    check("woven design has several strips", len(woven["strips"]) >= 4, len(woven["strips"]))
    doc = App.newDocument("StripWeaveImport")
    import Part
    part = doc.addObject("Part::Feature", "Part")
    part.Shape = Part.read(MODEL)
    doc.recompute()
    Gui.activeDocument().activeView().viewIsometric()
    Gui.activeDocument().activeView().fitAll()
    sm = h.prepared(doc, part, TRIANGLES)
    if not check("part prepared", sm is not None):
        return
    design = design_commands.new_design(sm, {"format": "stripweave-design", "version": 1, "strips": [HAND_STRIP]})
    check("hand-made design derived", design.StripCount == 1, design.Status)
    status = import_while_the_tool_runs(doc, design, woven)
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])
    if status is not None:
        reopen_refreshes_status(doc, design, status)


h.run(scenario)
