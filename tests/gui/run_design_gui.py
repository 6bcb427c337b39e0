"""GUI scenario for designs (the Design object, its stripes overlay and the
"Design strips" tool), executed by the FreeCAD GUI:

    xvfb-run -a -s "-screen 0 1280x800x24" freecad tests/gui/run_design_gui.py

(normally started by tests/gui/test_design_gui.py).  Environment:

    STRIPWEAVE_GUI_RESULT       JSON result file to write (required)
    STRIPWEAVE_GUI_SCREENSHOT   PNG of the torus design (default /tmp/stripweave_design_gui.png)
    STRIPWEAVE_GUI_SCREENSHOT2  PNG of the cube design (default /tmp/stripweave_design_box.png)
    STRIPWEAVE_GUI_WORKDIR      scratch directory (default: next to the result)
    STRIPWEAVE_GUI_TIMEOUT      seconds before the watchdog gives up (default 250)

A torus: Prepare surface, New design, Design strips; hover (through the
tool's API and through a real mouse move), Ctrl+wheel alternatives, two
clicks add two strips, Remove in the panel, undo, Esc; screenshots of the
preview (one strip, the proposal through a second point) and of the design.  Then a
cube with three belts (eight +1/4 singularities) and a second screenshot;
save and reopen (the stripes are derived again in the background).  Writes
the JSON result and exits with os._exit.
"""

import json
import math
import os
import shutil
import sys
import tempfile
import time

import numpy as np

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import gui_harness as h  # noqa: E402
from gui_harness import check, dist, prepared, pump, report_view_text, result, wait_until  # noqa: E402,F401

RESULT = os.environ.get("STRIPWEAVE_GUI_RESULT") or os.path.join(tempfile.gettempdir(), "stripweave_design_result.json")
SHOT_TORUS = os.environ.get("STRIPWEAVE_GUI_SCREENSHOT") or "/tmp/stripweave_design_gui.png"
SHOT_BOX = os.environ.get("STRIPWEAVE_GUI_SCREENSHOT2") or "/tmp/stripweave_design_box.png"
WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or os.path.dirname(os.path.abspath(RESULT))
TIMEOUT = float(os.environ.get("STRIPWEAVE_GUI_TIMEOUT", "250"))
SHOT_PREVIEW = os.path.join(os.path.dirname(os.path.abspath(SHOT_TORUS)), "stripweave_design_preview.png")
SHOT_WINDOW = os.path.join(os.path.dirname(os.path.abspath(SHOT_TORUS)), "stripweave_design_window.png")
HUMAN_COPIES = {SHOT_TORUS: "/tmp/stripweave_design_gui.png", SHOT_BOX: "/tmp/stripweave_design_box.png",
                SHOT_PREVIEW: "/tmp/stripweave_design_preview.png"}

WB = "StripWeaveWorkbench"
DESIGN_COMMANDS = ["StripWeave_NewDesign", "StripWeave_DesignStrips", "StripWeave_RemoveStrip",
                   "StripWeave_ImportDesign", "StripWeave_ExportDesign"]
CUBE_BELTS = [[(5, 5, 10, 1, 0, 0)], [(5, 3, 0, 0, 1, 0)], [(3, 0, 5, 1, 0, 0)]]

EXPECTED_ERRORS = []  # (start, end) spans of the report view text where errors are the point


def screen_pick(tool, view, point):
    """Coin screen position (origin bottom left) whose pick is ``point``, or None."""
    x, y = view.getPointOnScreen(App.Vector(*point))
    height = view.getSize()[1]
    for cx, cy in ((x, y), (x, height - 1 - y)):
        p = tool.pick(cx, cy)
        if p is not None and dist(p, point) < 0.5:
            return int(cx), int(cy)
    return None


