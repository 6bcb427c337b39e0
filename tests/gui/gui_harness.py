"""What every GUI scenario script shares (imported by the scripts FreeCAD's
GUI runs, never by pytest): the JSON result, checks, event pumping, the
watchdog, and REAL input.

Real input goes through the X server: ``xdotool`` moves the pointer, presses
buttons, turns the wheel and types, exactly as a user's mouse and keyboard
would (the events pass X -> Qt -> Quarter -> the navigation style -> Coin's
scene graph, FreeCAD's selection node included).  Scenario positions are
Coin's (device pixels, origin bottom left, what ``View3DInventor.
getPointOnScreen`` gives); :func:`x11_position` turns them into root-window
pixels.

Environment: STRIPWEAVE_GUI_RESULT (the JSON file to write),
STRIPWEAVE_GUI_TIMEOUT (watchdog seconds).
"""

import json
import math
import os
import subprocess
import sys
import threading
import time

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

RESULT = os.environ.get("STRIPWEAVE_GUI_RESULT") or "/tmp/stripweave_gui_result.json"
TIMEOUT = float(os.environ.get("STRIPWEAVE_GUI_TIMEOUT", "250"))

result = {"ok": False, "checks": [], "info": {}, "error": None}
_written = threading.Lock()


def write_result_and_exit(code):
    if _written.acquire(blocking=False):
        try:
            with open(RESULT, "w") as f:
                json.dump(result, f, indent=1, sort_keys=True, default=str)
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(code)


def _watchdog():
    time.sleep(TIMEOUT)
    result["error"] = "watchdog: scenario did not finish within {} s".format(TIMEOUT)
    write_result_and_exit(3)


def check(name, ok, detail=""):
    result["checks"].append({"name": name, "ok": bool(ok), "detail": str(detail)})
    App.Console.PrintMessage("GUITEST {} {}: {}\n".format("PASS" if ok else "FAIL", name, detail))
    return bool(ok)


def pump(seconds=0.2):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.01)


