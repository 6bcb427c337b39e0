"""GUI scenario: a REAL drag (xdotool) of a Layout's primal vertex in the
Edit layout vertices tool pins it where it is released (paper §7, manual).
Run by tests/gui/test_pin_drag_gui.py under Xvfb.

Three great circles on Part.makeSphere(5): a Layout with eight octant
vertices.  The tool starts from its command on the selected Layout; the
pointer presses on the dot of an octant vertex the view shows, moves in
steps to another point of that octant and releases.  Checked: the Design
has one pin, the point under the release; the undo step is "Move layout
vertex"; after the Layout's recompute that octant's vertex is placed
"pinned" within one solver edge of the point, and drawn green
(screenshot pinned.png, looked at); nothing is selected; Esc ends the
tool; Clear layout pins removes the pin.
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
RADIUS = 5.0
GREAT_CIRCLES = [[(5, 0, 0, 0, 1, 0)], [(0, 5, 0, 0, 0, 1)], [(0, 0, 5, 1, 0, 0)]]
SOLVER_EDGE = math.sqrt(4 * math.pi * RADIUS ** 2 / TRIANGLES * 4 / math.sqrt(3))


def octant_vertex(layout, signs):
    lj = json.loads(layout.LayoutJson or "{}")
    for i, v in enumerate(lj.get("vertices", [])):
        if all((c > 0) == (s > 0) for c, s in zip(v["position"], signs)):
            return i, v
    return None, None


def layout_current(layout):
    from freecad.stripweave_wb import tasks
    return (not tasks.running((layout.Document.Name, layout.Name)) and layout.Proxy.mesh(layout) is not None
            and bool(layout.LayoutJson) and not layout.Status.startswith("computing"))


def target_in_octant(position):
    """A point of the sphere in the vertex's octant, about 0.3 rad from it
    towards one axis (each axis tried: the first the view shows)."""
    u = np.asarray(position) / np.linalg.norm(position)
    for axis in range(3):
        d = u.copy()
        d[axis] += 0.6 * math.copysign(1.0, u[axis])
        yield tuple(RADIUS * d / np.linalg.norm(d))


def scenario():
    from freecad.stripweave_wb import design_model, layout_model, layout_tool
    from freecad.stripweave_wb.layout_pins import pins_of
    from freecad.stripweave_wb.layout_view import PINNED_COLOR
    from stripweave.design import Design
    import Part
    Gui.activateWorkbench("StripWeaveWorkbench")
    doc = App.newDocument("StripWeavePins")
    sphere = doc.addObject("Part::Feature", "Sphere")
    sphere.Shape = Part.makeSphere(RADIUS)
    doc.recompute()
    view = Gui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    sm = h.prepared(doc, sphere, TRIANGLES)
    if not check("part prepared", sm is not None):
        return
    design = design_model.create(sm, Design(GREAT_CIRCLES))
    doc.recompute()
    layout = layout_model.create(design)
    if not check("layout computed", h.wait_until(lambda: layout_current(layout), 180) and layout.PatchCount == 6,
                 (layout.Status, layout.PatchCount)):
        return
    h.pump(0.5)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(layout)
    Gui.runCommand("StripWeave_EditLayoutVertices")
    tool = layout_tool.active_tool()
    if not check("tool started from its command", tool is not None):
        return
    check("tool: nothing selected", not Gui.Selection.getSelection())

    chosen = None
    width, height = view.getSize()

    def off_centre(signs):   # the vertex nearest the view's centre first: seen face on
        _, v = octant_vertex(layout, signs)
        x, y = h.screen_position(view, v["position"]) if v else (1e9, 1e9)
        return math.hypot(x - width / 2, y - height / 2)
    for signs in sorted([(sx, sy, sz) for sx in (1, -1) for sy in (1, -1) for sz in (1, -1)], key=off_centre):
        k, v = octant_vertex(layout, signs)
        if k is None:
            continue
        start = h.screen_position(view, v["position"])
        if tool.vertex_at(*start) != k:
            continue
        for target in target_in_octant(v["position"]):
            end = h.screen_position(view, target)
            picked = tool.pick(*end)
            if picked is not None and h.dist(picked, target) < 3 * SOLVER_EDGE and h.dist(end, start) > 30:
                chosen = (signs, k, v, start, end)
                break
        if chosen:
            break
    if not check("a visible octant vertex and a visible point of its octant", chosen is not None):
        return
    signs, k, v, start, end = chosen
    h.result["info"].update({"octant": signs, "vertex_before": v, "press": start, "release": end})
    before_undo = (doc.UndoNames or [None])[0]
    h.mouse_move(view, *start)
    h.xdotool("mousedown", 1)
    h.drag_steps(view, start, end, 6)
    check("drag: the vertex grabbed", tool.grabbed == k, tool.grabbed)
    release_point = tool.pick(*end)   # the surface point under the release
    h.result["info"]["release_point"] = release_point
    shot = os.path.join(WORKDIR, "dragging.png")
    check("screenshot dragging.png", h.save_screenshot(view, shot), shot)
    h.xdotool("mouseup", 1)
    h.wait_until(lambda: bool(pins_of(design)), 10)
    h.wait_until(lambda: octant_vertex(layout, signs)[1] is not None
                 and octant_vertex(layout, signs)[1]["placement"] == "pinned" and layout_current(layout), 120)
    pins = pins_of(design)
    h.result["info"]["pins"] = pins
    # The tool's release and this pick may round the pointer to neighbouring pixels.
    off_px = h.dist(h.screen_position(view, pins[0]), end) if len(pins) == 1 else None
    h.result["info"]["pin_off_release_px"] = off_px
    check("release: one pin, the point of the part under the release (within 2 px)",
          len(pins) == 1 and release_point is not None and off_px <= 2.0, (pins, release_point, off_px))
    check("release: undo step 'Move layout vertex'", (doc.UndoNames or [None])[0] == "Move layout vertex",
          (before_undo, doc.UndoNames[:3]))
    k2, v2 = octant_vertex(layout, signs)
    h.result["info"]["vertex_after"] = v2
    gap = h.dist(v2["position"], release_point) if v2 and release_point else None
    h.result["info"]["pinned_gap"] = gap
    h.result["info"]["solver_edge"] = SOLVER_EDGE
    check("the octant's vertex is pinned within one solver edge of the release point",
          v2 is not None and v2["placement"] == "pinned" and gap <= SOLVER_EDGE, (v2, gap, SOLVER_EDGE))
    check("the vertex moved", v2 is not None and h.dist(v2["position"], v["position"]) > 3 * SOLVER_EDGE)
    check("the other vertices stay unpinned",
          sum(x["placement"] == "pinned" for x in json.loads(layout.LayoutJson)["vertices"]) == 1)
    check("release: nothing selected", not Gui.Selection.getSelection())
    h.pump(0.5)
    shot = os.path.join(WORKDIR, "pinned.png")
    if check("screenshot pinned.png", h.save_screenshot(view, shot), shot) and v2 is not None:
        at = h.screen_position(view, v2["position"])
        old = h.screen_position(view, v["position"])
        h.result["info"]["pinned_pixels"] = h.colour_hits(shot, view, [at], PINNED_COLOR, radius=4)
        h.result["info"]["old_place_pinned_pixels"] = h.colour_hits(shot, view, [old], PINNED_COLOR, radius=4)
        check("picture: the moved vertex drawn green (pinned), none at its old place",
              h.result["info"]["pinned_pixels"] == 1 and h.result["info"]["old_place_pinned_pixels"] == 0,
              (at, old))
    h.key("Escape")
    h.wait_until(lambda: layout_tool.active_tool() is None, 5)
    check("Esc: the tool ended", layout_tool.active_tool() is None)
    Gui.Selection.addSelection(layout)
    Gui.runCommand("StripWeave_ClearLayoutPins")
    check("Clear layout pins: no pins, undo step 'Clear layout pins'",
          pins_of(design) == [] and (doc.UndoNames or [None])[0] == "Clear layout pins", pins_of(design))
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
