"""GUI scenario: editing committed strips with the real X pointer and
keyboard (xdotool) in the Design strips tool (paper §4.1).  Run by
tests/gui/test_edit_gui.py under Xvfb.

A torus with one strip, the meridian at phi = 0, given by a directional
anchor at P = (13, 0, 0) and a positional one at (7, 0, 0).

* Grab-and-drag: the pointer presses on the meridian at P, moves in steps
  along the outer equator to R (phi = PHI) and releases.  Checked: the
  strip's loop then passes within TOLERANCE of R's surface point (the
  meridian at phi = PHI), the strip count is unchanged, the strip has one
  directional anchor, the change is one undo step "Re-route strip", and
  Ctrl+Z restores the old anchors and loop.  Screenshot grab.png (while
  dragging).
* Anchors: a click on the strip's row in the panel lists its two anchors
  with their direction flags; selecting the directional one and clicking
  "Make positional" drops its direction, selecting the second and clicking
  "Delete anchor" deletes it; each re-derives the design (one strip, no
  error) and is one undo step.  Screenshot panel.png (the main window).
"""

import json
import math
import os
import sys

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

import FreeCAD as App  # noqa: E402
import FreeCADGui as Gui  # noqa: E402
from PySide import QtCore, QtGui  # noqa: E402

import gui_harness as h  # noqa: E402
from gui_harness import check  # noqa: E402

WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or "/tmp"
TRIANGLES = 8000
P = (13.0, 0.0, 0.0)
PHI = 0.35
R = (13.0 * math.cos(PHI), 13.0 * math.sin(PHI), 0.0)
ANCHORS = [[13.0, 0.0, 0.0, 0.0, 0.0, 1.0], [7.0, 0.0, 0.0]]
TOLERANCE = 0.4   # model units (the torus's diagonal is ~37; its mesh edges ~0.5)


def loop_of(design, index=0):
    d = design.Proxy.derived(design)
    return np.asarray(d.strips[index]["points"], dtype=float) if d is not None and len(d.strips) > index else None


def gap(points, p):
    return float(np.linalg.norm(points - np.asarray(p), axis=1).min())


def meridian_offset(points, phi):
    """How far the loop strays from the meridian half-plane at angle phi (max |angle - phi|, radians)."""
    return float(np.abs(np.arctan2(points[:, 1], points[:, 0]) - phi).max())


def anchors_of(design):
    return [[a["point"] + (a["direction"] or []) for a in s["anchors"]] for s in json.loads(design.DesignJson)["strips"]]


def wait_edit(tool, timeout=120):
    h.wait_until(lambda: tool.add_serial is None, timeout)
    return tool.wait_idle(timeout)


def cursor():
    return h.viewport_widget().cursor().shape()


def grab_and_drag(doc, view, tool, design):
    old = loop_of(design)
    start, end = h.screen_position(view, P), h.screen_position(view, R)
    picked = tool.pick(*start)
    if not check("grab: P visible", picked is not None and h.dist(picked, P) < 0.5, picked):
        return
    released_at = tool.pick(*end)
    if not check("grab: R visible", released_at is not None and h.dist(released_at, R) < 0.5, released_at):
        return
    h.mouse_move(view, *start)
    tool.wait_idle(30)
    check("grab: an open hand over the loop", cursor() == QtCore.Qt.OpenHandCursor, cursor())
    h.xdotool("mousedown", 1)
    check("grab: the press on the loop grabs strip 1", tool._grab is not None and tool._grab[0] == 0)
    check("grab: a closed hand while grabbing", cursor() == QtCore.Qt.ClosedHandCursor, cursor())
    h.drag_steps(view, start, end, 8)
    tool.wait_idle(60)
    shown = tool.shown_proposal()
    if check("grab: the moved loop shown while dragging", shown is not None, tool.panel.proposal.text()):
        pts = np.asarray(shown["points"])
        check("grab: the shown loop passes the cursor's point", gap(pts, released_at) < TOLERANCE,
              gap(pts, released_at))
    shot = os.path.join(WORKDIR, "grab.png")
    check("screenshot grab.png", h.save_screenshot(view, shot), shot)
    h.xdotool("mouseup", 1)
    wait_edit(tool)
    check("release: the hand gone", cursor() != QtCore.Qt.ClosedHandCursor, cursor())
    new = loop_of(design)
    check("release: the strip count is unchanged", design.StripCount == 1, (design.StripCount, design.Status))
    if check("release: the strip is derived", new is not None):
        h.result["info"]["grab_gap_to_release_point"] = gap(new, released_at)
        check("release: the loop passes the release point's surface point", gap(new, released_at) < TOLERANCE,
              gap(new, released_at))
        h.result["info"]["grab_meridian_offset_rad"] = meridian_offset(new, PHI)
        check("release: the loop is the meridian there", meridian_offset(new, PHI) < 0.05,
              meridian_offset(new, PHI))
    anchors = anchors_of(design)[0]
    check("release: one directional anchor at the release point",
          len(anchors) == 1 and len(anchors[0]) == 6 and h.dist(anchors[0][:3], R) < 0.5, anchors)
    if new is not None and len(anchors) == 1:
        check("release: the loop passes the anchor", gap(new, anchors[0][:3]) < TOLERANCE, gap(new, anchors[0][:3]))
    check("release: one undo step 'Re-route strip'", (doc.UndoNames or [None])[0] == "Re-route strip",
          doc.UndoNames)
    check("release: nothing selected", not Gui.Selection.getSelection())
    h.key("ctrl+z")
    h.wait_until(lambda: anchors_of(design)[0] != anchors, 10)
    tool.wait_idle(120)
    check("Ctrl+Z: the old anchors back", anchors_of(design)[0] == ANCHORS, anchors_of(design))
    back = loop_of(design)
    if check("Ctrl+Z: derived again", back is not None and old is not None):
        check("Ctrl+Z: the old loop back", len(back) == len(old) and float(np.abs(back - old).max()) < 1e-9,
              (len(back), len(old)))


