"""GUI scenario: a DRAG with the real X pointer (xdotool) in the Design
strips tool sets a directional anchor, and the loop follows the drag
(paper §4.1).  Run by tests/gui/test_drag_gui.py under Xvfb.

A torus: the pointer presses on the outer equator at P = (13, 0, 0), moves
in steps towards a point diagonal to both the meridian and the equator
(45 degrees in the surface's metric), and the preview shows the loop
through P along the drag; the release adds that loop.  Checked: the anchor
the tool took points along the drag; the shown loop's and the added
strip's tangent at P are within 10 degrees of the drag (in the tangent
plane); nothing is selected.  Screenshot drag.png (while dragging).
Then Shift+click (shift_click_anchors): two anchors, Enter adds the strip
through both; Esc drops pending anchors.  Screenshot anchors.png.
"""

import json
import math
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
P = (13.0, 0.0, 0.0)
NORMAL = (1.0, 0.0, 0.0)          # the torus's normal at P
PHI, THETA = 0.1, 0.1 * 13 / 3    # equal arcs along the equator and the meridian: 45 degrees


def tangent_at(points, p):
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    i = int(np.argmin(np.linalg.norm(pts - np.asarray(p), axis=1)))
    a, b = pts[max(i - 2, 0)], pts[min(i + 2, len(pts) - 1)]
    t = b - a
    return t / np.linalg.norm(t), float(np.linalg.norm(pts[i] - np.asarray(p)))


def in_plane(v):
    v = np.asarray(v, dtype=float)
    n = np.asarray(NORMAL)
    v = v - v.dot(n) * n
    return v / np.linalg.norm(v)


def angle_deg(a, b):
    """Angle between two lines (direction-free), degrees."""
    return math.degrees(math.acos(min(1.0, abs(float(np.dot(in_plane(a), in_plane(b)))))))


def shift_click(view, tool, point):
    h.shift_click(view, point)
    tool.wait_idle(60)


def shift_click_anchors(doc, view, sm):
    """Shift+click on the outer equator at A1 and A2 (real keys and button):
    the preview is the loop through both (the outer equator, where a plain
    click at A1 gives a meridian); Esc drops a third pending anchor, Enter
    adds the strip through A1 and A2."""
    from freecad.stripweave_wb import design_tool
    design, tool = h.tool_on_new_design(doc, sm, "Shift+click")
    a1, a2 = (13.0, 0.0, 0.0), (9.19, -9.19, 0.0)
    for a in (a1, a2):
        shift_click(view, tool, a)
    check("Shift+click: two anchors pending, no strip yet", len(tool.pending) == 2 and design.StripCount == 0,
          (tool.pending, design.StripCount, tool.panel.status.text(), tool.panel.proposal.text()))
    shown = tool.shown_proposal()
    if check("Shift+click: the loop through both anchors shown", shown is not None and shown.get("exact"),
             tool.panel.proposal.text()):
        pts = np.asarray(shown["points"])
        check("Shift+click: it is the outer equator (z = 0, radius 13)",
              np.abs(pts[:, 2]).max() < 0.3 and np.abs(np.hypot(pts[:, 0], pts[:, 1]) - 13).max() < 0.3,
              (float(np.abs(pts[:, 2]).max()), float(np.abs(np.hypot(pts[:, 0], pts[:, 1]) - 13).max())))
    shot = os.path.join(WORKDIR, "anchors.png")
    check("screenshot anchors.png", h.save_screenshot(view, shot), shot)
    shift_click(view, tool, (0.0, -13.0, 0.0))
    h.key("Escape")
    tool.wait_idle(10)
    check("Esc: the pending anchors dropped, the tool still open",
          tool.pending == [] and design_tool.active_tool() is tool, tool.pending)
    for a in (a1, a2):
        shift_click(view, tool, a)
    h.key("Return")
    h.wait_until(lambda: tool.add_serial is None, 5)
    tool.wait_idle(90)
    check("Enter: one strip through the anchors", design.StripCount == 1, (design.StripCount, design.Status))
    data = json.loads(design.DesignJson)
    check("Enter: the strip keeps both anchors", data["strips"] and len(data["strips"][0]["anchors"]) == 2,
          data["strips"])
    d = design.Proxy.derived(design)
    if d is not None and d.strips:
        pts = np.asarray(d.strips[0]["points"])
        check("Enter: the strip is the outer equator",
              np.abs(pts[:, 2]).max() < 0.3 and np.abs(np.hypot(pts[:, 0], pts[:, 1]) - 13).max() < 0.3)
    h.key("Escape")
    h.wait_until(lambda: design_tool.active_tool() is None, 5)
    check("Esc with nothing pending: the tool closed", design_tool.active_tool() is None)


def scenario():
    Gui.activateWorkbench("StripWeaveWorkbench")
    doc = App.newDocument("StripWeaveDrag")
    started = h.design_tool_on(doc, h.torus_in_view(doc), TRIANGLES)
    if started is None:
        return
    view, design, tool = started
    sm = design.Surface

    start = h.screen_position(view, P)
    target = h.torus_point(PHI, THETA)
    end = h.screen_position(view, target)
    picked = tool.pick(*start)
    if not check("P visible", picked is not None and h.dist(picked, P) < 0.5, picked):
        return
    check("the drag's end visible", tool.pick(*end) is not None, end)
    h.mouse_move(view, *start)
    tool.wait_idle(30)
    h.xdotool("mousedown", 1)
    h.drag_steps(view, start, end, 6)
    h.wait_until(lambda: tool.drag_anchor is not None, 5)
    tool.wait_idle(60)
    anchor = tool.drag_anchor
    if not check("drag: a directional anchor at P", anchor is not None and h.dist(anchor[:3], P) < 0.5, anchor):
        h.xdotool("mouseup", 1)
        return
    drag = np.subtract(target, P)
    h.result["info"]["anchor_vs_drag_deg"] = angle_deg(anchor[3:], drag)
    check("drag: the anchor points along the drag (within 10 deg)", angle_deg(anchor[3:], drag) <= 10.0,
          angle_deg(anchor[3:], drag))
    shown = tool.shown_proposal()
    if check("drag: a loop shown along the drag", shown is not None, tool.panel.proposal.text()):
        t, gap = tangent_at(shown["points"], P)
        h.result["info"]["shown_tangent_vs_drag_deg"] = angle_deg(t, anchor[3:])
        check("drag: the shown loop passes P, tangent within 10 deg of the drag",
              gap < 0.5 and angle_deg(t, anchor[3:]) <= 10.0, (gap, angle_deg(t, anchor[3:])))
    shot = os.path.join(WORKDIR, "drag.png")
    check("screenshot drag.png", h.save_screenshot(view, shot), shot)
    before = design.StripCount
    h.xdotool("mouseup", 1)
    h.wait_until(lambda: tool.add_serial is None, 5)
    tool.wait_idle(90)
    check("release: one strip added", design.StripCount == before + 1, (before, design.StripCount,
                                                                         tool.panel.status.text()))
    check("release: nothing selected", not Gui.Selection.getSelection())
    d = design.Proxy.derived(design)
    if d is not None and d.strips:
        t, gap = tangent_at(d.strips[-1]["points"], P)
        h.result["info"]["strip_tangent_vs_drag_deg"] = angle_deg(t, anchor[3:])
        check("the added strip's loop passes P, tangent within 10 deg of the drag",
              gap < 0.5 and angle_deg(t, anchor[3:]) <= 10.0, (gap, angle_deg(t, anchor[3:])))
    tool.close()
    h.pump(0.3)
    shift_click_anchors(doc, view, sm)
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
