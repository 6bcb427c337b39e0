"""View provider of the Design object: draws the strips as stripe patterns
on the surface, the loops as thick lines in their strip's hue, and the cross
field's singularities as markers (+1/4 blue, -1/4 red, other green).

Display mode "Stripes" (design_overlay.py); the Part display modes still show
the Shape (the loops as wires) for selection and reuse.  The view settings
are persisted as JSON (the proxy state) and mirrored in view properties for
the property editor.  Drawing reads an immutable snapshot of the derived
state (``DesignModel.derived``); until there is one (a document just
reopened) the loops come from the stored Shape, the singularities from the
stored Summary, and the stripes follow when the background derivation ends.
"""

import numpy as np

import FreeCAD as App

from . import icon_path, messages

# setting -> (property type, property name, tooltip, default, constraint or None)
SETTINGS = {
    "stripe_period": ("App::PropertyFloat", "StripePeriod",
                      "Distance between stripes in model units (0: from the mesh density)", 0.0, None),
    "stripe_strength": ("App::PropertyFloatConstraint", "StripeStrength",
                        "How strongly the stripes tint the surface (0..1)", 0.85, (0.0, 1.0, 0.05)),
    "lift": ("App::PropertyFloatConstraint", "StripeLift",
             "Stripes float this fraction of the model size off the surface", 0.002, (0.0, 0.05, 0.0005)),
    "loop_width": ("App::PropertyFloatConstraint", "LoopWidth", "Line width of the loops (pixels)",
                   5.0, (1.0, 20.0, 1.0)),
    "marker_size": ("App::PropertyIntegerConstraint", "MarkerSize",
                    "Size of the singularity markers (pixels: 5, 7, 9, 11, 13, 15)", 13, (5, 15, 2)),
    "show_stripes": ("App::PropertyBool", "ShowStripes", "Show the stripe patterns", True, None),
    "show_loops": ("App::PropertyBool", "ShowLoops", "Show the loops", True, None),
    "show_singularities": ("App::PropertyBool", "ShowSingularities", "Show the singularities", True, None),
}
PROPERTY_TO_SETTING = {spec[1]: key for key, spec in SETTINGS.items()}
# Lines and markers float above the stripes: multiples of the stripes' lift.
LOOP_LIFT = 2.0
MARKER_LIFT = 2.5


def default_settings():
    return {key: spec[3] for key, spec in SETTINGS.items()}


