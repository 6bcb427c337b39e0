"""GUI scenario driven by REAL input: the "Design strips" tool used with the
X pointer and keyboard (xdotool), as a user would, executed by FreeCAD's GUI:

    xvfb-run -a -s "-screen 0 1280x800x24" freecad tests/gui/run_real_input.py

(normally started by tests/gui/test_real_input.py).  Environment: that of
gui_harness.py, plus STRIPWEAVE_GUI_TESTS (this folder), STRIPWEAVE_GUI_WORKDIR
(screenshots go there).

A torus: Prepare surface, New design, Design strips (through the commands);
then only real events: the pointer moves onto the outer equator (the preview
shows the loop through it), a click adds exactly that loop as a strip (the
part is neither preselected nor selected); on a second point Ctrl+wheel
browses the alternatives (the camera does not zoom) and a click adds exactly
the alternative shown; Esc ends the tool, after which a click selects the
part again.  Screenshots: click.png (after the first click), alternative.png
(the alternative shown, before its click).
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
# Second points, the first visible one with alternatives is used.
POINTS_B = ((0.0, -13.0, 0.0), (9.5, -2.5, 2.9), (-10.0, 0.0, 3.0), (7.0, 0.0, 0.0), (0.0, 13.0, 0.0))


def loop_distance(a, b):
    """Symmetric distance between two polylines given by dense vertices: the
    largest distance from a vertex of one to the nearest vertex of the other."""
    a, b = np.asarray(a, dtype=float).reshape(-1, 3), np.asarray(b, dtype=float).reshape(-1, 3)
    if not len(a) or not len(b):
        return float("inf")
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def start_tool(doc, view, sm):
    from freecad.stripweave_wb import design_model, design_tool
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(sm)
    h.mouse_move(view, *h.screen_position(view, (0, 0, 0)))  # the pointer in the 3D view, off the part
    pose = camera_pose(view)
    h.key("y")
    h.key("d")              # the Design strips shortcut: a new design on a model without one
    check("shortcut: the camera did not move", camera_pose(view) == pose, (pose, camera_pose(view)))
    h.wait_until(lambda: design_tool.active_tool() is not None, 10)
    designs = design_model.designs_of(sm)
    tool = design_tool.active_tool()
    if not check("shortcut Y, D (real keys): tool and design", tool is not None and len(designs) == 1, designs):
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


def camera_pose(view):
    """Position, orientation and height of the camera (its clipping planes
    follow the scene's extent, which the preview changes)."""
    cam = view.getCameraNode()
    height = cam.height.getValue() if hasattr(cam, "height") else cam.heightAngle.getValue()
    return (tuple(round(c, 6) for c in cam.position.getValue().getValue()),
            tuple(round(c, 6) for c in cam.orientation.getValue().getValue()), round(height, 6))


def browse_to(tool, view, notches):
    """Real Ctrl+wheel notches (one browse step each); True if the proposal
    that many steps on is shown."""
    pose = camera_pose(view)
    want = min(tool.want_index + notches, 5)
    h.ctrl_wheel(notches)
    h.wait_until(lambda: tool.want_index == want, 10)
    tool.wait_idle(60)
    check("Ctrl+wheel: one browse step per notch", tool.want_index == want, (tool.want_index, want))
    check("Ctrl+wheel: the camera did not zoom", camera_pose(view) == pose, (pose, camera_pose(view)))
    return tool.index == want


def browse_and_click(doc, view, tool, design, tolerance):
    """On a second point: Ctrl+wheel to the last alternative, click: that
    loop is the new strip (not the best one)."""
    for point in POINTS_B:
        if tool.pick(*h.screen_position(view, point)) is None:
            continue
        if hover(tool, view, point, "hover B") is None:
            continue
        best = shown_loop(tool)
        browse_to(tool, view, 1)
        if len(tool.proposals) >= 2:
            break
    else:
        check("browse: a second point with alternatives", False)
        return
    h.result["info"]["alternatives_B"] = [(round(a["length"], 3), round(a["cost"], 4)) for a in tool.proposals]
    check("Ctrl+wheel: the second alternative shown", tool.index == 1 and "alternative 2" in tool.panel.proposal.text(),
          (tool.index, tool.panel.proposal.text()))
    if len(tool.proposals) > 2:
        pose = camera_pose(view)
        h.key("Next")  # Page Down: the next alternative, from the keyboard
        tool.wait_idle(60)
        check("Page Down (real key): the third alternative shown", tool.index == 2, tool.index)
        check("Page Down: the camera did not move", camera_pose(view) == pose, (pose, camera_pose(view)))
    if len(tool.proposals) > 3:
        browse_to(tool, view, len(tool.proposals) - 3)
    last = len(tool.proposals) - 1
    check("Ctrl+wheel: the last alternative shown", tool.index == last, (tool.index, last))
    alternative = shown_loop(tool)
    gap = loop_distance(best, alternative)
    check("the alternative shown is not the best loop", gap > tolerance, gap)
    shot = os.path.join(WORKDIR, "alternative.png")
    check("screenshot of the alternative saved", h.save_screenshot(view, shot), shot)
    click_adds_shown_loop(doc, tool, design, "click B", tolerance)


def scenario():
    from freecad.stripweave_wb import design_tool
    Gui.activateWorkbench("StripWeaveWorkbench")
    doc = App.newDocument("StripWeaveRealInput")
    torus = h.torus_in_view(doc)
    sm = h.prepared(doc, torus, TRIANGLES)
    if not check("torus prepared", sm is not None):
        return
    view = Gui.activeDocument().activeView()
    tool, design = start_tool(doc, view, sm)
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
    if loop is not None:
        from freecad.stripweave_wb import stripe_pattern
        d = design.Proxy.derived(design)
        h.check_loops_in_picture("click picture", shot, view, [loop], [stripe_pattern.loop_color(0)],
                                 d.vertices[::max(1, len(d.vertices) // 400)], diagonal)

    browse_and_click(doc, view, tool, design, tolerance)

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
          ([o.Name for o in Gui.Selection.getSelection()], view.getObjectInfo(pos), torus.ViewObject.Visibility,
           Gui.Selection.getPreselection().ObjectName))
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
