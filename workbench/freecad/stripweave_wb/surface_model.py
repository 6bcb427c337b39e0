"""The SurfaceModel document object: a stripweave Surface prepared from a
Part or Mesh object, and its view provider (the feature-curve overlay).

App side (works under ``freecadcmd`` too)::

    from freecad.stripweave_wb import surface_model
    obj = surface_model.create(source)          # headless: builds at recompute
    obj.Proxy.surface(obj)                      # the native stripweave Surface

Persisted on the object: the parameters, ``Report`` (JSON of
``Surface.report()``) and the feature curves / boundary loops as hidden
output properties, so the overlay comes back when a document is reopened.
The native Surface itself is only cached on the proxy (not saved) and rebuilt
on demand.

Recompute: changing Source, TargetTriangles or FeatureAngle (or the source's
geometry) touches the object; ``execute`` then rebuilds the surface, on a
worker thread with a progress panel when the GUI is up, synchronously
otherwise.
"""

import json

import FreeCAD as App

from . import icon_path
from . import messages
from .worker import (DEFAULT_FEATURE_ANGLE_DEG, DEFAULT_TARGET_TRIANGLES, SourceError,
                     SurfaceJob, snapshot_source)

TYPE_NAME = "StripWeave::SurfaceModel"
PARAMETERS = ("Source", "TargetTriangles", "FeatureAngle")

# addProperty attribute bits (App::PropertyType)
_PROP_OUTPUT = 8