class ViewProviderDesign:
    def __init__(self, vobj):
        self.settings = default_settings()
        vobj.Proxy = self
        self._add_properties(vobj)

    def _add_properties(self, vobj):
        have = set(vobj.PropertiesList)
        for key, (ptype, name, tip, _default, constraint) in SETTINGS.items():
            if name in have:
                continue
            vobj.addProperty(ptype, name, "StripWeave", tip)
            value = self.settings.get(key, SETTINGS[key][3])
            setattr(vobj, name, (value,) + constraint if constraint else value)

    # -- FreeCAD view provider protocol ---------------------------------------------
    def attach(self, vobj):
        from . import design_overlay
        self.Object = vobj.Object
        if not hasattr(self, "settings"):
            self.settings = default_settings()
        self._add_properties(vobj)
        self._requested = None
        self.overlay = design_overlay.DesignOverlay(self.settings["loop_width"], self.settings["marker_size"])
        self._apply_visibility()
        vobj.addDisplayMode(self.overlay.root, "Stripes")
        self.redraw()

    def getDisplayModes(self, vobj):
        return ["Stripes"]

    def getDefaultDisplayMode(self):
        return "Stripes"

    def setDisplayMode(self, mode):
        return mode

    def getIcon(self):
        return icon_path("Design.svg")

    def updateData(self, obj, prop):
        if prop in ("Summary", "DesignJson", "Surface", "Features"):
            self.redraw()

    def onChanged(self, vobj, prop):
        key = PROPERTY_TO_SETTING.get(prop)
        if key is None or not hasattr(self, "settings"):
            return
        value = getattr(vobj, prop)
        self.settings[key] = bool(value) if isinstance(SETTINGS[key][3], bool) else type(SETTINGS[key][3])(value)
        ov = getattr(self, "overlay", None)
        if ov is None:
            return
        if key.startswith("show_"):
            self._apply_visibility()
        elif key == "loop_width":
            ov.loops.set_width(self.settings["loop_width"])
        elif key == "marker_size":
            ov.singularities.set_size(self.settings["marker_size"])
        else:
            self.redraw()

    def doubleClicked(self, vobj):
        from . import design_tool
        design_tool.start(vobj.Object)
        return True

    def setupContextMenu(self, vobj, menu):
        from PySide import QtGui
        action = QtGui.QAction("Design strips", menu)
        action.triggered.connect(lambda: self.doubleClicked(vobj))
        menu.addAction(action)

    def onDelete(self, vobj, subelements):
        from . import design_tool
        tool = design_tool.active_tool()
        if tool is not None and tool.obj_name == vobj.Object.Name:
            tool.close()
        return True

    # -- persistence: the view settings as JSON ----------------------------------------
    def __getstate__(self):
        return {"settings": dict(getattr(self, "settings", default_settings()))}

    def __setstate__(self, state):
        self.settings = default_settings()
        if isinstance(state, dict):
            self.settings.update({k: v for k, v in (state.get("settings") or {}).items() if k in SETTINGS})
        return None

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        return self.__setstate__(state)

    # -- drawing ----------------------------------------------------------------------
    def _apply_visibility(self):
        s = self.settings
        self.overlay.show(s["show_stripes"], s["show_loops"], s["show_singularities"])

    def redraw(self):
        """Draw from the derived snapshot, or from the stored results while
        the snapshot is being derived."""
        ov = getattr(self, "overlay", None)
        obj = getattr(self, "Object", None)
        try:
            if ov is None or obj is None or obj.Proxy is None:
                return
            state = obj.State
        except (ReferenceError, RuntimeError, AttributeError):  # deleted, or its document closed
            return
        if "Restore" in state:
            # properties arrive one by one while a document loads: draw once it is complete
            if not getattr(self, "_redraw_pending", False):
                from PySide import QtCore
                self._redraw_pending = True
                QtCore.QTimer.singleShot(100, self._deferred_redraw)
            return
        try:
            derived = obj.Proxy.derived(obj)
            if derived is not None:
                self._draw_derived(derived)
            else:
                self._draw_stored(obj)
                self._request_derivation(obj)
        except Exception as exc:
            messages.log("design overlay not drawn: {}".format(exc))

    def _deferred_redraw(self):
        self._redraw_pending = False
        self.redraw()

    def _draw_derived(self, d):
        s = self.settings
        ov = self.overlay
        lift = s["lift"]
        if len(d.vertices):
            period = s["stripe_period"] or stripe_period(d)
            ov.set_stripes(d.vertices, d.normals, d.triangles, [st["across"] for st in d.strips],
                           period, s["stripe_strength"], lift * d.lift.diagonal)
        # lines and markers above the stripes (lift.py)
        ov.set_loops([d.lift.lift(st["points"], LOOP_LIFT * lift) for st in d.strips])
        ov.set_singularities([(tuple(d.lift.lift([p], MARKER_LIFT * lift)[0]), i) for p, i in d.singularities])

    def _draw_stored(self, obj):
        ov = self.overlay
        ov.set_stripes(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), [], 1.0, 0.0, 0.0)
        loops = []
        shape = obj.Shape
        if not shape.isNull():
            for wire in shape.Wires:
                pts = [tuple(v.Point) for v in wire.OrderedVertexes]
                if wire.isClosed() and pts:
                    pts.append(pts[0])
                loops.append(pts)
        ov.set_loops(loops)
        summary = obj.Proxy.summary(obj)
        ov.set_singularities([(tuple(x["position"]), float(x["index"]))
                              for x in summary.get("singularities", [])])

    def _request_derivation(self, obj):
        """Derive in the background once per design state (GUI only)."""
        if not App.GuiUp or obj.Surface is None or "Restore" in obj.State:
            return
        from . import derive_async
        state = (obj.DesignJson, bool(obj.Features), obj.Surface.Name)
        if self._requested == state or derive_async.pending(obj):
            return
        self._requested = state
        derive_async.request(obj, callback=lambda o, err: self.redraw())


def stripe_period(derived):
    """Automatic stripe period, cached per mesh."""
    from . import stripe_pattern
    cached = getattr(derived, "_auto_period", None)
    if cached is None:
        cached = stripe_pattern.auto_period(derived.vertices, derived.triangles)
        derived._auto_period = cached
    return cached
