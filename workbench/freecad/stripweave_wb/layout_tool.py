"""The "Edit layout vertices" tool (paper §7, manual primalization): drag
a primal vertex of a Layout object within its region, or a primal edge
through a new point of its corridor, with the mouse.

* a left press within PICK_TOLERANCE_PX of a layout vertex's dot (on the
  side of the part facing the viewer) grabs it (closed-hand cursor; an open
  hand over a vertex or an edge shows that a press would grab it);
* dragging shows a green square (a pinned vertex's dot) at the point of the part under the
  cursor while that point lies in the vertex's region (paper §7: a vertex is dragged *within*
  its region); outside it the square stays at the last point inside and the cursor shows that
  the point is refused;
* the release pins the vertex at the square (the release point, or the last point of the
  region the drag passed): the point becomes a pin
  of the Layout's Design, replacing the pin of that vertex's region
  (layout_pins.move_vertex, one undoable transaction "Move layout
  vertex"); the Layout recomputes in the background and draws the vertex,
  now placed "pinned", as a green square (layout_view.py).  A release off
  the part moves nothing;
* a left press within PICK_TOLERANCE_PX of a layout edge's line (off the
  vertices' dots) grabs the edge; the release on the part re-routes it
  through the point there (layout_pins.route_edge: an edge route of the
  Design, replacing that edge's earlier one; one undoable transaction
  "Re-route layout edge"); the point is drawn as a green square.  The
  drag is kept within the edge's corridor (its two regions) as a vertex's
  within its region;
* presses elsewhere go on to the navigation style (rotate, pan);
* preselection and selection are off in the view while the tool runs
  (view_input.ViewCapture); Esc, the command again, or Close in its task
  panel (layout_panel.py: the pins and edge routes with a Remove button
  each, Clear all, the layout's state) ends it.

Coin event callbacks never edit the document or add nodes (that would
happen during a scene traversal): the edit runs from a zero-delay timer.

Scriptable (tests, macros)::

    tool = layout_tool.start(layout_obj); tool.vertex_at(x, y); tool.edge_at(x, y); tool.close()
"""

import numpy as np

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore
from pivy import coin

from . import messages
from .layout_view import PINNED_COLOR, PINNED_SIZE
from .view_input import ViewCapture, design_objects, pick_on, set_cursor

# A press this close to a vertex's dot (screen pixels) grabs it: the dot's
# radius (9 px markers) plus a hand's slack.
PICK_TOLERANCE_PX = 8
# A vertex whose dot is under the cursor but farther than this fraction of
# the layout's diagonal from the surface point there lies behind the part.
HIDDEN_FRACTION = 0.05
POLL_MS = 400   # the panel follows the Design and the Layout's recomputes

_active = None


def active_tool():
    return _active


def start(layout_obj):
    """Start the tool on Layout ``layout_obj`` (ending one on another
    layout and the Design strips tool, which owns the same mouse).  Returns
    the tool, or None when it cannot start (reported)."""
    global _active
    from . import design_tool
    if _active is not None and not _active.closed:
        if (_active.doc_name, _active.obj_name) == (layout_obj.Document.Name, layout_obj.Name):
            return _active
        _active.close()
    view = Gui.activeDocument().activeView() if Gui.activeDocument() else None
    if view is None or not hasattr(view, "getSceneGraph"):
        messages.error("Edit layout vertices needs a 3D view: activate the document's 3D view first.")
        return None
    if design_tool.active_tool() is not None:
        design_tool.active_tool().close()
    if layout_obj.ViewObject is not None:
        layout_obj.ViewObject.Visibility = True
    if layout_obj.Proxy.mesh(layout_obj) is None:   # picks land on the tinted mesh: compute it
        layout_obj.touch()
        layout_obj.Document.recompute()
    _active = LayoutVertexTool(layout_obj, view)
    _active.open()
    return _active


def toggle(layout_obj):
    """The command: end the running tool, or start it on ``layout_obj``."""
    if _active is not None and not _active.closed:
        _active.close()
        return None
    return start(layout_obj)


class _EscFilter(QtCore.QObject):
    """Esc in the 3D viewport ends the tool (Qt sees it before Coin does)."""

    def __init__(self, tool):
        super().__init__()
        self.tool = tool

    def eventFilter(self, watched, event):
        if event.type() == QtCore.QEvent.KeyPress and event.key() == QtCore.Qt.Key_Escape:
            QtCore.QTimer.singleShot(0, self.tool.close)
            return True
        return False