def grab_second_strip(doc, view, tool, design):
    """With two strips (the meridian, then the outer equator), the equator
    grabbed at Q and dragged up the tube to T: re-routed through T under the
    meridian's mask, the meridian unchanged; undone after."""
    from freecad.stripweave_wb import design_model
    design_model.add_strip(design, [(0.0, -13.0, 0.0)])
    tool.wait_idle(60)
    meridian = loop_of(design, 0)
    q, t = h.torus_point(-0.4, 0.0), h.torus_point(-0.4, 0.6)
    start, end = h.screen_position(view, q), h.screen_position(view, t)
    if not check("two strips: Q and T visible", tool.pick(*start) is not None and tool.pick(*end) is not None):
        return
    h.mouse_move(view, *start)
    tool.wait_idle(30)
    h.xdotool("mousedown", 1)
    check("two strips: the press grabs strip 2", tool._grab is not None and tool._grab[0] == 1, tool._grab)
    h.drag_steps(view, start, end, 6)
    tool.wait_idle(60)
    h.xdotool("mouseup", 1)
    wait_edit(tool)
    anchor = anchors_of(design)[1][0]
    moved = loop_of(design, 1)
    check("two strips: still two, strip 2 through the release point",
          design.StripCount == 2 and moved is not None and h.dist(anchor[:3], t) < 0.5
          and gap(moved, anchor[:3]) < TOLERANCE,
          (design.StripCount, anchor, None if moved is None else gap(moved, anchor[:3]), design.Status))
    same = loop_of(design, 0)
    check("two strips: the meridian unchanged", same is not None and len(same) == len(meridian)
          and float(np.abs(same - meridian).max()) < 1e-9)
    doc.undo()   # the re-route
    doc.undo()   # the equator
    tool.wait_idle(60)
    check("two strips: undone", anchors_of(design) == [ANCHORS], anchors_of(design))


