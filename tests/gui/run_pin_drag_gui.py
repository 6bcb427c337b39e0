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

Then an edge (§7, manual: where in its corridor a patch boundary lies): the
tool again; the pointer presses on a visible edge, a third of the way from
a vertex to where the edge crosses its loop (off the vertices' dots), moves
in steps to a point of that vertex's octant beside the edge and releases.
Checked: the Design has one edge route, through the point under the release
and across the grabbed edge's crossing; the undo step is "Re-route layout
edge"; after the Layout's recompute that edge passes the point within one
solver edge, with the same ends, and the layout keeps six clean patches;
the point is drawn green (screenshot routed.png, looked at); Esc ends the
tool.

Last, a vertex dragged out of its octant into the next one, released there:
the drag stops at its region, so the pin is the last point of its own
octant the drag passed, and that octant's vertex is the one pinned.  The
tool's task panel lists that pin and the edge route; a real click on the
pin's Remove button removes it (undo step "Remove layout pin"), one on Clear
all the route, and a real click on Close ends the tool.
"""

import json
import math
import os
import sys

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

import FreeCAD as App  # noqa: E402
import FreeCADGui as Gui  # noqa: E402
from PySide import QtCore  # noqa: E402

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


def layout_json(layout):
    return json.loads(layout.LayoutJson or "{}")


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


def on_sphere(p):
    p = np.asarray(p, dtype=float)
    return RADIUS * p / np.linalg.norm(p)


def same_octant(a, b):
    return all((x > 0) == (y > 0) for x, y in zip(a, b))


def candidates(lj):
    """Per edge and end: (edge, press point on the edge, target in that end's octant off the
    edge): the press a third of the way from the vertex to where the edge crosses its loop,
    the target beside that stretch, about 0.45 of its length off it on either side."""
    for k, e in enumerate(lj.get("edges", [])):
        pts = np.asarray(e["points"], dtype=float)
        c = np.asarray(e["crossing_point"], dtype=float)
        for end in (0, 1):
            a = np.asarray(lj["vertices"][e["vertices"][end]]["position"], dtype=float)
            stretch = pts if end == 0 else pts[::-1]
            i = int(np.argmin(np.linalg.norm(stretch - c, axis=1)))
            press = stretch[max(1, i // 3)]
            m = on_sphere(a + c)
            n = np.cross(m, c - a)
            n /= np.linalg.norm(n)
            for side in (1, -1):
                target = on_sphere(m + side * 0.45 * np.linalg.norm(c - a) * n)
                if same_octant(target, a):
                    yield k, tuple(press), tuple(target)


def distance_to_points(points, p):
    """To an edge's points (its refined vertices, at most a solver edge apart)."""
    return float(np.min(np.linalg.norm(np.asarray(points, dtype=float) - np.asarray(p, dtype=float), axis=1)))


def route_phase(doc, view, layout, design, tool):
    """A real drag of an edge routes it through the release point (paper §7, manual)."""
    from freecad.stripweave_wb import layout_tool
    from freecad.stripweave_wb.layout_pins import routes_of
    from freecad.stripweave_wb.layout_view import PINNED_COLOR
    before = layout_json(layout)
    chosen = None
    width, height = view.getSize()

    def off_centre(candidate):   # the edge nearest the view's centre first: seen face on
        x, y = h.screen_position(view, candidate[1])
        return math.hypot(x - width / 2, y - height / 2)
    for k, press, target in sorted(candidates(before), key=off_centre):
        start = h.screen_position(view, press)
        if tool.vertex_at(*start) is not None or tool.edge_at(*start) != k:
            continue
        end = h.screen_position(view, target)
        picked = tool.pick(*end)
        if picked is not None and h.dist(picked, target) < 3 * SOLVER_EDGE and h.dist(end, start) > 25:
            chosen = (k, press, target, start, end)
            break
    if not check("route: a visible edge and a visible point of its corridor", chosen is not None):
        return
    k, press, target, start, end = chosen
    edge_before = before["edges"][k]
    h.result["info"].update({"edge": k, "press": start, "release": end, "target": target,
                             "target_off_edge_before": distance_to_points(edge_before["points"], target)})
    h.mouse_move(view, *start)
    h.pump(0.2)
    cursor = h.viewport_widget().cursor().shape()
    check("route: an open hand over the edge before the press", cursor == QtCore.Qt.OpenHandCursor, cursor)
    h.xdotool("mousedown", 1)
    h.drag_steps(view, start, end, 6)
    check("drag: the edge grabbed", tool.grabbed_edge == k and tool.grabbed is None, (tool.grabbed_edge, tool.grabbed))
    release_point = tool.pick(*end)
    h.result["info"]["release_point"] = release_point
    shot = os.path.join(WORKDIR, "route_dragging.png")
    check("screenshot route_dragging.png", h.save_screenshot(view, shot), shot)
    h.xdotool("mouseup", 1)
    h.wait_until(lambda: bool(routes_of(design)), 10)
    h.wait_until(lambda: layout_current(layout) and any(e.get("through") for e in layout_json(layout)["edges"]), 120)
    routes = routes_of(design)
    h.result["info"]["routes"] = routes
    # The tool's release and this pick may round the pointer to neighbouring pixels.
    off_px = h.dist(h.screen_position(view, routes[0]["through"]), end) if len(routes) == 1 else None
    h.result["info"]["route_off_release_px"] = off_px
    check("route: release: one edge route, through the point of the part under the release (within 2 px), "
          "across the grabbed edge's crossing",
          len(routes) == 1 and release_point is not None and off_px <= 2.0
          and h.dist(routes[0]["across"], edge_before["crossing_point"]) < 1e-6, (routes, release_point, off_px))
    check("route: release: undo step 'Re-route layout edge'", (doc.UndoNames or [None])[0] == "Re-route layout edge",
          doc.UndoNames[:3])
    after = layout_json(layout)
    routed = [e for e in after["edges"] if e.get("through") is not None]
    gap = distance_to_points(routed[0]["points"], release_point) if len(routed) == 1 and release_point else None
    h.result["info"].update({"routed_gap": gap, "solver_edge": SOLVER_EDGE})
    check("route: the grabbed edge now passes the release point (within one solver edge), same ends",
          len(routed) == 1 and routed[0]["vertices"] == edge_before["vertices"] and gap <= SOLVER_EDGE,
          (len(routed), gap))
    check("route: the layout keeps six clean patches", layout.PatchCount == 6 and layout.Clean,
          (layout.PatchCount, layout.Clean, after.get("problems")))
    check("route: release: nothing selected", not Gui.Selection.getSelection())
    h.pump(0.5)
    shot = os.path.join(WORKDIR, "routed.png")
    if check("screenshot routed.png", h.save_screenshot(view, shot), shot) and routed:
        at = h.screen_position(view, routed[0]["through"])
        h.result["info"]["route_pixels"] = h.colour_hits(shot, view, [at], PINNED_COLOR, radius=4)
        check("route: picture: the route's point drawn green", h.result["info"]["route_pixels"] == 1, at)
    h.key("Escape")
    h.wait_until(lambda: layout_tool.active_tool() is None, 5)
    check("route: Esc: the tool ended", layout_tool.active_tool() is None)


def outside_phase(doc, view, layout, design):
    """A vertex dragged out of its region stops at the region (paper §7: dragged within its
    region): the release across the loop pins it at the last point of its own octant."""
    from freecad.stripweave_wb import layout_tool
    from freecad.stripweave_wb.layout_pins import pins_of
    Gui.Selection.addSelection(layout)
    Gui.runCommand("StripWeave_EditLayoutVertices")
    tool = layout_tool.active_tool()
    if not check("outside: tool started again", tool is not None):
        return
    width, height = view.getSize()
    chosen = None
    for signs in sorted([(sx, sy, sz) for sx in (1, -1) for sy in (1, -1) for sz in (1, -1)],
                        key=lambda sg: h.dist(h.screen_position(view, octant_vertex(layout, sg)[1]["position"]),
                                              (width / 2, height / 2))):
        k, v = octant_vertex(layout, signs)
        start = h.screen_position(view, v["position"])
        if tool.vertex_at(*start) != k:
            continue
        for axis in range(3):   # across the loop in the plane of this axis, into the next octant
            d = np.asarray(v["position"]) / RADIUS
            d[axis] = -0.5 * math.copysign(1.0, d[axis])
            target = on_sphere(d)
            end = h.screen_position(view, target)
            picked = tool.pick(*end)
            if picked is not None and h.dist(picked, target) < 3 * SOLVER_EDGE and h.dist(end, start) > 40:
                chosen = (signs, k, axis, start, end, picked)
                break
        if chosen:
            break
    if not check("outside: a visible vertex and a visible point of the next octant", chosen is not None):
        return
    signs, k, axis, start, end, release_point = chosen
    h.mouse_move(view, *start)
    h.xdotool("mousedown", 1)
    h.drag_steps(view, start, end, 8)
    h.xdotool("mouseup", 1)
    h.wait_until(lambda: bool(pins_of(design)), 10)
    h.wait_until(lambda: layout_current(layout) and octant_vertex(layout, signs)[1]["placement"] == "pinned", 120)
    pins = pins_of(design)
    side = pins[0][axis] * signs[axis] if len(pins) == 1 else None
    h.result["info"].update({"outside_pins": pins, "outside_release": release_point, "outside_side": side})
    check("outside: one pin, on the grabbed vertex's side of the loop (within a solver edge), "
          "the release beyond it", len(pins) == 1 and side > -SOLVER_EDGE and release_point[axis] * signs[axis] < 0,
          (pins, release_point))
    placed = [i for i, x in enumerate(layout_json(layout)["vertices"]) if x["placement"] == "pinned"]
    check("outside: the grabbed octant's vertex is the one pinned", placed == [octant_vertex(layout, signs)[0]], placed)
    panel_phase(doc, layout, design, tool)


def panel_phase(doc, layout, design, tool):
    """The tool's task panel: the pin and the edge route in its table; a real click on the
    pin's Remove button removes it (one undo step), one on Clear all the route; a real click
    on Close ends the tool."""
    from PySide import QtGui
    from freecad.stripweave_wb import layout_tool
    from freecad.stripweave_wb.layout_pins import pins_of, routes_of
    h.wait_until(lambda: len(tool.panel.remove_buttons) == 2, 5)
    rows = [(kind, i) for kind, i, _ in tool.panel.remove_buttons]
    check("panel: two rows, the pin and the edge route", rows == [("pin", 0), ("route", 0)], rows)
    h.wait_until(lambda: "6 patches" in tool.panel.state.text(), 10)   # the panel polls the Layout
    check("panel: the layout's state", "6 patches, clean" in tool.panel.state.text(), tool.panel.state.text())
    shot = os.path.join(WORKDIR, "layout_panel.png")
    check("screenshot layout_panel.png", tool.panel.form.grab().save(shot), shot)
    if rows != [("pin", 0), ("route", 0)]:
        return
    h.click_widget(tool.panel.remove_buttons[0][2])
    h.wait_until(lambda: not pins_of(design), 10)
    check("panel: Remove removed the pin alone, undo step 'Remove layout pin'",
          pins_of(design) == [] and len(routes_of(design)) == 1
          and (doc.UndoNames or [None])[0] == "Remove layout pin", (pins_of(design), doc.UndoNames[:2]))
    h.wait_until(lambda: [(k, i) for k, i, _ in tool.panel.remove_buttons] == [("route", 0)], 5)
    h.click_widget(tool.panel.clear_all)
    h.wait_until(lambda: not routes_of(design), 10)
    check("panel: Clear all removed the route, undo step 'Clear layout pins'",
          routes_of(design) == [] and (doc.UndoNames or [None])[0] == "Clear layout pins", doc.UndoNames[:2])
    h.wait_until(lambda: not tool.panel.remove_buttons, 5)
    check("panel: the table empty again", not tool.panel.remove_buttons)
    close = None
    for box in tool.panel.form.window().findChildren(QtGui.QDialogButtonBox):
        close = box.button(QtGui.QDialogButtonBox.Close) or close
    if check("panel: a Close button", close is not None):
        h.click_widget(close)
        h.wait_until(lambda: layout_tool.active_tool() is None, 5)
        check("panel: Close ended the tool", layout_tool.active_tool() is None)


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
    Gui.runCommand("StripWeave_EditLayoutVertices")
    tool = layout_tool.active_tool()
    h.wait_until(lambda: layout_current(layout), 120)
    if check("route: tool started again", tool is not None):
        route_phase(doc, view, layout, design, tool)
    outside_phase(doc, view, layout, design)
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
