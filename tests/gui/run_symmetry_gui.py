"""GUI scenario for symmetric design (paper §5.8, issue 21), executed by FreeCAD's GUI
(started by tests/gui/test_symmetry_gui.py).  Real input only (xdotool through the X server):

A 40 x 20 x 8 slab with an off-centre boss and its mirror image in x (tests/models.py
mirrored_box): Design strips; the Options tab's symmetry (a click on the tab), Detect (a click on the
mode box, Down, Return), the detected plane x = 0 ticked (a click on its check box); the plane
is drawn; a click on the part adds a strip and its mirror image; a screenshot of the view
(STRIPWEAVE_GUI_SCREENSHOT); None turns symmetry off: design.symmetry cleared, nothing drawn.
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


def tick_first(widget):
    """A real click on the check box of the list's first row."""
    rect = widget.visualItemRect(widget.item(0))
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


def scenario():
    from models import mirrored_box
    from freecad.stripweave_wb import design_panel
    from stripweave.symmetry import loops_symmetry_error

    Gui.activateWorkbench("StripWeaveWorkbench")
    doc = App.newDocument("StripWeaveSymmetry")
    part = doc.addObject("Part::Feature", "MirroredBox")
    part.Shape = mirrored_box()
    doc.recompute()
    view = Gui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    pump(0.3)
    started = h.design_tool_on(doc, part, TRIANGLES)
    if started is None:
        return
    view, design, tool = started
    panel = tool.panel
    diagonal = part.Shape.BoundBox.DiagonalLength

    bar = panel.tabs.tabBar()
    click_tab(bar, design_panel.TABS.index("Options"))
    Gui.getMainWindow().grab().save(os.path.join(WORKDIR, "window_tab.png"))
    check("Options tab (symmetry) shown", panel.tabs.currentIndex() == design_panel.TABS.index("Options"),
          panel.tabs.currentIndex())
    h.click_widget(panel.symmetry_mode)
    h.key("Down")
    h.key("Return")
    h.wait_until(lambda: panel.symmetry_list.count() > 0, 30)
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

    start = h.screen_position(view, CLICK)
    picked = tool.pick(*start)
    if not check("the click point is visible", picked is not None and h.dist(picked, CLICK) < 0.5, picked):
        return
    h.mouse_move(view, *start)
    tool.wait_idle(60)
    h.mouse_click(1)
    h.wait_until(lambda: tool.add_serial is None, 5)
    h.wait_until(lambda: derived(tool, design), 120)
    strips = json.loads(design.DesignJson)["strips"]
    d = design.Proxy.derived(design)
    loops = [s["points"] for s in d.strips] if d is not None else []
    error = loops_symmetry_error(loops, stored[0]) if len(loops) == 2 and stored else None
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
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:3])


h.run(scenario)