def wait_until(cond, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if cond():
            return True
        pump(0.05)
    return cond()


def report_view_text():
    te = Gui.getMainWindow().findChild(QtGui.QTextEdit, "Report view")
    return te.toPlainText() if te is not None else ""


def tracebacks_in_report_view():
    return [l for l in report_view_text().splitlines() if "Traceback" in l or "internal error" in l]


def run(scenario):
    """Run ``scenario()`` once the GUI is up; write the result and exit
    (0: every check passed)."""
    def main():
        code = 1
        try:
            scenario()
            failed = [c["name"] for c in result["checks"] if not c["ok"]]
            result["failed"] = failed
            result["ok"] = not failed and bool(result["checks"])
            code = 0 if result["ok"] else 1
        except Exception:
            import traceback
            result["error"] = traceback.format_exc()
            App.Console.PrintError("GUITEST ERROR\n" + result["error"])
        result["report_view_tail"] = report_view_text()[-6000:]
        write_result_and_exit(code)

    threading.Thread(target=_watchdog, name="gui-test watchdog", daemon=True).start()
    QtCore.QTimer.singleShot(200, main)


# -- documents ---------------------------------------------------------------------

def torus_in_view(doc, name="Torus"):
    """A Part torus (radii 10 and 3, about z) in an isometric, fitted view."""
    import Part
    torus = doc.addObject("Part::Feature", name)
    torus.Shape = Part.makeTorus(10, 3)
    doc.recompute()
    view = Gui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    pump(0.3)
    return torus


def torus_point(phi, theta):
    """The point of torus_in_view's torus at angles phi (about z) and theta (about the tube)."""
    rho = 10 + 3 * math.cos(theta)
    return (rho * math.cos(phi), rho * math.sin(phi), 3 * math.sin(theta))


def design_tool_on(doc, source, triangles, anchors=(), derive_timeout=90):
    """Prepare ``source``, add a Design (with one strip through ``anchors``
    if given) and start the Design strips tool on it.  Returns (view,
    design, tool), or None when the part could not be prepared (checked)."""
    from freecad.stripweave_wb import design_commands, design_model, design_tool
    sm = prepared(doc, source, triangles)
    if not check("part prepared", sm is not None):
        return None
    view = Gui.activeDocument().activeView()
    design = design_commands.new_design(sm)
    if anchors:
        design_model.add_strip(design, [list(a) for a in anchors])
    tool = design_tool.start(design)
    check("tool: design derived", tool.wait_idle(derive_timeout) and tool.worker is not None)
    return view, design, tool


def tool_on_new_design(doc, sm, label):
    """Hide the document's designs (their stripes lie over the surface and
    would take the picks), add a new Design on ``sm`` and start the tool on
    it (checked as ``label``).  Returns (design, tool)."""
    from freecad.stripweave_wb import design_commands, design_tool
    for o in doc.Objects:
        if o.ViewObject is not None and o.Name.startswith("Design"):
            o.ViewObject.Visibility = False
    design = design_commands.new_design(sm)
    tool = design_tool.start(design)
    check("{}: tool on a new design".format(label), tool.wait_idle(90) and tool.worker is not None)
    return design, tool


def prepared(doc, source, triangles):
    """Prepare surface on ``source`` (waits for the build); its SurfaceModel or None."""
    from freecad.stripweave_wb import builder, commands
    from freecad.stripweave_wb.surface_model import is_surface_model
    commands.prepare_surface(source, target_triangles=triangles)
    builder.wait_for_builds(TIMEOUT / 3)
    pump(0.2)
    models = [o for o in doc.Objects if is_surface_model(o) and o.Source == source]
    return models[0] if models else None


# -- geometry of the view ------------------------------------------------------------

def dist(a, b):
    return math.sqrt(sum((float(x) - float(y)) ** 2 for x, y in zip(a, b)))


def viewport_widget():
    """The widget of the active 3D view that receives the mouse (the GL viewport)."""
    mdi = Gui.getMainWindow().findChild(QtGui.QMdiArea)
    sub = mdi.activeSubWindow() if mdi is not None else None
    if sub is None or sub.widget() is None:
        return None
    for gv in sub.widget().findChildren(QtGui.QGraphicsView):
        if gv.viewport() is not None:
            return gv.viewport()
    return None


def screen_position(view, point):
    """Coin position (x, y) of a model point."""
    x, y = view.getPointOnScreen(App.Vector(*point))
    return int(x), int(y)


def x11_position(view, x, y):
    """Root-window pixel of Coin position (x, y).  Qt's widget geometry is in
    logical pixels (the Xvfb screen may scale them: devicePixelRatio != 1),
    the X server and Coin count device pixels."""
    vp = viewport_widget()
    dpr = vp.devicePixelRatioF() if hasattr(vp, "devicePixelRatioF") else 1.0
    origin = vp.mapToGlobal(QtCore.QPoint(0, 0))
    height = view.getSize()[1]
    return int(round(origin.x() * dpr + x)), int(round(origin.y() * dpr + height - 1 - y))


# -- real input ------------------------------------------------------------------------

def xdotool(*args, settle=0.15):
    """Send X input events (the pointer and keyboard of the X display), then
    let Qt deliver them."""
    subprocess.run(["xdotool"] + [str(a) for a in args], check=True, timeout=20)
    pump(settle)


def mouse_move(view, x, y):
    """Move the real pointer to Coin position (x, y), in two steps (a pointer
    that jumps onto a spot gives one motion event; users give several)."""
    gx, gy = x11_position(view, x, y)
    xdotool("mousemove", gx + 3, gy + 2, settle=0.05)
    xdotool("mousemove", gx, gy)


def drag_steps(view, start, end, steps, settle=0.1):
    """Move the real pointer (a button held or not) from Coin position
    ``start`` to ``end`` in ``steps`` equal steps, as a hand would."""
    for k in range(1, steps + 1):
        x = start[0] + (end[0] - start[0]) * k / float(steps)
        y = start[1] + (end[1] - start[1]) * k / float(steps)
        xdotool("mousemove", *x11_position(view, int(round(x)), int(round(y))), settle=settle)


def shift_click(view, point):
    """Real Shift + left click on model point ``point``."""
    mouse_move(view, *screen_position(view, point))
    xdotool("keydown", "shift", settle=0.05)
    mouse_click(1)
    xdotool("keyup", "shift")


def mouse_click(button=1):
    xdotool("click", button)


def ctrl_wheel(notches):
    """Ctrl + wheel notches at the pointer: > 0 turns the wheel down (X
    button 5: the next, worse alternative), < 0 up (button 4)."""
    button = 5 if notches > 0 else 4
    xdotool("keydown", "ctrl", settle=0.05)
    try:
        for _ in range(abs(int(notches))):
            xdotool("click", button, settle=0.05)
    finally:
        xdotool("keyup", "ctrl")


def key(name):
    xdotool("key", name)


def click_widget(widget, point=None):
    """A real click in the middle of ``widget`` (or at its local QPoint
    ``point``); a widget in a scroll area (the task view) is scrolled into
    sight first, as a user would."""
    parent = widget.parentWidget()
    while parent is not None and not isinstance(parent, QtGui.QScrollArea):
        parent = parent.parentWidget()
    if parent is not None:
        parent.ensureWidgetVisible(widget)
        pump(0.1)
    dpr = widget.devicePixelRatioF() if hasattr(widget, "devicePixelRatioF") else 1.0
    centre = _settled(lambda: widget.mapToGlobal(point if point is not None else widget.rect().center()))
    xdotool("mousemove", int(centre.x() * dpr), int(centre.y() * dpr), settle=0.05)
    xdotool("click", 1, settle=0.0)


def _settled(where, timeout=2.0):
    """where() once two readings 50 ms apart agree: a panel re-lays itself out after the event
    loop runs (a table row removed moves the button below it up), and a click aimed at the
    old place missed the button on a loaded machine."""
    last, end = None, time.monotonic() + timeout
    while True:
        pump(0.05)
        now = where()
        if now == last or time.monotonic() > end:
            return now
        last = now


def save_screenshot(view, path):
    """The 3D view rendered to ``path`` at its current camera and size, so
    pixel (x, height - 1 - y) of the image is Coin position (x, y)."""
    Gui.updateGui()
    width, height = view.getSize()
    view.saveImage(path, int(width), int(height), "White")
    return os.path.isfile(path) and os.path.getsize(path) > 5000


# -- what a screenshot shows ----------------------------------------------------------

def visible_points(view, points, tolerance):
    """(point, (x, y)) for the points of the model the view shows at their
    own screen position (the pick there lands within ``tolerance`` of them:
    not hidden behind other geometry, inside the view)."""
    width, height = view.getSize()
    out = []
    for p in points:
        x, y = screen_position(view, p)
        if not (3 <= x < width - 3 and 3 <= y < height - 3):
            continue
        info = view.getObjectInfo((x, y))
        if info and dist((info["x"], info["y"], info["z"]), p) <= tolerance:
            out.append((tuple(p), (x, y)))
    return out


def colour_hits(image_path, view, positions, colour, radius=3, tolerance=0.06):
    """How many Coin ``positions`` have a pixel of ``colour`` (RGB in 0..1,
    within ``tolerance`` per channel) within ``radius`` pixels in the image
    saved by :func:`save_screenshot`."""
    image = QtGui.QImage(image_path)
    height = image.height()
    hits = 0
    for x, y in positions:
        row = height - 1 - y
        found = False
        for dx in range(-radius, radius + 1):
            for dy in range(-radius, radius + 1):
                c = QtGui.QColor(image.pixel(x + dx, row + dy))
                if all(abs(a - b) <= tolerance for a, b in zip((c.redF(), c.greenF(), c.blueF()), colour)):
                    found = True
                    break
            if found:
                break
        hits += found
    return hits


def check_loops_in_picture(label, image_path, view, loops, colours, surface_points, diagonal):
    """The picture shows each loop in its colour where it projects (most of
    its visible points), and no loop colour on surface points away from the
    loops (the check tells loops from the rest)."""
    tol = 0.01 * diagonal
    for i, (loop, colour) in enumerate(zip(loops, colours)):
        step = max(1, len(loop) // 80)
        seen = visible_points(view, loop[::step], tol)
        hits = colour_hits(image_path, view, [pos for _, pos in seen], colour)
        result["info"]["{} loop {} pixels".format(label, i + 1)] = [hits, len(seen)]
        check("{}: loop {} drawn in its colour where it projects".format(label, i + 1),
              len(seen) >= 5 and hits >= 0.8 * len(seen), (hits, len(seen), colour))
    everything = [p for loop in loops for p in loop]
    away = [p for p in surface_points if min(dist(p, q) for q in everything[::3]) > 0.15 * diagonal]
    seen = visible_points(view, away, tol)
    for i, colour in enumerate(colours):
        hits = colour_hits(image_path, view, [pos for _, pos in seen], colour)
        check("{}: no loop {} colour away from the loops".format(label, i + 1),
              len(seen) >= 5 and hits <= 0.1 * len(seen), (hits, len(seen)))