def overlay_state(vobj):
    from freecad.stripweave_wb import design_overlay as ov
    from freecad.stripweave_wb import overlay
    root = vobj.RootNode
    out = {}
    for key, name in (("stripes", ov.STRIPES_NODE), ("loops", ov.LOOPS_NODE),
                      ("singularities", ov.SINGULARITIES_NODE)):
        nodes = overlay.find_nodes(root, name)
        out[key + "_nodes"] = len(nodes)
    p = vobj.Proxy.overlay
    out["stripe_triangles"] = p.stripes.triangle_count()
    out["loop_polylines"] = p.loops.polyline_count()
    out["singularity_points"] = p.singularities.point_count()
    return out


def viewport_widget():
    from freecad.stripweave_wb.view_input import viewport_widgets
    ws = [w for w in viewport_widgets() if not isinstance(w, QtGui.QGraphicsView)]
    return ws[0] if ws else None


def to_qt(widget, view, x, y):
    """Coin position (device pixels, origin bottom left) -> Qt widget position
    (logical pixels, origin top left)."""
    dpr = widget.devicePixelRatioF() if hasattr(widget, "devicePixelRatioF") else 1.0
    return x / dpr, (view.getSize()[1] - 1 - y) / dpr


def send_mouse_move(widget, x, y):
    ev = QtGui.QMouseEvent(QtCore.QEvent.MouseMove, QtCore.QPointF(x, y), QtCore.Qt.NoButton,
                           QtCore.Qt.NoButton, QtCore.Qt.NoModifier)
    QtGui.QApplication.sendEvent(widget, ev)


def send_ctrl_wheel(widget, x, y, delta):
    ev = QtGui.QWheelEvent(QtCore.QPointF(x, y), QtCore.QPointF(widget.mapToGlobal(QtCore.QPoint(int(x), int(y)))),
                           QtCore.QPoint(0, 0), QtCore.QPoint(0, delta), QtCore.Qt.NoButton,
                           QtCore.Qt.ControlModifier, QtCore.Qt.NoScrollPhase, False)
    QtGui.QApplication.sendEvent(widget, ev)