def edit_anchors(doc, tool, design):
    panel = tool.panel
    table = panel.table
    rect = table.visualItemRect(table.item(0, 2))   # the length column (Remove is a button)
    h.click_widget(table.viewport(), rect.center())
    h.pump(0.3)
    buttons = [b for b in table.findChildren(QtGui.QPushButton) if b.isVisible()]
    check("the strip table shows one Remove button per strip, in its column",
          len(buttons) == table.rowCount() and all(
              abs(b.geometry().center().x() - table.columnViewportPosition(1) - table.columnWidth(1) / 2.0) <= 2
              for b in buttons), [(b.objectName(), b.geometry().getRect()) for b in buttons])
    click_tab(panel, "Anchors")
    items = [panel.anchor_list.item(i).text() for i in range(panel.anchor_list.count())]
    check("select strip 1: its two anchors listed with their direction flags",
          len(items) == 2 and "directional" in items[0] and "positional" in items[1],
          (items, table.rowCount(), panel.selected_strip(), design.StripCount))
    panel_fits(panel, "panel.png")

    list_rect = panel.anchor_list.visualItemRect(panel.anchor_list.item(0))
    h.click_widget(panel.anchor_list.viewport(), list_rect.center())
    h.pump(0.2)
    check("anchor 1 selected: Make positional enabled", panel.positional.isEnabled())
    h.click_widget(panel.positional)
    wait_edit(tool)
    anchors = anchors_of(design)[0]
    check("Make positional: both anchors positional, the design re-derived",
          [len(a) for a in anchors] == [3, 3] and design.StripCount == 1 and not design.Status.startswith("error"),
          (anchors, design.StripCount, design.Status))
    check("Make positional: one undo step", (doc.UndoNames or [None])[0] == "Make anchor positional",
          doc.UndoNames)
    items = [panel.anchor_list.item(i).text() for i in range(panel.anchor_list.count())]
    check("Make positional: the list shows it", len(items) == 2 and all("positional" in t for t in items), items)

    list_rect = panel.anchor_list.visualItemRect(panel.anchor_list.item(1))
    h.click_widget(panel.anchor_list.viewport(), list_rect.center())
    h.pump(0.2)
    h.click_widget(panel.delete_anchor)
    wait_edit(tool)
    anchors = anchors_of(design)[0]
    check("Delete anchor: one anchor left, the design re-derived",
          anchors == [ANCHORS[0][:3]] and design.StripCount == 1 and not design.Status.startswith("error"),
          (anchors, design.StripCount, design.Status))
    check("Delete anchor: one undo step", (doc.UndoNames or [None])[0] == "Delete anchor", doc.UndoNames)
    list_rect = panel.anchor_list.visualItemRect(panel.anchor_list.item(0))
    h.click_widget(panel.anchor_list.viewport(), list_rect.center())
    h.pump(0.2)
    check("the last anchor cannot be deleted (Remove removes the strip)", not panel.delete_anchor.isEnabled())


def click_tab(panel, name):
    bar = panel.tabs.tabBar()
    index = [bar.tabText(i).split(" ")[0] for i in range(bar.count())].index(name)
    h.click_widget(bar, bar.tabRect(index).center())
    h.pump(0.2)
    return check("tab {} shown".format(name), panel.tabs.currentIndex() == index)


def panel_fits(panel, name):
    """The task panel fits the combo view of the default window: its scroll
    area needs no vertical scrolling.  Screenshot ``name`` (the main window)."""
    main = Gui.getMainWindow()
    shot = os.path.join(WORKDIR, name)
    check("screenshot " + name, main.grab().save(shot), shot)
    h.result["info"]["main_window_size"] = [main.width(), main.height()]
    area = panel.form.parentWidget()
    while area is not None and not isinstance(area, QtGui.QScrollArea):
        area = area.parentWidget()
    check("{}: the panel fits the default combo view (no vertical scrolling)".format(name),
          area is not None and area.verticalScrollBar().maximum() == 0,
          None if area is None else (area.verticalScrollBar().maximum(), area.viewport().height()))


def on_torus(p, tolerance=0.3):
    return abs(math.hypot(math.hypot(p[0], p[1]) - 10.0, p[2]) - 3.0) <= tolerance


def regions_and_options(doc, tool, design):
    """The Layout tab lists the regions by colour with where they are; the
    Options tab sets the compatibility band and the boundary mode, which the
    running session takes."""
    panel = tool.panel
    tool.wait_idle(60)
    click_tab(panel, "Layout")
    counts = panel.region_counts.text()
    items = [panel.region_list.item(i).text() for i in range(panel.region_list.count())]
    h.result["info"]["regions"] = [counts] + items
    check("Layout: one red region (the torus cut along one meridian is a cylinder)", "red 1 " in counts
          and "invalid" in counts, counts)
    positions = [json.loads("[" + t.split(" at (")[1].split(")")[0] + "]") for t in items if t.startswith("red at (")]
    check("Layout: the red region listed with a point on it", len(positions) == 1 and on_torus(positions[0]),
          items)
    panel_fits(panel, "layout_tab.png")

    click_tab(panel, "Options")
    check("Options: the band's precision follows the model (diagonal 37: 1e-3, steps of 0.1)",
          panel.band.decimals() == 3 and abs(panel.band.singleStep() - 0.1) < 1e-12,
          (panel.band.decimals(), panel.band.singleStep()))
    h.click_widget(panel.band)
    h.key("ctrl+a")
    h.xdotool("type", "2.5")
    h.key("Return")
    h.wait_until(lambda: json.loads(design.DesignJson)["options"].get("compatibility_band") is not None, 5)
    tool.wait_idle(120)
    band = json.loads(design.DesignJson)["options"].get("compatibility_band")
    check("Options: the band set in the design", band == 2.5, band)
    session = tool.cache.session
    check("Options: the running session takes the band",
          session is not None and session.native.compatibility_band == 2.5
          and session.design.options.get("compatibility_band") == 2.5,
          None if session is None else session.native.compatibility_band)
    check("Options: one undo step 'Set compatibility band'",
          (doc.UndoNames or [None])[0] == "Set compatibility band", doc.UndoNames)
    check("Options: the design derived with it", design.StripCount == 1 and not design.Status.startswith("error"),
          design.Status)
    panel_fits(panel, "options_tab.png")

    h.click_widget(panel.boundary)
    h.pump(0.3)
    h.key("Down")
    h.key("Return")
    h.wait_until(lambda: json.loads(design.DesignJson)["options"].get("boundary") == "trimmed", 5)
    tool.wait_idle(120)
    session = tool.cache.session
    check("Options: the boundary mode set in the design and the session",
          design.Boundary == "trimmed" and session is not None
          and session.design.options.get("boundary") == "trimmed",
          (design.Boundary, json.loads(design.DesignJson)["options"].get("boundary")))
    check("Options: the band kept", session is not None and session.native.compatibility_band == 2.5)
    click_tab(panel, "Strips")


