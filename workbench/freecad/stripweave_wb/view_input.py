"""What a tool that owns the mouse in the 3D view needs (GUI only): the
Design strips tool (design_tool.py) and Edit layout vertices
(layout_tool.py).

* :class:`ViewCapture`: while a tool runs, its Coin event callbacks, a Qt
  event filter on the viewport's widgets, its overlay node in the scene,
  and preselection and selection off (:class:`SelectionSuspended`);
  ``release()`` undoes all of it;
* :func:`pick_on`: the point of the part under a screen position, if it
  lies on given objects (:func:`design_objects`: a design's part);
* :func:`set_cursor`: the cursor over the view's widgets.
"""

import FreeCADGui as Gui
from PySide import QtGui


class ViewCapture:
    """A tool's hold on ``view``: ``overlay`` (a Coin node) added to its
    scene, ``handlers`` ((SoEvent class, callback), ...) as event
    callbacks, ``qt_filter`` on the viewport widgets (``widgets``), and
    selection suspended, until :meth:`release`."""

    def __init__(self, view, overlay, handlers, qt_filter):
        self.view, self.overlay, self.qt_filter = view, overlay, qt_filter
        self.scene = view.getSceneGraph()
        self.scene.addChild(overlay)
        self.selection = SelectionSuspended(self.scene)
        self.callbacks = [(cls, view.addEventCallbackPivy(cls.getClassTypeId(), fn)) for cls, fn in handlers]
        self.widgets = viewport_widgets()
        for w in self.widgets:
            w.installEventFilter(qt_filter)

    def release(self):
        for cls, cb in self.callbacks:
            try:
                self.view.removeEventCallbackPivy(cls.getClassTypeId(), cb)
            except Exception:   # the view was closed
                pass
        self.callbacks = []
        for w in self.widgets:
            try:
                w.removeEventFilter(self.qt_filter)
            except RuntimeError:
                pass
        self.widgets = []
        self.selection.restore()
        self.scene.removeChild(self.overlay)


def design_objects(design):
    """The names of what a pick on ``design``'s part may land on: the
    design, its SurfaceModel and the part."""
    names = {design.Name}
    sm = design.Surface
    if sm is not None:
        names.add(sm.Name)
        if sm.Source is not None:
            names.add(sm.Source.Name)
    return names


def pick_on(view, names, x, y):
    """The point under Coin position (x, y) of ``view`` if it lies on one
    of the objects ``names``, else None."""
    info = view.getObjectInfo((int(x), int(y)))
    if not info or not (names & {info.get("Object"), info.get("ParentObject")}):
        return None
    return (float(info["x"]), float(info["y"]), float(info["z"]))


def set_cursor(widgets, shape):
    """``shape`` (a Qt cursor shape) over the view's widgets; None: FreeCAD's."""
    for w in widgets:
        try:
            if shape is None:
                w.unsetCursor()
            else:
                w.setCursor(QtGui.QCursor(shape))
        except RuntimeError:   # the view was closed
            pass



class SelectionSuspended:
    """Preselection and selection off in one view while a tool runs.

    FreeCAD's selection node (SoFCUnifiedSelection, the root of the view's
    scene graph) handles a button release before the event reaches any
    event callback below it, and marks it handled when the cursor is over a
    part: the tool would see the press but never the release, and the click
    would select the part.  Its ``highlightMode`` and ``selectionMode``
    fields switch both off for this view only (what FreeCAD's own
    EnablePreselection / EnableSelection preferences set, without touching
    the user's parameters); :meth:`restore` puts the old values back."""

    OFF = 2  # SoFCUnifiedSelection::OFF (its HighlightModes: AUTO, ON, OFF)

    def __init__(self, scene):
        self.scene = scene  # keeps the node (and so its fields) alive until restore
        self.fields = []
        for name in ("highlightMode", "selectionMode"):
            field = scene.getField(name) if scene is not None else None
            if field is not None:
                self.fields.append((field, field.getValue()))
                field.setValue(self.OFF)
        Gui.Selection.clearPreselection()
        Gui.Selection.clearSelection()

    def restore(self):
        for field, value in self.fields:
            field.setValue(value)
        self.fields = []
        self.scene = None


def viewport_widgets():
    """The widgets of the active 3D view that receive mouse and key events."""
    mw = Gui.getMainWindow()
    mdi = mw.findChild(QtGui.QMdiArea)
    sub = mdi.activeSubWindow() if mdi is not None else None
    if sub is None or sub.widget() is None:
        return []
    out = []
    for gv in sub.widget().findChildren(QtGui.QGraphicsView):
        out.append(gv)
        if gv.viewport() is not None:
            out.append(gv.viewport())
    return out
