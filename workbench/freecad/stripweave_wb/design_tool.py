"""The "Design strips" tool (paper §4.1): weave dual strips with the mouse.

* hovering the surface shows the best compatible loop through the point
  under the cursor (``DesignSession.best_loop``), as a highlighted line;
* Ctrl+wheel (or Page Down / Page Up) browses the alternatives through that
  point, best first (``DesignSession.loops([point], alternatives=6)``); the
  plain wheel still zooms;
* a click adds the strip shown, exactly that loop: from the first of its
  directional anchors (native ``loop_anchor``: a g' node of the loop, the
  one nearest the point first) from which the design's loop search derives
  the same loop again, verified by that search before the design changes
  (one undoable transaction; nothing is added, and the panel says why, if
  no anchor reproduces it).  A click where nothing is shown adds the loop
  through the picked point as a positional anchor.  The tool owns the
  click: while it runs, FreeCAD's preselection and selection are off in its
  view (``view_input.SelectionSuspended``), and the press and the release of a click
  on the model are both marked handled, so neither selects the part;
* grab-and-drag (§4.1's route-planner metaphor): a press on a committed
  strip's loop (within GRAB_TOLERANCE_PX of it; the cursor is an open hand
  there) grabs that loop; dragging
  shows the loop through the cursor along the grabbed loop's direction
  there, and the release re-routes the strip: its anchors are replaced by
  that one directional anchor and the design re-derives (one undoable
  transaction "Re-route strip"; a refused re-route changes nothing);
* Shift+click collects anchors for one strip, the preview
  shows the loop through them (and the cursor), Enter adds it, Esc drops
  them; with anchors pending, a drag grabs that current loop (§4.1): it
  follows the cursor, and the release adds an anchor there;
* a drag from a point on the model (more than CLICK_TOLERANCE_PX) sets a
  directional anchor there along the drag: the loop through the point in
  that direction follows the drag live, and the release adds it (as a click
  adds the loop shown);
* the task panel lists the strips with Remove buttons, the singularities and
  fold-overs; selecting a strip lists its anchors, which can be deleted or
  made positional (each an undoable transaction, the design re-derives);
  it lists the regions by colour with where they are and the layout's
  defects (computed on the worker after every change), and sets the
  compatibility band and the boundary mode, which the running session
  takes (re-derived in the background); Close or Esc ends the tool;
* symmetry (paper §5.8): the Symmetry tab detects the part's symmetries
  and accepts some (stored in the design, undoable); the accepted ones are
  drawn (symmetry_overlay.py: a plane, an axis) and every strip added gets
  its images (SessionCache.add_strip, stripweave.symmetry.add_images); a
  refused image leaves the design as it was, the panel says why.

Queries run on a :class:`QueryWorker` thread; a newer query interrupts an
older one, and results computed for an older cursor position or an older
design are dropped.  The GUI thread only picks, draws and edits the
document.  Coin event callbacks never add or remove nodes (that would happen
during a scene traversal): closing from a callback is deferred.

Scriptable (tests, macros)::

    tool = design_tool.start(design_obj)
    tool.hover_screen(x, y)      # what the mouse-move callback calls
    tool.hover_point((13, 0, 0)) # the same, without picking
    tool.wait_idle(); tool.preview_point_count()
    tool.browse(+1); tool.shown_proposal()
    tool.click_screen(x, y) / tool.add_at(point); tool.close()
    tool.drag_to(point, direction); tool.add_dragged()    # what a drag does
"""

import collections
import time

import numpy as np

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui
from pivy import coin

from . import derive_async, design_model, messages
from .design_overlay import PreviewOverlay
from .design_panel import DesignPanel
from .query_worker import QueryWorker
from .symmetry_overlay import SymmetryOverlay
from .view_input import ViewCapture, design_objects, pick_on, set_cursor

POLL_MS = 30
ALTERNATIVES = 6
CLICK_TOLERANCE_PX = 4
# A press this close to a committed loop (screen pixels) grabs it: about the
# width of the drawn loop line and its pick halo.
GRAB_TOLERANCE_PX = 6

_active = None


def active_tool():
    return _active


def start(obj):
    """Start the tool on Design ``obj`` (closing one running on another
    design).  Returns the tool, or None when it cannot start (reported)."""
    global _active
    if _active is not None:
        if _active.obj_name == obj.Name and _active.doc_name == obj.Document.Name and not _active.closed:
            return _active
        _active.close()
    view = Gui.activeDocument().activeView() if Gui.activeDocument() else None
    if view is None or not hasattr(view, "getSceneGraph"):
        messages.error("Design strips needs a 3D view: activate the document's 3D view first.")
        return None
    if Gui.Control.activeDialog():
        messages.error("Another task panel is open: finish or close it first, then run Design strips.")
        return None
    tool = DesignTool(obj, view)
    _active = tool
    tool.open()
    return tool