def on_outer_equator(points):
    pts = np.asarray(points, dtype=float)
    return float(max(np.abs(pts[:, 2]).max(), np.abs(np.hypot(pts[:, 0], pts[:, 1]) - 13).max()))


def grab_current_loop(doc, view, sm):
    """A second design: Shift+click at P makes P pending; a plain drag from P
    to B (on the outer equator, 45 degrees on) grabs the current loop, which
    follows the cursor; the release adds an anchor at B (two pending, no
    strip yet) and the loop through both is the outer equator; Enter adds it."""
    design, tool = h.tool_on_new_design(doc, sm, "current loop")
    b = (9.19, -9.19, 0.0)
    h.shift_click(view, P)
    tool.wait_idle(60)
    check("current loop: one anchor pending", len(tool.pending) == 1, tool.pending)
    start, end = h.screen_position(view, P), h.screen_position(view, b)
    h.mouse_move(view, *start)
    tool.wait_idle(30)
    check("current loop: an open hand (a drag moves it)", cursor() == QtCore.Qt.OpenHandCursor, cursor())
    h.xdotool("mousedown", 1)
    h.drag_steps(view, start, end, 6)
    tool.wait_idle(60)
    shown = tool.shown_proposal()
    check("current loop: it follows the cursor while dragged",
          shown is not None and tool.point is not None and gap(np.asarray(shown["points"]), tool.point) < TOLERANCE,
          tool.panel.proposal.text())
    h.xdotool("mouseup", 1)
    tool.wait_idle(60)
    check("current loop: the release adds an anchor there, no strip yet",
          len(tool.pending) == 2 and h.dist(tool.pending[1], b) < 0.5 and design.StripCount == 0,
          (tool.pending, design.StripCount))
    shown = tool.shown_proposal()
    check("current loop: the loop through both anchors is the outer equator",
          shown is not None and shown.get("exact") and on_outer_equator(shown["points"]) < 0.3,
          None if shown is None else on_outer_equator(shown["points"]))
    h.key("Return")
    h.wait_until(lambda: tool.add_serial is None, 5)
    wait_edit(tool)
    loop = loop_of(design)
    check("current loop: Enter adds the outer equator",
          design.StripCount == 1 and loop is not None and on_outer_equator(loop) < 0.3,
          (design.StripCount, None if loop is None else on_outer_equator(loop)))
    shot = os.path.join(WORKDIR, "current_loop.png")
    check("screenshot current_loop.png", h.save_screenshot(view, shot), shot)
    tool.close()


def scenario():
    Gui.activateWorkbench("StripWeaveWorkbench")
    doc = App.newDocument("StripWeaveEdit")
    started = h.design_tool_on(doc, h.torus_in_view(doc), TRIANGLES, ANCHORS)
    if started is None:
        return
    view, design, tool = started
    check("the meridian strip", design.StripCount == 1 and meridian_offset(loop_of(design), 0.0) < 0.05,
          design.Status)
    grab_and_drag(doc, view, tool, design)
    grab_second_strip(doc, view, tool, design)
    edit_anchors(doc, tool, design)
    regions_and_options(doc, tool, design)
    tool.close()
    h.pump(0.3)
    grab_current_loop(doc, view, design.Surface)
    h.pump(0.3)
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
