"""GUI scenario for symmetric design (paper §5.8, issue 21), executed by FreeCAD's GUI
(started by tests/gui/test_symmetry_gui.py).  Real input only (xdotool through the X server):

A 40 x 20 x 8 slab with an off-centre boss and its mirror image in x (tests/models.py
mirrored_box): Design strips; the Options tab's symmetry (a click on the tab), Detect (a click on the
mode box, Down, Return), the detected plane x = 0 ticked (a click on its check box); the plane
is drawn; a click on the part adds a strip and its mirror image; a screenshot of the view
(STRIPWEAVE_GUI_SCREENSHOT); None turns symmetry off: design.symmetry cleared, nothing drawn.
Then the same slab with its bosses a half turn apart (tests/models.py turned_box): Detect lists
the rotation of order 2 and no plane; ticked, its axis is drawn; a click adds a strip and its
image under the half turn (rotation.png).
Writes the JSON result (STRIPWEAVE_GUI_RESULT) and exits with os._exit.
"""

import json
import os
import sys

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__))))

import gui_harness as h  # noqa: E402
from gui_harness import check, pump  # noqa: E402

WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or "/tmp"
SHOT = os.environ.get("STRIPWEAVE_GUI_SCREENSHOT") or os.path.join(WORKDIR, "symmetry.png")
TRIANGLES = 8000
CLICK = (16.0, 0.0, 8.0)   # on the slab's top, beside the right boss (x in [7, 13])


def tick_first(widget, row=0):
    """A real click on the check box of the list's row ``row`` (the first by default)."""
    rect = widget.visualItemRect(widget.item(row))
    option = QtGui.QStyleOptionViewItem()
    option.rect = rect
    option.features |= QtGui.QStyleOptionViewItem.HasCheckIndicator
    box = widget.style().subElementRect(QtGui.QStyle.SE_ItemViewItemCheckIndicator, option, widget)
    h.click_widget(widget.viewport(), box.center() if box.isValid() else QtCore.QPoint(rect.left() + 10,
                                                                                      rect.center().y()))


def click_tab(bar, index):
    """A real click on tab ``index`` of ``bar``, scrolled into sight first (the side tab bar
    can be taller than the task view)."""
    centre = bar.tabRect(index).center()
    parent = bar.parentWidget()
    while parent is not None and not isinstance(parent, QtGui.QScrollArea):
        parent = parent.parentWidget()
    if parent is not None:
        p = bar.mapTo(parent.widget(), centre)
        parent.ensureVisible(p.x(), p.y(), 20, 20)
        pump(0.1)
    dpr = bar.devicePixelRatioF() if hasattr(bar, "devicePixelRatioF") else 1.0
    g = bar.mapToGlobal(centre)
    h.xdotool("mousemove", int(g.x() * dpr), int(g.y() * dpr), settle=0.05)
    h.xdotool("click", 1)


def derived(tool, design):
    return (design.Proxy.derived(design) is not None and tool.worker is not None and tool.worker.idle()
            and tool.add_serial is None)


def tool_with_detected_symmetries(doc_name, name, shape):
    """A new document with ``shape``, the Design strips tool on it, its Options tab (a real
    click) and Detect (a click on the mode box, Down, Return) listing what it found.
    Returns (doc, view, design, tool, diagonal), or None when the tool did not start."""
    from freecad.stripweave_wb import design_panel
    doc = App.newDocument(doc_name)
    part = doc.addObject("Part::Feature", name)
    part.Shape = shape
    doc.recompute()
    view = Gui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    pump(0.3)
    started = h.design_tool_on(doc, part, TRIANGLES)
    if started is None:
        return None
    view, design, tool = started
    panel = tool.panel
    click_tab(panel.tabs.tabBar(), design_panel.TABS.index("Options"))
    Gui.getMainWindow().grab().save(os.path.join(WORKDIR, "window_tab_{}.png".format(name)))
    check("{}: Options tab (symmetry) shown".format(name),
          panel.tabs.currentIndex() == design_panel.TABS.index("Options"), panel.tabs.currentIndex())
    h.click_widget(panel.symmetry_mode)
    h.key("Down")
    h.key("Return")
    h.wait_until(lambda: panel.symmetry_list.count() > 0, 30)
    return doc, view, design, tool, part.Shape.BoundBox.DiagonalLength


def click_on_part(view, tool, design, label):
    """A real click at CLICK on the part, once the tool is idle; waits for the design to be
    derived.  Returns (the design's strips, the derived state), or None when CLICK is not in
    sight (checked, ``label`` first)."""
    start = h.screen_position(view, CLICK)
    picked = tool.pick(*start)
    if not check(label + "the click point is visible", picked is not None and h.dist(picked, CLICK) < 0.5, picked):
        return None
    h.mouse_move(view, *start)
    tool.wait_idle(60)
    h.mouse_click(1)
    h.wait_until(lambda: tool.add_serial is None, 5)
    h.wait_until(lambda: derived(tool, design), 120)
    return json.loads(design.DesignJson)["strips"], design.Proxy.derived(design)


def pair_error(clicked, stored):
    """(the strips, the symmetry error of the clicked strip's loop and its image's) after a
    click (click_on_part), the error None unless there are two loops and a symmetry."""
    from stripweave.symmetry import loops_symmetry_error
    strips, d = clicked
    loops = [s["points"] for s in d.strips] if d is not None else []
    return strips, loops, (loops_symmetry_error(loops, stored[0]) if len(loops) == 2 and stored else None)