def _json_safe(value):
    """report() values -> plain JSON types (numpy scalars/arrays included)."""
    if isinstance(value, dict):
        return {str(k): _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    if hasattr(value, "tolist"):
        return _json_safe(value.tolist())
    if isinstance(value, (bool, int, float, str)) or value is None:
        return value
    return str(value)


def flatten_polylines(polylines):
    """list of (k,3) arrays -> (list of 3-tuples, counts); polylines with
    fewer than two points are dropped."""
    points, counts = [], []
    for line in polylines:
        pts = line.tolist() if hasattr(line, "tolist") else [list(p) for p in line]
        if len(pts) < 2:
            continue
        points.extend((float(p[0]), float(p[1]), float(p[2])) for p in pts)
        counts.append(len(pts))
    return points, counts


def split_polylines(points, counts):
    """Inverse of :func:`flatten_polylines` (list of lists of 3-tuples)."""
    out, i = [], 0
    for c in counts:
        out.append([tuple(p) for p in points[i:i + c]])
        i += c
    return out


def is_surface_model(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", None) == TYPE_NAME


def parameter_defaults():
    """Defaults from the user parameters (preferences.py: Edit > Preferences > StripWeave)."""
    from . import preferences
    return {"target_triangles": preferences.target_triangles(), "feature_angle_deg": preferences.feature_angle()}


class SurfaceModel:
    """Proxy of the ``Part::FeaturePython`` SurfaceModel object."""

    Type = TYPE_NAME
    # class-level defaults: __init__ is not called when a document is restored
    _surface = None
    _surface_key = None

    def __init__(self, obj, target_triangles=DEFAULT_TARGET_TRIANGLES,
                 feature_angle_deg=DEFAULT_FEATURE_ANGLE_DEG):
        self.Type = TYPE_NAME
        self._add_properties(obj)
        obj.TargetTriangles = (int(target_triangles), 100, 10000000, 1000)
        obj.FeatureAngle = (float(feature_angle_deg), 0.0, 180.0, 1.0)
        obj.Proxy = self

    @staticmethod
    def _add_properties(obj):
        have = set(obj.PropertiesList)

        def add(ptype, name, group, tip, attr=0, read_only=False, hidden=False):
            if name not in have:
                obj.addProperty(ptype, name, group, tip, attr, read_only, hidden)

        add("App::PropertyLink", "Source", "StripWeave",
            "The Part or Mesh object the surface model is prepared from")
        add("App::PropertyIntegerConstraint", "TargetTriangles", "StripWeave",
            "Approximate number of triangles of the solver mesh")
        add("App::PropertyFloatConstraint", "FeatureAngle", "StripWeave",
            "Dihedral angle (degrees) above which an edge is a sharp feature")
        add("App::PropertyString", "Report", "Report",
            "Surface report as JSON (vertices, triangles, genus, feature curves, ...)",
            _PROP_OUTPUT, True, False)
        for name, tip in (("FeaturePoints", "Points of all feature curves (model units)"),
                          ("BoundaryPoints", "Points of all boundary loops (model units)")):
            add("App::PropertyVectorList", name, "Report", tip, _PROP_OUTPUT, True, True)
        for name, tip in (("FeatureCounts", "Number of points of each feature curve"),
                          ("BoundaryCounts", "Number of points of each boundary loop")):
            add("App::PropertyIntegerList", name, "Report", tip, _PROP_OUTPUT, True, True)

    # -- persistence: nothing but the type; the native surface is a cache ----
    def __getstate__(self):
        return {"Type": TYPE_NAME, "version": 1}

    def __setstate__(self, state):
        self.Type = TYPE_NAME
        self._surface = None
        self._surface_key = None
        return None

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        return self.__setstate__(state)

    def onDocumentRestored(self, obj):
        self._add_properties(obj)  # documents from older versions

    # -- parameters / recompute -----------------------------------------------
    def parameters(self, obj):
        return {
            "target_triangles": int(obj.TargetTriangles),
            "feature_angle_deg": float(obj.FeatureAngle),
        }

    def _key(self, obj):
        src = obj.Source
        return (src.Name if src else None, int(obj.TargetTriangles), float(obj.FeatureAngle),
                _source_stamp(src))

    def is_up_to_date(self, obj):
        return self._surface is not None and self._surface_key == self._key(obj)

    def execute(self, obj):
        if obj.Source is None:
            self.clear(obj, error="no source object")
            return
        if self.is_up_to_date(obj):
            return
        if App.GuiUp:
            # never block the GUI: rebuild on a worker thread, after recompute
            from . import builder
            builder.schedule_rebuild(obj)
            return
        try:
            job = SurfaceJob(snapshot_source(obj.Source), label=obj.Label, **self.parameters(obj))
        except SourceError as exc:
            self.clear(obj, error=str(exc))
            raise ValueError("StripWeave: {}".format(exc)) from None
        job.run_here()
        if job.error is not None:
            self.clear(obj, error=job.error_message())
            raise ValueError("StripWeave: " + job.error_message())
        self.set_surface(obj, job.surface)

    # -- results --------------------------------------------------------------
    def surface(self, obj):
        """The native stripweave Surface, built now (blocking) if not cached."""
        if not self.is_up_to_date(obj):
            if obj.Source is None:
                raise ValueError("StripWeave: SurfaceModel '{}' has no source".format(obj.Label))
            job = SurfaceJob(snapshot_source(obj.Source), label=obj.Label, **self.parameters(obj))
            job.run_here()
            if job.error is not None:
                raise job.error
            self.set_surface(obj, job.surface)
        return self._surface

    def set_surface(self, obj, surface):
        """Store a freshly built Surface: cache it, write Report and the
        overlay polylines (output properties: the object is not touched)."""
        report = _json_safe(surface.report())
        fpts, fcounts = flatten_polylines(surface.feature_curve_points())
        bpts, bcounts = flatten_polylines(surface.boundary_loop_points())
        self._surface = surface
        self._surface_key = self._key(obj)
        # points before counts: the view provider redraws on the counts
        obj.FeaturePoints = fpts
        obj.FeatureCounts = fcounts
        obj.BoundaryPoints = bpts
        obj.BoundaryCounts = bcounts
        obj.Report = json.dumps(report, sort_keys=True)
        return report

    def clear(self, obj, error=None):
        self._surface = None
        self._surface_key = None
        obj.FeaturePoints = []
        obj.FeatureCounts = []
        obj.BoundaryPoints = []
        obj.BoundaryCounts = []
        obj.Report = json.dumps({"error": error}) if error else ""

    def report(self, obj):
        """The stored report as a dict ({} if none)."""
        try:
            return json.loads(obj.Report) if obj.Report else {}
        except ValueError:
            return {}


def _source_stamp(src):
    """Cheap fingerprint of the source geometry, to skip needless rebuilds."""
    if src is None:
        return None
    try:
        if hasattr(src, "Mesh") and src.isDerivedFrom("Mesh::Feature"):
            m = src.Mesh
            bb = m.BoundBox
            return ("mesh", m.CountPoints, m.CountFacets,
                    tuple(round(v, 9) for v in (bb.XMin, bb.YMin, bb.ZMin, bb.XMax, bb.YMax, bb.ZMax)))
        shape = src.Shape
        if shape.isNull():
            return ("shape", None)
        bb = shape.BoundBox
        return ("shape", shape.hashCode(), len(shape.Faces),
                tuple(round(v, 9) for v in (bb.XMin, bb.YMin, bb.ZMin, bb.XMax, bb.YMax, bb.ZMax)))
    except Exception:
        return None


class ViewProviderSurfaceModel:
    """Draws the feature curves and boundary loops as a Coin overlay (display
    mode "Overlay"); see ``overlay.py`` for the node names."""

    def __init__(self, vobj):
        self._add_properties(vobj)
        vobj.Proxy = self

    @staticmethod
    def _add_properties(vobj):
        from . import overlay
        have = set(vobj.PropertiesList)
        if "FeatureColor" not in have:
            vobj.addProperty("App::PropertyColor", "FeatureColor", "StripWeave", "Colour of the feature curves")
            vobj.FeatureColor = overlay.FEATURE_COLOR
        if "BoundaryColor" not in have:
            vobj.addProperty("App::PropertyColor", "BoundaryColor", "StripWeave", "Colour of the boundary loops")
            vobj.BoundaryColor = overlay.BOUNDARY_COLOR
        if "CurveWidth" not in have:
            vobj.addProperty("App::PropertyFloatConstraint", "CurveWidth", "StripWeave",
                             "Line width of feature curves and boundary loops (pixels)")
            vobj.CurveWidth = (overlay.LINE_WIDTH, 1.0, 20.0, 1.0)

    def attach(self, vobj):
        from . import overlay
        self.Object = vobj.Object
        self.overlay = overlay.Overlay(
            feature_color=tuple(getattr(vobj, "FeatureColor", overlay.FEATURE_COLOR))[:3],
            boundary_color=tuple(getattr(vobj, "BoundaryColor", overlay.BOUNDARY_COLOR))[:3],
            line_width=getattr(vobj, "CurveWidth", overlay.LINE_WIDTH),
        )
        vobj.addDisplayMode(self.overlay.root, "Overlay")
        self._redraw("Feature")
        self._redraw("Boundary")

    def getDisplayModes(self, vobj):
        return ["Overlay"]

    def getDefaultDisplayMode(self):
        return "Overlay"

    def setDisplayMode(self, mode):
        return mode

    def getIcon(self):
        return icon_path("SurfaceModel.svg")

    def updateData(self, obj, prop):
        if prop in ("FeatureCounts", "FeaturePoints"):
            self._redraw("Feature")
        elif prop in ("BoundaryCounts", "BoundaryPoints"):
            self._redraw("Boundary")

    def onChanged(self, vobj, prop):
        ov = getattr(self, "overlay", None)
        if ov is None:
            return
        if prop == "FeatureColor":
            ov.features.set_color(tuple(vobj.FeatureColor)[:3])
        elif prop == "BoundaryColor":
            ov.boundaries.set_color(tuple(vobj.BoundaryColor)[:3])
        elif prop == "CurveWidth":
            ov.features.set_line_width(vobj.CurveWidth)
            ov.boundaries.set_line_width(vobj.CurveWidth)

    def onDelete(self, vobj, subelements):
        from . import builder, design_model
        builder.cancel_for(vobj.Object)
        users = [d.Label for d in design_model.designs_of(vobj.Object)]
        if users:
            messages.warning("SurfaceModel '{}' deleted: {} no surface model now; undo, or link another "
                             "SurfaceModel in the Surface property".format(
                                 vobj.Object.Label, ", ".join("'{}'".format(u) for u in users)
                                 + (" has" if len(users) == 1 else " have")))
        return True

    def doubleClicked(self, vobj):
        # report on demand: print it again and select the object
        obj = vobj.Object
        rep = obj.Proxy.report(obj) if is_surface_model(obj) else {}
        if rep:
            messages.message("report of '{}':\n{}".format(obj.Label, format_report(rep)))
        return True

    def _redraw(self, which):
        ov = getattr(self, "overlay", None)
        obj = getattr(self, "Object", None)
        if ov is None or obj is None:
            return
        pts = getattr(obj, which + "Points", None)
        counts = getattr(obj, which + "Counts", None)
        if pts is None or counts is None or sum(counts) != len(pts):
            return  # half-updated (points set, counts not yet): wait
        target = ov.features if which == "Feature" else ov.boundaries
        try:
            target.set_polylines([(v.x, v.y, v.z) for v in pts], counts)
        except ValueError as exc:
            messages.log("overlay not drawn: {}".format(exc))

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None


def format_report(report):
    """Human-readable report (``stripweave.format_report`` when available)."""
    try:
        from . import import_stripweave
        return import_stripweave().format_report(report)
    except Exception:
        return "\n".join("  {}: {}".format(k, v) for k, v in sorted(report.items()))


def create(source, target_triangles=None, feature_angle_deg=None, surface=None,
           doc=None, name="SurfaceModel"):
    """Add a SurfaceModel for ``source`` to the document and return it.

    With ``surface`` (an already built stripweave Surface) the object is
    filled in and left untouched, so no recompute rebuilds it; without it,
    the next recompute builds the surface.  Does not open a transaction.
    """
    defaults = parameter_defaults()
    if target_triangles is None:
        target_triangles = defaults["target_triangles"]
    if feature_angle_deg is None:
        feature_angle_deg = defaults["feature_angle_deg"]
    doc = doc or source.Document
    obj = doc.addObject("Part::FeaturePython", name)
    SurfaceModel(obj, target_triangles, feature_angle_deg)
    obj.Source = source
    obj.Label = "SurfaceModel ({})".format(source.Label)
    if App.GuiUp and obj.ViewObject is not None:
        ViewProviderSurfaceModel(obj.ViewObject)
    if surface is not None:
        obj.Proxy.set_surface(obj, surface)
        obj.purgeTouched()
    return obj
