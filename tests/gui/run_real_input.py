"""GUI scenario driven by REAL input: the "Design strips" tool used with the
X pointer and keyboard (xdotool), as a user would, executed by FreeCAD's GUI:

    xvfb-run -a -s "-screen 0 1280x800x24" freecad tests/gui/run_real_input.py

(normally started by tests/gui/test_real_input.py).  Environment: that of
gui_harness.py, plus STRIPWEAVE_GUI_TESTS (this folder), STRIPWEAVE_GUI_WORKDIR
(screenshots go there).

A torus: Prepare surface, New design, Design strips (through the commands);
then only real events: the pointer moves onto the outer equator (the preview
shows the loop through it), a click adds exactly that loop as a strip (the
part is neither preselected nor selected); Esc ends the tool, after which a
click selects the part again.  Screenshot: click.png.
"""

import os
import sys

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

import FreeCAD as App  # noqa: E402
import FreeCADGui as Gui  # noqa: E402

import gui_harness as h  # noqa: E402
from gui_harness import check  # noqa: E402

WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or "/tmp"
TRIANGLES = 8000
POINT_A = (13.0, 0.0, 0.0)   # outer equator: the best loop through it is a meridian


def loop_distance(a, b):
    """Symmetric distance between two polylines given by dense vertices: the
    largest distance from a vertex of one to the nearest vertex of the other."""
    a, b = np.asarray(a, dtype=float).reshape(-1, 3), np.asarray(b, dtype=float).reshape(-1, 3)
    if not len(a) or not len(b):
        return float("inf")
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def start_tool(doc, sm):
    from freecad.stripweave_wb import design_model, design_tool
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(sm)
    Gui.runCommand("StripWeave_DesignStrips")  # a new design on a model without one
    designs = design_model.designs_of(sm)
    tool = design_tool.active_tool()
    if not check("Design strips: tool and design", tool is not None and len(designs) == 1, designs):
        return None, None
    check("Design strips: design derived", tool.wait_idle(90) and tool.worker is not None)
    return tool, designs[0]


def shown_loop(tool):
    if not tool.proposals or tool.index >= len(tool.proposals):
        return None
    return np.asarray(tool.proposals[tool.index]["points"], dtype=float)


def hover(tool, view, point, label):
    """Real pointer onto ``point``; returns the Coin position, or None."""
    pos = h.screen_position(view, point)
    picked = tool.pick(*pos)
    if not check("{}: {} visible at {}".format(label, point, pos), picked is not None and h.dist(picked, point) < 0.5,
                 picked):
        return None
    h.mouse_move(view, *pos)
    h.wait_until(lambda: tool.point is not None and h.dist(tool.point, picked) < 0.5, 10)
    tool.wait_idle(30)
    check("{}: the pointer's move reached the tool".format(label),
          tool.point is not None and h.dist(tool.point, picked) < 0.5, tool.point)
    check("{}: preview loop drawn".format(label), tool.preview_point_count() > 10, tool.preview_point_count())
    pre = Gui.Selection.getPreselection()
    check("{}: no preselection while the tool runs".format(label), not pre.ObjectName, pre.ObjectName)
    return pos


def strip_loop(design, index):
    d = design.Proxy.derived(design)
    if d is None or index >= len(d.strips):
        return None
    return d.strips[index]["points"]


def click_adds_shown_loop(doc, tool, design, label, tolerance):
    """Real click at the pointer: one strip more, its loop the one shown."""
    shown = shown_loop(tool)
    before = design.StripCount
    h.mouse_click(1)
    h.wait_until(lambda: tool.add_serial is None, 5)
    tool.wait_idle(90)
    check("{}: click added one strip".format(label), design.StripCount == before + 1,
          (before, design.StripCount, design.Status, tool.panel.status.text()))
    check("{}: undoable 'Add strip'".format(label), (doc.UndoNames or [None])[0] == "Add strip", doc.UndoNames)
    check("{}: nothing selected".format(label), not Gui.Selection.getSelection(),
          [o.Name for o in Gui.Selection.getSelection()])
    added = strip_loop(design, before)
    gap = loop_distance(shown, added) if shown is not None and added is not None else float("inf")
    h.result["info"][label + "_loop_distance"] = gap
    check("{}: the strip's loop is the loop shown (within {:.3g})".format(label, tolerance), gap <= tolerance, gap)
    return added


def scenario():
    from freecad.stripweave_wb import design_tool
    Gui.activateWorkbench("StripWeaveWorkbench")
    doc = App.newDocument("StripWeaveRealInput")
    torus = h.torus_in_view(doc)
    sm = h.prepared(doc, torus, TRIANGLES)
    if not check("torus prepared", sm is not None):
        return
    view = Gui.activeDocument().activeView()
    tool, design = start_tool(doc, sm)
    if tool is None:
        return
    scene = view.getSceneGraph()
    check("tool: selection and preselection off in the view",
          scene.getField("selectionMode").getValue() != 1 and scene.getField("highlightMode").get() == "OFF",
          (scene.getField("selectionMode").get(), scene.getField("highlightMode").get()))
    diagonal = torus.Shape.BoundBox.DiagonalLength
    tolerance = 1e-3 * diagonal

    pos = hover(tool, view, POINT_A, "hover A")
    if pos is None:
        return
    loop = click_adds_shown_loop(doc, tool, design, "click A", tolerance)
    if loop is not None:
        ring = np.hypot(loop[:, 0], loop[:, 1])
        check("click A: a meridian (the loop stays in the plane y = 0 at distance 10 from the axis)",
              np.abs(loop[:, 1]).max() < 0.05 * diagonal and np.abs(np.hypot(ring - 10, loop[:, 2]) - 3).max() < 0.1,
              (float(np.abs(loop[:, 1]).max()), float(np.abs(np.hypot(ring - 10, loop[:, 2]) - 3).max())))
    shot = os.path.join(WORKDIR, "click.png")
    check("screenshot after the click saved", h.save_screenshot(view, shot), shot)

    h.key("Escape")
    h.wait_until(lambda: design_tool.active_tool() is None, 5)
    check("Esc (real key): tool closed", design_tool.active_tool() is None and not Gui.Control.activeDialog())
    check("Esc: selection restored in the view",
          scene.getField("selectionMode").getValue() == 1 and scene.getField("highlightMode").get() == "AUTO",
          (scene.getField("selectionMode").get(), scene.getField("highlightMode").get()))
    for o in (sm, design):
        o.ViewObject.Visibility = False
    torus.ViewObject.Visibility = True
    h.pump(0.2)
    h.mouse_move(view, *pos)
    h.mouse_click(1)
    h.pump(0.3)
    check("after the tool: a click selects the part again",
          [o.Name for o in Gui.Selection.getSelection()] == [torus.Name],
          [o.Name for o in Gui.Selection.getSelection()])
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