class DragMarker:
    """A green square at the point a grabbed vertex would be pinned at."""

    def __init__(self):
        self.root = coin.SoSeparator()
        self.root.setName("StripWeaveLayoutDrag")
        # unpickable: it sits under the cursor, where the release picks the part
        style = coin.SoPickStyle()
        style.style = coin.SoPickStyle.UNPICKABLE
        # no depth test: the point is where the pick landed, so in sight, but
        # the surface's triangles around it would cut its square
        depth = coin.SoDepthBuffer()
        depth.test = False
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        colour = coin.SoBaseColor()
        colour.rgb.setValue(*PINNED_COLOR)   # as the vertex will be drawn
        size = coin.SoDrawStyle()
        size.pointSize = PINNED_SIZE
        self.coords = coin.SoCoordinate3()
        for node in (style, depth, light, colour, size, self.coords, coin.SoPointSet()):
            self.root.addChild(node)
        self.set(None)

    def set(self, point):
        if point is None:
            self.coords.point.setNum(0)
        else:
            self.coords.point.setValues(0, 1, [tuple(map(float, point))])
            self.coords.point.setNum(1)


class LayoutVertexTool:
    def __init__(self, obj, view):
        self.doc_name, self.obj_name = obj.Document.Name, obj.Name
        self.view = view
        self.closed = False
        self.marker = DragMarker()
        self.grabbed = None        # the vertex index while one is dragged
        self.grabbed_edge = None   # the edge index while one is dragged
        self.allowed = None        # while dragging: the regions the point may lie in (None: any)
        self.last_inside = None    # the last point of the drag inside them
        # layout.json parsed once per LayoutJson, not per mouse move: (text, layout, per edge
        # its points, the edges' diagonal), and the region mesh's triangle centroids
        self._parsed = (None, {}, [], 1.0)
        self._centroids = (None, None)
        self.last_error = None
        self._filter = _EscFilter(self)
        self._capture = None       # ViewCapture while the tool runs
        self._cursor = None
        from .layout_panel import LayoutPanel
        self.panel = LayoutPanel(self, obj.Label)
        self.timer = QtCore.QTimer()
        self.timer.setInterval(POLL_MS)
        self.timer.timeout.connect(self.refresh_panel)

    def obj(self):
        doc = App.listDocuments().get(self.doc_name)
        return doc.getObject(self.obj_name) if doc else None

    # -- life cycle -----------------------------------------------------------------
    def open(self):
        self._capture = ViewCapture(self.view, self.marker.root, (
            (coin.SoLocation2Event, self._on_move), (coin.SoMouseButtonEvent, self._on_button),
            (coin.SoKeyboardEvent, self._on_key)), self._filter)
        if Gui.Control.activeDialog():
            Gui.Control.closeDialog()
        Gui.Control.showDialog(self.panel)
        self.refresh_panel()
        self.timer.start()
        messages.message("Edit layout vertices: drag a vertex of '{}' within its region to pin it there, "
                         "or an edge to route it through a point of its corridor; Esc ends".format(self.obj().Label))

    def close(self, from_panel=False):
        """End the tool (idempotent).  ``from_panel``: the task dialog is
        closing itself (Close button), do not close it again."""
        global _active
        if self.closed:
            return
        self.closed = True
        self.timer.stop()
        self._set_cursor(None)
        if self._capture is not None:
            self._capture.release()
            self._capture = None
        if not from_panel and Gui.Control.activeDialog():
            Gui.Control.closeDialog()
        if _active is self:
            _active = None

    # -- the panel ----------------------------------------------------------------------
    def refresh_panel(self):
        from .layout_panel import layout_state
        obj = self.obj()
        if obj is None or self.closed:
            return
        try:   # the Design's JSON parsed once per poll
            design = obj.Design.Proxy.design(obj.Design) if obj.Design is not None else None
            pins, routes = (design.pins, design.edge_routes) if design is not None else ([], [])
        except Exception:   # a DesignJson that does not parse: the design's recompute says why
            pins, routes = [], []
        self.panel.refresh(pins, routes, layout_state(obj, self.layout()))

    def remove(self, kind, index):
        """The panel's Remove of pin or edge route ``index`` (``kind`` "pin" or "route")."""
        from . import layout_pins
        edit = layout_pins.remove_pin if kind == "pin" else layout_pins.remove_route
        self._panel_edit(lambda obj: edit(obj, index), "{} {} removed".format(
            "pin" if kind == "pin" else "edge route", index + 1))

    def clear_all(self):
        """The panel's Clear all: every pin and edge route of the Design."""
        from . import layout_pins
        self._panel_edit(layout_pins.clear_pins, "pins and edge routes cleared")

    def _panel_edit(self, edit, done):
        obj = self.obj()
        if obj is None or self.closed:
            return
        try:
            edit(obj)
        except Exception as exc:
            self.panel.set_status(str(exc), error=True)
            return
        self.panel.set_status(done)
        self.refresh_panel()

    # -- the layout, parsed once per recompute ----------------------------------------
    def layout(self):
        """The Layout's layout.json ({} without one), parsed again only when it changed."""
        obj = self.obj()
        text = obj.LayoutJson if obj is not None else ""
        if text != self._parsed[0]:
            layout = obj.Proxy.layout(obj) if obj is not None else {}
            points = [np.asarray(e["points"], dtype=float) for e in layout.get("edges", [])]
            everything = np.concatenate(points) if points else np.zeros((1, 3))
            self._parsed = (text, layout, points, float(np.linalg.norm(np.ptp(everything, axis=0))) or 1.0)
        return self._parsed[1]

    def region_at(self, point):
        """The region (layout.json index) under surface point ``point``
        (layout_pins.region_of_point with the mesh's centroids kept), None
        without the region mesh in memory."""
        from .layout_pins import region_of_point
        obj = self.obj()
        mesh = obj.Proxy.mesh(obj) if obj is not None else None
        if mesh is None or "region" not in mesh:
            return None
        if self._centroids[0] is not mesh:
            self._centroids = (mesh, mesh["vertices"][mesh["triangles"]].mean(axis=1))
        return region_of_point(mesh, point, self._centroids[1])

    # -- picking ---------------------------------------------------------------------
    def pick(self, x, y):
        """The point of the part under Coin position (x, y), or None."""
        obj = self.obj()
        if obj is None:
            return None
        names = {obj.Name} | (design_objects(obj.Design) if obj.Design is not None else set())
        return pick_on(self.view, names, x, y)

    def vertex_at(self, x, y):
        """The index of the layout vertex whose dot is within
        PICK_TOLERANCE_PX of Coin position (x, y) and faces the viewer (the
        nearest to the surface point there), or None."""
        vertices = self.layout().get("vertices", [])
        if not vertices:
            return None
        positions = np.asarray([v["position"] for v in vertices], dtype=float)
        screen = np.asarray([tuple(self.view.getPointOnScreen(App.Vector(*p)))[:2] for p in positions])
        near = np.flatnonzero(np.hypot(screen[:, 0] - x, screen[:, 1] - y) <= PICK_TOLERANCE_PX)
        if not len(near):
            return None
        point = self.pick(x, y)
        if point is None:
            return None
        gaps = np.linalg.norm(positions[near] - np.asarray(point), axis=1)
        diagonal = float(np.linalg.norm(np.ptp(positions, axis=0))) or 1.0
        best = int(np.argmin(gaps))
        return int(near[best]) if gaps[best] <= HIDDEN_FRACTION * diagonal else None

    def edge_at(self, x, y):
        """The index of the layout edge whose line passes within
        PICK_TOLERANCE_PX of Coin position (x, y) on the side of the part
        facing the viewer (of several, the one nearest on screen), or None."""
        if not self.layout().get("edges"):
            return None
        point = self.pick(x, y)
        if point is None:
            return None
        _, _, points, diagonal = self._parsed
        best, best_px = None, PICK_TOLERANCE_PX
        for k, pts in enumerate(points):
            # Only the edge's points near the surface point under the cursor can be
            # the line seen there: the others are projected no more.
            near = pts[np.linalg.norm(pts - np.asarray(point), axis=1) <= HIDDEN_FRACTION * diagonal]
            if not len(near):
                continue
            screen = np.asarray([tuple(self.view.getPointOnScreen(App.Vector(*p)))[:2] for p in near])
            px = float(np.min(np.hypot(screen[:, 0] - x, screen[:, 1] - y)))
            if px <= best_px:
                best, best_px = k, px
        return best

    def regions_of_grab(self):
        """The regions (layout.json indices) the grabbed vertex or edge may be
        dragged in: the vertex's region, the edge's two; None when the region
        mesh is not in memory (no restriction: the layout snaps the point)."""
        obj = self.obj()
        mesh = obj.Proxy.mesh(obj) if obj is not None else None
        if mesh is None or "region" not in mesh:
            return None
        layout = self.layout()
        vertices = layout.get("vertices", [])
        ends = [self.grabbed] if self.grabbed is not None else layout["edges"][self.grabbed_edge]["vertices"]
        return {int(vertices[v]["region"]) for v in ends}

    def inside(self, point):
        """Whether surface point ``point`` lies in the grab's regions."""
        if self.allowed is None:
            return True
        region = self.region_at(point)
        return region is not None and region in self.allowed

    def _drag_to(self, x, y):
        """The point of the drag at (x, y): the part's point there inside the
        grab's regions, else the last one inside (None if none yet)."""
        point = self.pick(x, y)
        if point is not None and self.inside(point):
            self.last_inside = point
            self._set_cursor(QtCore.Qt.ClosedHandCursor)
        else:
            self._set_cursor(QtCore.Qt.ForbiddenCursor)
        return self.last_inside

    # -- input -------------------------------------------------------------------------
    def _on_button(self, event_cb):
        ev = event_cb.getEvent()
        if ev.getButton() != coin.SoMouseButtonEvent.BUTTON1:
            return
        x, y = (int(c) for c in ev.getPosition())
        if ev.getState() == coin.SoButtonEvent.DOWN:
            self.grabbed = self.vertex_at(x, y)
            self.grabbed_edge = self.edge_at(x, y) if self.grabbed is None else None
            if self.grabbed is not None or self.grabbed_edge is not None:
                event_cb.setHandled()
                self.allowed, self.last_inside = self.regions_of_grab(), None
                self._set_cursor(QtCore.Qt.ClosedHandCursor)
        elif ev.getState() == coin.SoButtonEvent.UP and self.grabbed is not None:
            event_cb.setHandled()
            vertex, self.grabbed = self.grabbed, None
            point = self._drag_to(x, y)
            self._set_cursor(None)
            QtCore.QTimer.singleShot(0, lambda: self.drop(vertex, point))
        elif ev.getState() == coin.SoButtonEvent.UP and self.grabbed_edge is not None:
            event_cb.setHandled()
            edge, self.grabbed_edge = self.grabbed_edge, None
            point = self._drag_to(x, y)
            self._set_cursor(None)
            QtCore.QTimer.singleShot(0, lambda: self.drop_edge(edge, point))

    def _on_move(self, event_cb):
        x, y = (int(c) for c in event_cb.getEvent().getPosition())
        if self.grabbed is not None or self.grabbed_edge is not None:
            event_cb.setHandled()
            point = self._drag_to(x, y)
            if point is not None:
                self.marker.set(point)
            return
        grabbable = self.vertex_at(x, y) is not None or self.edge_at(x, y) is not None
        self._set_cursor(QtCore.Qt.OpenHandCursor if grabbable else None)

    def _on_key(self, event_cb):
        if coin.SoKeyboardEvent.isKeyPressEvent(event_cb.getEvent(), coin.SoKeyboardEvent.ESCAPE):
            event_cb.setHandled()
            QtCore.QTimer.singleShot(0, self.close)   # not inside the scene traversal

    def _set_cursor(self, shape):
        if shape != self._cursor and self._capture is not None:
            self._cursor = shape
            set_cursor(self._capture.widgets, shape)

    # -- the edit ---------------------------------------------------------------------
    def drop(self, vertex, point):
        """Pin layout vertex ``vertex`` at surface point ``point`` (None: the
        release was off the part, nothing moves).  True if the design changed."""
        from . import layout_pins
        return self._edit("vertex", vertex, point, layout_pins.move_vertex, ("not moved", "pinned at"))

    def drop_edge(self, edge, point):
        """Route layout edge ``edge`` through surface point ``point`` (None:
        the release was off the part, nothing changes).  True if the design
        changed."""
        from . import layout_pins
        return self._edit("edge", edge, point, layout_pins.route_edge, ("not re-routed", "routed through"))

    def _edit(self, what, index, point, edit, words):
        """Apply ``edit(layout, index, point)`` (a layout_pins function) and say what happened."""
        failed, done = words
        self.marker.set(None)
        obj = self.obj()
        if obj is None or self.closed:
            return False
        if point is None:
            self.last_error = "released off the part or outside its region: {} {} {}".format(what, index + 1, failed)
            messages.warning(self.last_error)
            self.panel.set_status(self.last_error, error=True)
            return False
        try:
            edit(obj, index, point)
        except Exception as exc:
            self.last_error = "{} {} {}: {}".format(what, index + 1, failed, exc)
            messages.error(self.last_error, dialog=False)
            self.panel.set_status(self.last_error, error=True)
            return False
        self.last_error = None
        text = "layout {} {} {} ({:.4g}, {:.4g}, {:.4g})".format(what, index + 1, done, *point)
        messages.message(text)
        self.panel.set_status(text)
        self.refresh_panel()
        return True