def picture_shows_the_loops(label, path, view, design):
    """What the screenshot must show: each strip's loop in its colour."""
    from freecad.stripweave_wb import stripe_pattern
    d = design.Proxy.derived(design)
    if not check(label + ": design derived", d is not None):
        return
    loops = [s["points"] for s in d.strips]
    h.check_loops_in_picture(label, path, view, loops, [stripe_pattern.loop_color(i) for i in range(len(loops))],
                             d.vertices[::max(1, len(d.vertices) // 400)], design.Shape.BoundBox.DiagonalLength
                             or float(np.linalg.norm(np.ptp(d.vertices, axis=0))))


def save_screenshot(view, path, refit=True, view_size=False):
    """``view_size``: the image has the view's size, so a Coin position is
    its pixel (for checks of what it shows); else 1024 x 768."""
    Gui.Selection.clearSelection()
    if refit:
        view.viewIsometric()
        view.fitAll()
    pump(0.5)
    if view_size:
        h.save_screenshot(view, path)
    else:
        view.saveImage(path, 1024, 768, "White")
    ok = os.path.isfile(path) and os.path.getsize(path) > 5000
    copy = HUMAN_COPIES.get(path)
    if ok and copy and os.path.abspath(copy) != os.path.abspath(path):
        try:
            shutil.copyfile(path, copy)
        except OSError:
            pass
    return ok


def torus_scenario(doc):
    from freecad.stripweave_wb import design_model, design_overlay, design_tool, overlay

    torus = h.torus_in_view(doc)
    view = Gui.activeDocument().activeView()
    sm = prepared(doc, torus, 16000)
    if not check("torus: SurfaceModel prepared", sm is not None):
        return None

    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(sm)
    Gui.runCommand("StripWeave_NewDesign")
    pump(0.2)
    designs = design_model.designs_of(sm)
    if not check("New design: one Design on the SurfaceModel", len(designs) == 1, len(designs)):
        return None
    design = designs[0]
    check("New design: undoable", (doc.UndoNames or [None])[0] == "New design", doc.UndoNames)
    check("New design: display mode Stripes", design.ViewObject.DisplayMode == "Stripes",
          design.ViewObject.DisplayMode)

    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(design)
    Gui.runCommand("StripWeave_DesignStrips")
    tool = design_tool.active_tool()
    if not check("Design strips: tool started", tool is not None):
        return None
    check("Design strips: task panel open", bool(Gui.Control.activeDialog()))
    check("Design strips: preview node in the scene graph",
          len(overlay.find_nodes(view.getSceneGraph(), design_overlay.PREVIEW_NODE)) == 1)
    t0 = time.monotonic()
    check("Design strips: design derived", tool.wait_idle(90) and tool.worker is not None,
          "{:.1f} s".format(time.monotonic() - t0))

    # hover (the function the mouse-move callback calls): the meridian through (13, 0, 0)
    pos = screen_pick(tool, view, (13, 0, 0))
    if not check("hover: (13,0,0) visible and pickable", pos is not None, pos):
        return design
    result["info"]["hover_screen"] = pos
    picked = tool.hover_screen(*pos)
    t0 = time.monotonic()
    tool.wait_idle(30)
    result["info"]["hover_ms"] = round(1000 * (time.monotonic() - t0))
    n = tool.preview_point_count()
    check("hover: preview loop drawn", n > 10, n)
    best = tool.proposals[0] if tool.proposals else {}
    check("hover: the preview is the meridian (closed, 2 pi 3)",
          best.get("closed") and abs(best.get("length", 0) - 2 * math.pi * 3) < 0.02 * 2 * math.pi * 3,
          {k: best.get(k) for k in ("closed", "length", "cost")})
    check("hover: proposal shown in the panel", "best" in tool.panel.proposal.text(), tool.panel.proposal.text())

    # the same through a real mouse move (Qt -> Quarter -> Coin -> the tool's callback)
    vp = viewport_widget()
    tool.preview.clear()
    tool.point = None
    if check("viewport widget found", vp is not None):
        send_mouse_move(vp, *to_qt(vp, view, *pos))
        pump(0.1)
        tool.wait_idle(30)
        check("mouse move: callback picked the point", tool.point is not None and dist(tool.point, picked) < 0.5,
              tool.point)
        check("mouse move: preview loop drawn", tool.preview_point_count() > 10, tool.preview_point_count())

    # click: the strip is added (one transaction)
    check("click: accepted", tool.click_screen(*pos))
    tool.wait_idle(60)
    check("click: strip 1 added", design.StripCount == 1, (design.StripCount, design.Status))
    check("click: undoable 'Add strip'", (doc.UndoNames or [None])[0] == "Add strip", doc.UndoNames)
    check("panel: one strip listed", tool.panel.row_count() == 1, tool.panel.row_count())
    w = design.Shape.Wires
    check("Shape: one closed wire of length 2 pi 3",
          len(w) == 1 and w[0].isClosed() and abs(w[0].Length - 2 * math.pi * 3) < 0.02 * 2 * math.pi * 3,
          [(x.isClosed(), x.Length) for x in w])

    # a second point: the proposal must cross the meridian strip (not another meridian)
    second = None
    for p in ((0, -13, 0), (0, 13, 0), (-13, 0, 0), (9.5, -2.5, 2.9)):
        second = screen_pick(tool, view, p)
        if second is not None:
            result["info"]["second_point"] = p
            break
    if not check("hover 2: a second point is pickable", second is not None):
        return design
    tool.hover_screen(*second)
    tool.wait_idle(30)
    best2 = tool.proposals[0] if tool.proposals else {}
    check("hover 2: preview drawn", tool.preview_point_count() > 10, tool.preview_point_count())
    check("screenshot (preview) saved", save_screenshot(view, SHOT_PREVIEW, refit=False), SHOT_PREVIEW)
    check("hover 2: compatible proposal (not a meridian)",
          best2 and abs(best2["length"] - 2 * math.pi * 3) > 0.05 * 2 * math.pi * 3, best2.get("length"))

    # Ctrl+wheel: the alternatives (through the tool API and a real wheel event)
    tool.browse(1)
    tool.wait_idle(60)
    result["info"]["alternatives"] = [(round(a["length"], 3), round(a["cost"], 4)) for a in tool.proposals]
    check("browse: alternatives listed", len(tool.proposals) > 1, len(tool.proposals))
    check("browse: second alternative shown", tool.index == 1 and "alternative 2" in tool.panel.proposal.text(),
          tool.panel.proposal.text())
    costs = [a["cost"] for a in tool.proposals]
    check("browse: alternatives in order of quality", costs == sorted(costs), costs)
    if vp is not None:
        send_ctrl_wheel(vp, *to_qt(vp, view, *second), 120)  # wheel up: back to the best
        pump(0.1)
        tool.wait_idle(10)
        check("Ctrl+wheel event: back to the best", tool.index == 0, tool.index)
    tool.click_screen(*second)
    tool.wait_idle(60)
    check("click 2: strip 2 added", design.StripCount == 2, (design.StripCount, design.Status))
    check("panel: two strips listed", tool.panel.row_count() == 2, tool.panel.row_count())
    summary = design.Proxy.summary(design)
    result["info"]["torus_summary"] = summary
    result["info"]["torus_status"] = design.Status
    check("design: no error", not summary.get("error") and "Invalid" not in design.State, design.Status)

    ov = overlay_state(design.ViewObject)
    result["info"]["torus_overlay"] = ov
    check("overlay: stripes drawn", ov["stripes_nodes"] == 1 and ov["stripe_triangles"] > 1000, ov)
    check("overlay: two loops", ov["loop_polylines"] == 2, ov)
    check("overlay: singularity markers match the summary",
          ov["singularity_points"] == len(summary.get("singularities", [])), ov)
    check("screenshot (torus) saved", save_screenshot(view, SHOT_TORUS, view_size=True), SHOT_TORUS)
    picture_shows_the_loops("torus picture", SHOT_TORUS, view, design)
    Gui.getMainWindow().grab().save(SHOT_WINDOW)  # the task panel, for a human to look at

    # Remove in the panel, then undo
    button = tool.panel.form.findChild(QtGui.QPushButton, "StripWeaveRemoveStrip2")
    if check("panel: Remove button of strip 2", button is not None):
        button.click()
        pump(0.2)
        tool.wait_idle(30)
        check("Remove: one strip left", design.StripCount == 1 and tool.panel.row_count() == 1,
              (design.StripCount, tool.panel.row_count()))
        check("Remove: undoable", (doc.UndoNames or [None])[0] == "Remove strip", doc.UndoNames)
        doc.undo()
        doc.recompute()
        pump(0.2)
        tool.wait_idle(30)
        check("undo: two strips again", design.StripCount == 2 and tool.panel.row_count() == 2,
              (design.StripCount, tool.panel.row_count()))

    # a design holding a strip no loop can make: kept, reported, the failed row removable
    expected_error_from = len(report_view_text())  # the recompute error prints a traceback: expected
    data = json.loads(design.DesignJson)
    data["strips"].append({"anchors": [{"point": [-13, 0, 0], "direction": [0, 0, 1]}]})
    design_model.write_design(design, data, "Bad strip")
    pump(0.2)
    tool.wait_idle(30)
    check("bad strip: design kept", len(json.loads(design.DesignJson)["strips"]) == 3)
    check("bad strip: object invalid, two strips derived", "Invalid" in design.State and design.StripCount == 2,
          (design.State, design.StripCount))
    check("bad strip: panel shows the error and three rows",
          tool.panel.row_count() == 3 and "strip 3" in tool.panel.status.text(),
          (tool.panel.row_count(), tool.panel.status.text()))
    check("bad strip: error in the report view", "strip 3" in report_view_text()[expected_error_from:])
    EXPECTED_ERRORS.append((expected_error_from, len(report_view_text())))
    doc.undo()
    doc.recompute()
    pump(0.2)
    tool.wait_idle(30)
    check("bad strip: undo repairs", design.StripCount == 2 and "Invalid" not in design.State
          and tool.panel.row_count() == 2, (design.State, tool.panel.row_count()))

    # Esc in the 3D view closes the tool
    if vp is not None:
        vp.setFocus()
        QtGui.QApplication.sendEvent(vp, QtGui.QKeyEvent(QtCore.QEvent.KeyPress, QtCore.Qt.Key_Escape,
                                                         QtCore.Qt.NoModifier))
        pump(0.3)
    check("Esc: tool closed", design_tool.active_tool() is None)
    check("Esc: task panel closed", not Gui.Control.activeDialog())
    check("Esc: preview node removed",
          len(overlay.find_nodes(view.getSceneGraph(), design_overlay.PREVIEW_NODE)) == 0)
    for o in (torus, sm, design):
        o.ViewObject.Visibility = False
    return design


def box_scenario(doc):
    from freecad.stripweave_wb import design_commands
    box = doc.addObject("Part::Box", "Box")
    box.Length = box.Width = box.Height = 10
    doc.recompute()
    sm = prepared(doc, box, 12000)
    if not check("box: SurfaceModel prepared", sm is not None):
        return None
    design = design_commands.new_design(sm, {"format": "stripweave-design", "version": 1, "strips": [
        {"anchors": [{"point": a[:3], "direction": a[3:]} for a in s]} for s in CUBE_BELTS]})
    pump(0.2)
    summary = design.Proxy.summary(design)
    result["info"]["box_summary"] = summary
    counts = summary.get("singularity_counts", {})
    check("box: three belts", design.StripCount == 3, design.Status)
    check("box: eight +1/4 singularities", counts.get("+1/4") == 8 and counts.get("-1/4") == 0, counts)
    ov = overlay_state(design.ViewObject)
    result["info"]["box_overlay"] = ov
    check("box: overlay has 3 loops and 8 markers", ov["loop_polylines"] == 3 and ov["singularity_points"] == 8, ov)
    view = Gui.activeDocument().activeView()
    check("screenshot (cube) saved", save_screenshot(view, SHOT_BOX), SHOT_BOX)
    return design


def reopen_scenario(doc, names):
    from freecad.stripweave_wb import builder, derive_async
    path = os.path.join(WORKDIR, "stripweave_design_gui.FCStd")
    doc.saveAs(path)
    App.closeDocument(doc.Name)
    pump(0.3)
    doc = App.openDocument(path)
    pump(0.3)
    for name in names:
        d = doc.getObject(name)
        if not check("reopen: {} restored".format(name), d is not None and d.Proxy is not None):
            continue
        ov = overlay_state(d.ViewObject)
        check("reopen: {} loops drawn from the stored shape".format(name), ov["loop_polylines"] == d.StripCount, ov)
    done = wait_until(lambda: not derive_async.pending() and not builder.active_builds(), TIMEOUT / 3)
    pump(0.3)
    check("reopen: background derivation finished", done)
    for name in names:
        d = doc.getObject(name)
        if d is None:
            continue
        ov = overlay_state(d.ViewObject)
        check("reopen: {} stripes derived again".format(name),
              d.Proxy.derived(d) is not None and ov["stripe_triangles"] > 500, ov)
    App.closeDocument(doc.Name)


def scenario():
    result["info"]["freecad"] = ".".join(App.Version()[:3])
    check("workbench registered", WB in Gui.listWorkbenches())
    Gui.activateWorkbench(WB)
    pump(0.2)
    for name in DESIGN_COMMANDS:
        check("command {} registered".format(name), name in Gui.listCommands())
    doc = App.newDocument("StripWeaveDesignGui")
    torus_design = torus_scenario(doc)
    box_design = box_scenario(doc)
    text = report_view_text()
    for start, end in reversed(EXPECTED_ERRORS):
        text = text[:start] + text[end:]
    errors = [l for l in text.splitlines() if "Traceback" in l or "internal error" in l]
    check("no tracebacks in the report view", not errors, errors[:5])
    reopen_scenario(doc, [d.Name for d in (torus_design, box_design) if d is not None])


h.run(scenario)