# Keyboard browsing, for users without a wheel: the next (worse) or previous alternative.
BROWSE_KEYS = {QtCore.Qt.Key_PageDown: 1, QtCore.Qt.Key_PageUp: -1}


class _ViewEventFilter(QtCore.QObject):
    """Qt filter on the 3D viewport: Ctrl+wheel and Page Down / Page Up
    browse (and do not zoom), Esc closes the tool."""

    def __init__(self, tool):
        super().__init__()
        self.tool = tool
        self._last = None

    def _first_sight(self, event, what):
        """The view (a QGraphicsView) is handed its viewport's events too:
        one notch or key press reaches both filtered widgets, with one
        timestamp.  True the first time."""
        stamp = (event.type(), event.timestamp(), what)
        if stamp == self._last:
            return False
        self._last = stamp
        return True

    def eventFilter(self, watched, event):
        try:
            kind = event.type()
            if kind == QtCore.QEvent.Wheel and (event.modifiers() & QtCore.Qt.ControlModifier):
                delta = event.angleDelta().y()
                if delta and self._first_sight(event, delta):
                    self.tool.browse(1 if delta < 0 else -1)  # wheel down: next, worse alternative
                return True
            if (kind in (QtCore.QEvent.MouseButtonPress, QtCore.QEvent.MouseButtonRelease)
                    and event.button() == QtCore.Qt.LeftButton and (event.modifiers() & QtCore.Qt.ShiftModifier)):
                # Shift+click: FreeCAD's navigation styles take Shift+button before the scene
                # graph would show it to the tool, so it is taken here, on the release.
                if kind == QtCore.QEvent.MouseButtonRelease and self._first_sight(event, "shift-click"):
                    self.tool.shift_click_widget(watched, event.pos())
                return True
            if kind in (QtCore.QEvent.KeyPress, QtCore.QEvent.KeyRelease) and event.key() in BROWSE_KEYS:
                # FreeCAD's navigation styles zoom on Page Up / Page Down,
                # some on the release too: both are the tool's while it runs.
                if kind == QtCore.QEvent.KeyPress and self._first_sight(event, event.key()):
                    self.tool.browse(BROWSE_KEYS[event.key()])
                return True
            if kind == QtCore.QEvent.KeyPress and event.key() == QtCore.Qt.Key_Escape:
                if self._first_sight(event, event.key()) and not self.tool.drop_anchors():
                    QtCore.QTimer.singleShot(0, self.tool.close)
                return True
            if kind == QtCore.QEvent.KeyPress and event.key() in (QtCore.Qt.Key_Return, QtCore.Qt.Key_Enter):
                if self._first_sight(event, event.key()):
                    self.tool.commit_anchors()
                return True
        except Exception:
            messages.log("design tool event filter: {}".format(event))
        return False