def scenario():
    from models import mirrored_box

    Gui.activateWorkbench("StripWeaveWorkbench")
    opened = tool_with_detected_symmetries("StripWeaveSymmetry", "MirroredBox", mirrored_box())
    if opened is None:
        return
    doc, view, design, tool, diagonal = opened
    panel = tool.panel
    rows = [panel.symmetry_list.item(i).text() for i in range(panel.symmetry_list.count())]
    h.result["info"]["detected"] = rows
    check("Detect lists the mirror plane x = 0", any(s["kind"] == "reflection" and abs(abs(s["normal"][0]) - 1) < 1e-6
                                                    for s in panel.symmetries), rows)
    tick_first(panel.symmetry_list)
    h.wait_until(lambda: "symmetry" in json.loads(design.DesignJson), 10)
    h.wait_until(lambda: derived(tool, design), 120)
    stored = json.loads(design.DesignJson).get("symmetry") or []
    check("ticked: the design holds the reflection", len(stored) == 1 and stored[0]["kind"] == "reflection", stored)
    check("ticked: one undo step 'Set symmetry'", list(doc.UndoNames)[:1] == ["Set symmetry"], list(doc.UndoNames)[:3])
    check("the plane is drawn", tool.symmetry_overlay.plane_count() == 1, tool.symmetry_overlay.plane_count())

    clicked = click_on_part(view, tool, design, "")
    if clicked is None:
        return
    strips, loops, error = pair_error(clicked, stored)
    h.result["info"]["mirror_error"] = error
    h.result["info"]["x_means"] = [float(p[:, 0].mean()) for p in loops]
    h.result["info"]["status"] = panel.status.text()
    check("click: the strip and its mirror image (2 strips)", len(strips) == 2 and strips[1].get("image_of") == 0,
          (len(strips), panel.status.text()))
    check("the two loops are mirror images within 1e-3 of the diagonal",
          error is not None and error <= 1e-3 * diagonal, error)
    check("screenshot saved", h.save_screenshot(view, SHOT), SHOT)

    h.click_widget(panel.symmetry_mode)
    h.key("Up")
    h.key("Return")
    h.wait_until(lambda: "symmetry" not in json.loads(design.DesignJson), 10)
    h.wait_until(lambda: derived(tool, design), 120)
    check("None: design.symmetry cleared", "symmetry" not in json.loads(design.DesignJson),
          json.loads(design.DesignJson).get("symmetry"))
    check("None: nothing drawn", tool.symmetry_overlay.plane_count() == 0, tool.symmetry_overlay.plane_count())
    check("None: the mode shows None", panel.symmetry_mode.currentIndex() == 0, panel.symmetry_mode.currentText())
    check("None: the strips stay", len(json.loads(design.DesignJson)["strips"]) == 2)
    rotation_phase()
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:3])


def rotation_phase():
    """The slab with its bosses a half turn about z apart (no mirror plane): Detect lists the
    rotation of order 2; ticked, its axis is drawn, and a click on the part adds a strip and
    its image under the half turn, as exact as a mirror pair: the solver mesh is made
    symmetric under the rotation (one half turned), so the image loop searched there is the
    turned loop."""
    from models import turned_box
    from freecad.stripweave_wb import design_tool
    if design_tool.active_tool() is not None:
        design_tool.active_tool().close()
    opened = tool_with_detected_symmetries("StripWeaveRotation", "TurnedBox", turned_box())
    if opened is None:
        return
    doc, view, design, tool, diagonal = opened
    panel = tool.panel
    found = list(panel.symmetries)
    h.result["info"]["rotation_detected"] = [panel.symmetry_list.item(i).text() for i in range(panel.symmetry_list.count())]
    row = next((i for i, s in enumerate(found) if s["kind"] == "rotation" and s["order"] == 2), None)
    if not check("rotation: Detect lists the half turn about z, no mirror plane",
                 row is not None and not any(s["kind"] == "reflection" for s in found), found):
        return
    tick_first(panel.symmetry_list, row)
    h.wait_until(lambda: "symmetry" in json.loads(design.DesignJson), 10)
    h.wait_until(lambda: derived(tool, design), 120)
    stored = json.loads(design.DesignJson).get("symmetry") or []
    check("rotation: the design holds the half turn",
          len(stored) == 1 and stored[0]["kind"] == "rotation" and stored[0]["order"] == 2, stored)
    check("rotation: its axis is drawn", tool.symmetry_overlay.axis_count() == 1, tool.symmetry_overlay.axis_count())
    clicked = click_on_part(view, tool, design, "rotation: ")
    if clicked is None:
        return
    strips, _, error = pair_error(clicked, stored)
    h.result["info"].update({"rotation_error": error, "rotation_diagonal": diagonal,
                             "rotation_status": panel.status.text()})
    check("rotation: the click adds the strip and its image (2 strips)",
          len(strips) == 2 and strips[1].get("image_of") == 0, (len(strips), panel.status.text()))
    check("rotation: the two loops are each other's half-turn images within 1e-3 of the diagonal",
          error is not None and error <= 1e-3 * diagonal, error)
    check("rotation: screenshot saved", h.save_screenshot(view, os.path.join(WORKDIR, "rotation.png")))


h.run(scenario)