class DesignTool:
    def __init__(self, obj, view):
        self.doc_name, self.obj_name = obj.Document.Name, obj.Name
        self.view = view
        self.cache = obj.Proxy.cache()
        self.worker = None
        self.closed = False
        self.preview = PreviewOverlay()
        self.symmetry_overlay = SymmetryOverlay()
        self.panel = DesignPanel(self, obj.Label)
        self.point = None             # the surface point the proposals pass
        self.proposals = []           # loops through it: [best] or the alternatives
        self.index = 0                # the proposal shown (0: the best)
        self.want_index = 0           # asked for by the wheel, shown once computed
        self.proposal_serial = 0      # newest proposal query
        self.alternatives_requested = False
        self.add_serial = None        # strip edit (addition, re-route, anchor edit) in flight
        self.add_base = None          # DesignJson the edit is based on
        self.edit_name = None         # the transaction name of a strip edit in flight
        self._grab = None             # (strip index, its loop's points) while a loop is grabbed
        self._grab_current = False    # the loop of the strip being made is grabbed
        self._asked = (None, 0.0)     # (serial, time) of the newest proposal query
        # Milliseconds from a query (a hover, a drag step, a browse) to its preview on
        # screen, the newest last (a figure for bench notes and tests).
        self.latencies_ms = collections.deque(maxlen=1000)
        self.last_error = None
        self._seen_json = obj.DesignJson
        self._press = None
        self._press_point = None      # the surface point under the press
        self.drag_anchor = None       # (x, y, z, dx, dy, dz) while dragging
        self.pending = []             # Shift+click's anchors of the strip being made (Enter adds it)
        self._filter = _ViewEventFilter(self)
        self._filtered = []           # the view's widgets (cursor) while the tool runs
        self._capture = None          # ViewCapture while the tool runs
        self.timer = QtCore.QTimer()
        self.timer.setInterval(POLL_MS)
        self.timer.timeout.connect(self._poll)

    # -- life cycle -------------------------------------------------------------------
    def obj(self):
        doc = App.listDocuments().get(self.doc_name)
        return doc.getObject(self.obj_name) if doc else None

    def open(self):
        obj = self.obj()
        self._capture = ViewCapture(self.view, self.preview.root, (
            (coin.SoLocation2Event, self._on_move), (coin.SoMouseButtonEvent, self._on_button),
            (coin.SoKeyboardEvent, self._on_key)), self._filter)
        self._filtered = self._capture.widgets
        self._capture.scene.addChild(self.symmetry_overlay.root)
        Gui.Control.showDialog(self.panel)
        self._refresh_panel(obj)
        self.timer.start()
        self._ensure_derived(obj)

    def close(self, from_panel=False):
        """End the tool (idempotent).  ``from_panel``: the task dialog is
        closing itself (Close button), do not close it again."""
        global _active
        if self.closed:
            return
        self.closed = True
        self.timer.stop()
        if self.worker is not None:
            self.worker.stop()
        self._set_cursor(None)
        if self._capture is not None:
            self._capture.scene.removeChild(self.symmetry_overlay.root)
            self._capture.release()
            self._capture = None
        self._filtered = []
        if not from_panel and Gui.Control.activeDialog():
            Gui.Control.closeDialog()
        if _active is self:
            _active = None

    def _ensure_derived(self, obj):
        if obj.Proxy.derived(obj) is not None:
            self._ready()
            return
        self.panel.set_status("deriving the design (cross field, parameterization, strips) ...")
        derive_async.request(obj, callback=self._on_derived)

    def _on_derived(self, obj, error):
        if self.closed:
            return
        if error:
            self.panel.set_status("cannot derive the design: {}".format(error), True)
            return
        if obj is not None and obj.Proxy.derived(obj) is not None:
            obj.ViewObject.Proxy.redraw()
            self._ready()

    def _ready(self):
        if self.worker is None:
            self.worker = QueryWorker(self.cache)
        obj = self.obj()
        self.panel.set_scale(self._scale())
        self._refresh_panel(obj)
        if not self.last_error:
            self.panel.set_status(obj.Status)
        self._request_regions()
        if self.point is not None:
            self._propose()

    # -- input ---------------------------------------------------------------------------
    def _on_move(self, event_cb):
        pos = event_cb.getEvent().getPosition()
        x, y = int(pos[0]), int(pos[1])
        if self._press is not None and (abs(x - self._press[0]) > CLICK_TOLERANCE_PX
                                        or abs(y - self._press[1]) > CLICK_TOLERANCE_PX):
            event_cb.setHandled()
            if self._grab is not None:
                self.grab_screen(x, y)
            elif self._grab_current:
                self.hover_screen(x, y)   # the loop through the pending anchors and the cursor
            else:
                self.drag_screen(x, y)
            return
        self.hover_screen(x, y)

    def drag_screen(self, x, y):
        """A drag from the press point to (x, y): the loop through the press
        point along the drag (a directional anchor, paper §4.1), shown live;
        the release adds it.  Returns the anchor or None (cursor off the model)."""
        point = self.pick(x, y)
        start = self._press_point
        if point is None or start is None or self.closed:
            return None
        direction = np.subtract(point, start)
        norm = float(np.linalg.norm(direction))
        if norm <= 0.0:
            return None
        return self.drag_to(start, direction / norm)

    def drag_to(self, start, direction):
        """Show the loop through surface point ``start`` along ``direction``."""
        self.point = tuple(float(c) for c in start)
        self.drag_anchor = self.point + tuple(float(c) for c in direction)
        self.index = self.want_index = 0
        self.alternatives_requested = False
        self.proposals = []
        if self.worker is not None and not self.closed:
            self._ask("best", self.drag_anchor)
        return self.drag_anchor

    def _on_button(self, event_cb):
        """A left click that starts on the model belongs to the tool: its
        press and its release are both handled here (a release left to the
        scene graph would reach FreeCAD's selection), and a release within
        CLICK_TOLERANCE_PX of the press adds the strip.  Other buttons, and
        clicks that start off the model, go on to the navigation style."""
        ev = event_cb.getEvent()
        if ev.getButton() != coin.SoMouseButtonEvent.BUTTON1:
            return
        pos = ev.getPosition()
        x, y = int(pos[0]), int(pos[1])
        if ev.getState() == coin.SoButtonEvent.DOWN:
            self._press_point = self.pick(x, y)
            self._press = (x, y) if self._press_point is not None else None
            self.drag_anchor = None
            self._grab = None
            self._grab_current = False
            if self._press is not None:
                event_cb.setHandled()
                if self.pending:   # the strip being made: its loop passes the cursor, a drag moves it
                    self._grab_current = not (ev.wasShiftDown() or bool(
                        QtGui.QApplication.keyboardModifiers() & QtCore.Qt.ShiftModifier))
                else:
                    self._grab = self.grabbed_strip(self._press_point)
                if self._grab is not None or self._grab_current:
                    self._set_cursor(QtCore.Qt.ClosedHandCursor)
        elif ev.getState() == coin.SoButtonEvent.UP and self._press is not None:
            px, py = self._press
            self._press = None
            event_cb.setHandled()
            clicked = abs(x - px) <= CLICK_TOLERANCE_PX and abs(y - py) <= CLICK_TOLERANCE_PX
            shift = ev.wasShiftDown() or bool(QtGui.QApplication.keyboardModifiers() & QtCore.Qt.ShiftModifier)
            grab, self._grab = self._grab, None
            grab_current, self._grab_current = self._grab_current, False
            self._set_cursor(None)
            if grab is not None and not clicked:
                self.reroute_screen(grab, x, y)
            elif grab_current and not clicked:
                anchor = self.pick(x, y) or self.point
                if anchor is not None:
                    self.add_anchor(anchor)
            elif shift:
                anchor = self.pick(x, y) if clicked else self.drag_anchor
                if anchor is not None:
                    self.add_anchor(anchor)
            elif clicked:
                self.click_screen(x, y)
            elif self.drag_anchor is not None:
                self.add_dragged()

    # -- grab-and-drag ---------------------------------------------------------------------
    def grabbed_strip(self, point):
        """(index, loop points) of the committed strip whose loop passes
        within GRAB_TOLERANCE_PX of surface point ``point``, the nearest;
        None if none does."""
        obj = self.obj()
        d = obj.Proxy.derived(obj) if obj is not None else None
        if d is None or not d.strips:
            return None
        reach = GRAB_TOLERANCE_PX * self._model_per_pixel(point)
        gaps = [_polyline_gap(s["points"], point) for s in d.strips]
        best = int(np.argmin(gaps))
        return (best, np.asarray(d.strips[best]["points"], dtype=float)) if gaps[best] <= reach else None

    def _model_per_pixel(self, point):
        """Model units per screen pixel at ``point`` (across the view)."""
        view_dir = np.asarray(tuple(self.view.getViewDirection()), dtype=float)
        across = np.cross(view_dir, (0.0, 0.0, 1.0))
        if np.linalg.norm(across) < 1e-6:
            across = np.cross(view_dir, (1.0, 0.0, 0.0))
        across /= np.linalg.norm(across)
        step = 1e-3 * self._scale()
        a = self.view.getPointOnScreen(App.Vector(*point))
        b = self.view.getPointOnScreen(App.Vector(*(np.asarray(point) + step * across)))
        pixels = float(np.hypot(b[0] - a[0], b[1] - a[1]))
        return step / pixels if pixels > 0 else step

    def grab_anchor(self, grab, point):
        """The directional anchor a grabbed loop moved to ``point`` is
        re-routed through: the point, with the grabbed loop's tangent where
        it passes nearest (the loop keeps its course; §4.1)."""
        pts = grab[1]
        i = int(np.argmin(np.linalg.norm(pts - np.asarray(point), axis=1)))
        tangent = pts[min(i + 2, len(pts) - 1)] - pts[max(i - 2, 0)]
        norm = float(np.linalg.norm(tangent))
        if norm <= 0.0:   # a degenerate stretch of loop: the point alone
            return tuple(float(c) for c in point)
        return tuple(float(c) for c in point) + tuple(float(c) for c in tangent / norm)

    def grab_screen(self, x, y):
        """The grabbed loop dragged to screen position (x, y): shows the loop
        through the point there (not under the compatibility mask: the
        strip's own would refuse it; the release derives it under the mask
        of the strips before it).  Returns the anchor or None."""
        point = self.pick(x, y)
        if point is None or self._grab is None or self.closed:
            return None
        return self.grab_to(point)

    def grab_to(self, point):
        self.point = tuple(float(c) for c in point)
        self.drag_anchor = self.grab_anchor(self._grab, self.point)
        self.index = self.want_index = 0
        self.alternatives_requested = False
        self.proposals = []
        if self.worker is not None and not self.closed:
            self._ask("best", self.drag_anchor, masked=False)
        return self.drag_anchor

    def reroute_screen(self, grab, x, y):
        """Release of a grab at (x, y): re-route the strip through the point there."""
        point = self.pick(x, y)
        anchor = self.grab_anchor(grab, point) if point is not None else self.drag_anchor
        self.drag_anchor = None
        if anchor is None:
            return False
        return self.edit_strip(grab[0], [anchor], "Re-route strip")

    def edit_strip(self, index, anchors, name):
        """Replace strip ``index``'s anchors (off the GUI thread); the
        document changes in one transaction ``name`` if the design derives."""
        obj = self.obj()
        if self.worker is None or obj is None or self.add_serial is not None:
            return False
        self.add_base = obj.DesignJson
        self.edit_name = name
        self.add_serial = self.worker.edit_strip(index, anchors)
        self.panel.set_busy(True)
        self.panel.set_status("{} {} ...".format(name.lower(), index + 1))
        return True

    # -- anchors of a committed strip (the panel's anchor list) -------------------------------
    def strip_anchors(self, index):
        """Strip ``index``'s anchors as (x,y,z[,dx,dy,dz]) lists."""
        obj = self.obj()
        lists = obj.Proxy.design(obj).anchor_lists() if obj is not None else []
        return lists[index] if 0 <= index < len(lists) else []

    def delete_anchor(self, index, anchor):
        """Delete anchor ``anchor`` of strip ``index`` (its last anchor stays:
        removing the strip is Remove's)."""
        anchors = self.strip_anchors(index)
        if len(anchors) < 2 or not 0 <= anchor < len(anchors):
            return False
        return self.edit_strip(index, anchors[:anchor] + anchors[anchor + 1:], "Delete anchor")

    def make_positional(self, index, anchor):
        """Drop the direction of anchor ``anchor`` of strip ``index``."""
        anchors = self.strip_anchors(index)
        if not 0 <= anchor < len(anchors) or len(anchors[anchor]) != 6:
            return False
        anchors[anchor] = anchors[anchor][:3]
        return self.edit_strip(index, anchors, "Make anchor positional")

    def _refresh_panel(self, obj):
        try:
            design = obj.Proxy.design(obj)
        except Exception:
            design = None
        self.panel.refresh(obj.Proxy.summary(obj), design.anchor_lists() if design is not None else [])
        if design is not None:
            self.panel.set_options(design.options)
            self.panel.set_accepted_symmetry(design.symmetry or [])
            self.symmetry_overlay.set(design.symmetry or [], _bounding_box(obj))

    # -- symmetry (the panel's Symmetry tab) ---------------------------------------------
    def detect_symmetry(self):
        """The part's symmetries (design_model.detect_symmetry), [] with the reason in the
        status line when detection fails."""
        obj = self.obj()
        if obj is None:
            return []
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            found = design_model.detect_symmetry(obj)
        except Exception as exc:
            self.panel.set_status("symmetry not detected: {}".format(exc), True)
            return []
        finally:
            QtGui.QApplication.restoreOverrideCursor()
        self.panel.set_status("{} symmetr{} found: tick one to add every strip with its images".format(
            len(found), "y" if len(found) == 1 else "ies") if found else "no symmetry found")
        return found

    def accepted_symmetry(self):
        obj = self.obj()
        return design_model.symmetry(obj) if obj is not None else []

    def set_symmetry(self, symmetries):
        """Accept ``symmetries`` ([] turns symmetry off): one undoable transaction; the
        drawing follows."""
        obj = self.obj()
        if obj is None:
            return False
        if self.add_serial is not None:   # an addition in flight was made under the old ones
            self.panel.set_status("wait for the strip being added, then set the symmetry", True)
            self._refresh_panel(obj)
            return False
        try:
            changed = design_model.set_symmetry(obj, symmetries)
        except Exception as exc:
            self.panel.set_status("symmetry not set: {}".format(exc), True)
            self._refresh_panel(obj)
            return False
        self._seen_json = obj.DesignJson
        self._refresh_panel(obj)
        if changed:   # derived again: the solver mesh is made symmetric under the reflections
            self.proposals = []
            self.preview.clear()
            self.panel.set_status("symmetry {}: deriving the design ...".format("accepted" if symmetries else "off"))
            derive_async.request(obj, callback=self._on_derived, then_recompute=True)
        return changed

    def _request_regions(self):
        if self.worker is not None and not self.closed:
            self.panel.set_regions(None)
            self.worker.regions()

    def set_options(self, **options):
        """The panel's Options: change the design's options (one undoable
        transaction); the session takes them in the background (a new
        DesignState; a new loop engine for the boundary mode)."""
        obj = self.obj()
        if obj is None or self.add_serial is not None:
            self._refresh_panel(obj) if obj is not None else None
            return False
        try:
            changed = design_model.set_options(obj, **options)
        except Exception as exc:
            self.panel.set_status("option not set: {}".format(exc), True)
            self._refresh_panel(obj)
            return False
        if changed:
            self._seen_json = obj.DesignJson
            self._refresh_panel(obj)
            self.proposals = []
            self.preview.clear()
            self.panel.set_status("deriving the design with the new options ...")
            derive_async.request(obj, callback=self._on_derived, then_recompute=True)
        return changed

    def _on_key(self, event_cb):
        ev = event_cb.getEvent()
        if coin.SoKeyboardEvent.isKeyPressEvent(ev, coin.SoKeyboardEvent.ESCAPE):
            event_cb.setHandled()
            if not self.drop_anchors():
                QtCore.QTimer.singleShot(0, self.close)  # not inside the scene traversal

    def pick(self, x, y):
        """The point of the model under screen position (x, y) (Coin
        coordinates, origin bottom left), or None."""
        obj = self.obj()
        return pick_on(self.view, design_objects(obj), x, y) if obj is not None else None

    def hover_screen(self, x, y):
        """Mouse moved to (x, y): propose the best loop through the point
        under the cursor.  Returns the picked point or None (off the model)."""
        if self.closed:
            return None
        point = self.pick(x, y)
        # anchors pending: the current loop passes the cursor, a drag moves it
        self._set_cursor(QtCore.Qt.OpenHandCursor if point is not None and (
            self.pending or self.grabbed_strip(point) is not None) else None)
        if point is not None:
            self.hover_point(point)
        return point

    def _set_cursor(self, shape):
        """An open hand over a committed loop (a press grabs it), a closed
        hand while one is grabbed; FreeCAD's cursor elsewhere."""
        if shape == getattr(self, "_cursor", None):
            return
        self._cursor = shape
        set_cursor(self._filtered, shape)

    def hover_point(self, point):
        """Propose the best loop through ``point`` (a surface point)."""
        self.point = tuple(float(c) for c in point)
        self.drag_anchor = None
        self.index = self.want_index = 0
        self.alternatives_requested = False
        self.proposals = []
        self._propose()

    def browse(self, step):
        """Show the next (step > 0) or previous alternative through the point."""
        if self.point is None or self.worker is None:
            return
        self.want_index = max(0, min(ALTERNATIVES - 1, self.want_index + int(step)))
        if not self.alternatives_requested:
            self.alternatives_requested = True
            self._ask("alternatives", self.point, ALTERNATIVES)
            self.panel.set_proposal("searching alternatives ...")
        else:
            self._show()

    def click_screen(self, x, y):
        point = self.pick(x, y)
        if point is None:
            return False
        return self.add_at(point)

    def add_at(self, point):
        """Add the strip shown (when ``point`` is near the hovered point), or
        the strip through ``point`` as a positional anchor."""
        obj = self.obj()
        if self.worker is None or obj is None or self.add_serial is not None:
            return False
        shown = self.shown_proposal() if self._near(point) else None
        self.add_base = obj.DesignJson
        if shown is not None and shown.get("exact"):
            self.add_serial = self.worker.add_strip(shown["anchors"])
            self.pending = []
        elif shown is not None:
            self.add_serial = self.worker.add_strip(shown["anchors"], shown=shown["points"])
        else:
            self.add_serial = self.worker.add_strip([list(map(float, point))])
        self.panel.set_busy(True)
        self.panel.set_status("adding the strip ...")
        return True

    def shift_click_widget(self, widget, pos):
        """Shift+click at Qt position ``pos`` of the viewport ``widget``: the
        point there becomes one more anchor (Coin counts device pixels from
        the bottom left)."""
        dpr = widget.devicePixelRatioF() if hasattr(widget, "devicePixelRatioF") else 1.0
        height = self.view.getSize()[1]
        point = self.pick(int(round(pos.x() * dpr)), int(round(height - 1 - pos.y() * dpr)))
        return self.add_anchor(point) if point is not None else None

    def add_anchor(self, anchor):
        """Shift+click: one more anchor for the strip being made; the
        preview shows the loop through all of them."""
        self.pending.append([float(c) for c in anchor])
        self.point = tuple(self.pending[-1][:3])
        self.drag_anchor = None
        self.index = self.want_index = 0
        self.alternatives_requested = False
        self.proposals = []
        self.panel.set_status("{} anchor{} for the next strip: Shift+click adds more, Enter adds the strip, "
                              "Esc drops them".format(len(self.pending), "" if len(self.pending) == 1 else "s"))
        self._propose()
        return len(self.pending)

    def commit_anchors(self):
        """Enter: add the strip through the Shift+click anchors."""
        obj = self.obj()
        if not self.pending or self.worker is None or obj is None or self.add_serial is not None:
            return False
        self.add_base = obj.DesignJson
        self.add_serial = self.worker.add_strip([list(a) for a in self.pending])
        self.pending = []
        self.panel.set_busy(True)
        self.panel.set_status("adding the strip through the anchors ...")
        return True

    def drop_anchors(self):
        """Esc with anchors pending drops them (a second Esc ends the tool)."""
        if not self.pending:
            return False
        self.pending = []
        self.proposals = []
        self.preview.clear()
        self.panel.set_status("anchors dropped")
        return True

    def add_dragged(self):
        """The release of a drag: add the loop shown along it (once its
        query has answered; before that, the directional anchor itself)."""
        obj = self.obj()
        if self.worker is None or obj is None or self.add_serial is not None or self.drag_anchor is None:
            return False
        shown = self.shown_proposal()
        self.add_base = obj.DesignJson
        if shown is not None:
            self.add_serial = self.worker.add_strip(shown["anchors"], shown=shown["points"])
        else:
            self.add_serial = self.worker.add_strip([list(self.drag_anchor)])
        self.drag_anchor = None
        self.panel.set_busy(True)
        self.panel.set_status("adding the strip along the drag ...")
        return True

    def shown_proposal(self):
        """The proposal the preview shows (a dict as SessionCache.proposals), or None."""
        if self.proposals and 0 <= self.index < len(self.proposals) and self.preview_point_count():
            return self.proposals[self.index]
        return None

    def remove(self, index):
        obj = self.obj()
        if obj is None or self.add_serial is not None:
            return
        try:
            design_model.remove_strip(obj, index)
        except Exception as exc:
            messages.error("cannot remove strip {}: {}".format(index + 1, exc))
        self._after_edit(obj)

    # -- results (GUI thread, QTimer) ------------------------------------------------------
    def _poll(self):
        try:
            self._step()
        except Exception:
            import traceback
            messages.error("design tool: internal error:\n" + traceback.format_exc(), dialog=False)

    def _step(self):
        obj = self.obj()
        if obj is None:
            self.close()
            return
        if obj.DesignJson != self._seen_json:  # undo/redo, import, property edits
            self._seen_json = obj.DesignJson
            self.proposals = []
            self.preview.clear()
            self._refresh_panel(obj)
            if obj.Proxy.derived(obj) is None:
                self._ensure_derived(obj)
            else:
                self._request_regions()
                if self.point is not None:
                    self._propose()
        if self.worker is None:
            return
        for r in self.worker.take_results():
            if r.kind in ("add", "edit"):
                self._on_edited(obj, r)
            elif r.kind == "regions":
                if r.error or r.revision == self.cache.revision:
                    self.panel.set_regions(None if r.error else r.value, r.error)
            elif r.cancelled or r.serial != self.proposal_serial:
                continue  # an older cursor position
            elif r.error:
                self.proposals = []
                self.preview.clear()
                self.panel.set_proposal("no compatible strip through this point: {}".format(r.error))
            elif r.revision != self.cache.revision:
                self._propose()  # computed before the design changed
            else:
                self.proposals = list(r.value)
                self._show()

    def _on_edited(self, obj, r):
        self.add_serial = None
        self.panel.set_busy(False)
        name = "Add strip" if r.kind == "add" else self.edit_name
        if r.error:
            self.last_error = r.error
            what = "strip not added" if r.kind == "add" else "{}: nothing changed".format(name)
            self.panel.set_status("{}: {}".format(what, r.error), True)
            messages.warning("{}: {}".format(what, r.error))
            if r.kind == "edit":
                self._ensure_derived(obj)   # the session reverted the edit; the view is current
            return
        if obj.DesignJson != self.add_base:  # the design changed meanwhile: this edit is stale
            self.panel.set_status("the design changed while the strip was edited; try again", True)
            self._ensure_derived(obj)
            return
        self.last_error = None
        design_model.write_design(obj, r.value, name)
        self._after_edit(obj)

    def _after_edit(self, obj):
        self._seen_json = obj.DesignJson
        self._refresh_panel(obj)
        if not self.last_error:
            self.panel.set_status(obj.Status, obj.Status.startswith("error"))
        self.proposals = []
        self.preview.clear()
        if obj.Proxy.derived(obj) is None:
            self._ensure_derived(obj)
            return
        self._request_regions()
        if self.point is not None:
            self.hover_point(self.point)  # the next proposal, under the new mask: the best again

    def _propose(self):
        if self.worker is None or self.point is None or self.closed:
            return
        if derive_async.pending(self.obj()):
            return  # the session is catching up with the design; _ready proposes again
        where = self.drag_anchor if self.drag_anchor is not None else self.point
        if self.pending:   # the strip being made: its anchors, and the cursor's unless it is the last one
            extra = [] if tuple(self.pending[-1][:3]) == tuple(where[:3]) else [list(where)]
            where = tuple(tuple(a) for a in self.pending + extra)
        if self.alternatives_requested:
            self._ask("alternatives", where, ALTERNATIVES)
        else:
            self._ask("best", where, masked=self._grab is None)

    def _ask(self, kind, where, alternatives=1, masked=True):
        """Queue a proposal query; the newest is the one shown."""
        self.proposal_serial = self.worker.propose(kind, where, alternatives, masked)
        self._asked = (self.proposal_serial, time.monotonic())

    def _show(self):
        if not self.proposals:
            return
        serial, asked = self._asked
        if serial == self.proposal_serial:   # first shown for this query: its latency on screen
            self.latencies_ms.append(1000.0 * (time.monotonic() - asked))
            self._asked = (None, 0.0)
        self.index = min(self.want_index, len(self.proposals) - 1)
        loop = self.proposals[self.index]
        points, anchor = self._lifted(loop["points"], self.point)
        self.preview.set_loop(points, anchor)
        which = "best" if self.index == 0 else "alternative {} of {}".format(self.index + 1, len(self.proposals))
        self.panel.set_proposal("{}: {} loop, length {:.4g}, cost {:.4g}".format(
            which, "closed" if loop.get("closed") else "open", loop["length"], loop["cost"]))

    def _lifted(self, points, anchor):
        """The preview floats above the design's loops (lift.py)."""
        obj = self.obj()
        d = obj.Proxy.derived(obj) if obj is not None else None
        if d is None:
            return points, anchor
        from .design_view import MARKER_LIFT
        settings = getattr(obj.ViewObject.Proxy, "settings", None) or {}
        fraction = MARKER_LIFT * float(settings.get("lift", 0.002))
        return d.lift.lift(points, fraction), tuple(d.lift.lift([anchor], fraction)[0])

    def _near(self, point):
        if self.point is None:
            return False
        return float(np.linalg.norm(np.subtract(point, self.point))) <= 0.02 * self._scale()

    def _scale(self):
        """The solver mesh's bounding-box diagonal (1 before it is derived)."""
        obj = self.obj()
        d = obj.Proxy.derived(obj) if obj is not None else None
        return float(np.linalg.norm(np.ptp(d.vertices, axis=0))) if d is not None and len(d.vertices) else 1.0

    # -- for tests and macros --------------------------------------------------------------
    def preview_point_count(self):
        return self.preview.point_count()

    def wait_idle(self, timeout=30.0):
        """Process GUI events until the worker has nothing to do and its
        results are handled.  True if that happened within ``timeout``."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            QtGui.QApplication.processEvents(QtCore.QEventLoop.AllEvents, 20)
            if (self.worker is not None and self.worker.idle() and self.add_serial is None
                    and not derive_async.pending(self.obj())):
                self._poll()
                return True
            time.sleep(0.01)
        return False


def _polyline_gap(points, point):
    """Distance from ``point`` to the polyline ``points`` ((k, 3))."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    p = np.asarray(point, dtype=float)
    if len(pts) == 1:
        return float(np.linalg.norm(pts[0] - p))
    a, b = pts[:-1], pts[1:]
    ab = b - a
    length2 = np.maximum((ab * ab).sum(axis=1), 1e-300)
    t = np.clip(((p - a) * ab).sum(axis=1) / length2, 0.0, 1.0)
    return float(np.linalg.norm(a + t[:, None] * ab - p, axis=1).min())


def _bounding_box(obj):
    """The part's bounding box (xmin, ymin, zmin, xmax, ymax, zmax): its source shape's, else
    the derived solver mesh's; None when neither is there (nothing is drawn)."""
    sm = obj.Surface
    source = getattr(sm, "Source", None) if sm is not None else None
    shape = getattr(source, "Shape", None)
    if shape is not None and not shape.isNull():
        b = shape.BoundBox
        return (b.XMin, b.YMin, b.ZMin, b.XMax, b.YMax, b.ZMax)
    derived = obj.Proxy.derived(obj)
    if derived is not None and len(derived.vertices):
        return tuple(derived.vertices.min(axis=0)) + tuple(derived.vertices.max(axis=0))
    return None
