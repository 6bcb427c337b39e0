"""The "StripWeave Design" document object: an ordered list of dual strips
on a SurfaceModel (paper §4.1), and what it implies (§6).

App side (works under ``freecadcmd`` too)::

    from freecad.stripweave_wb import design_model
    obj = design_model.create(surface_model)
    design_model.add_strip(obj, [(13, 0, 0, 0, 0, 1)])   # one undoable transaction
    design_model.edit_strip(obj, 0, [(13, 0, 0)])        # its anchors replaced, re-derived
    design_model.set_symmetry(obj, design_model.detect_symmetry(obj))  # strips added later get their images
    obj.Shape                       # compound of the strips' loops (closed wires)
    obj.Proxy.derived(obj)          # snapshot: strips, stripe coordinates, singularities

Persisted: ``DesignJson``, the whole design file (``stripweave.design``; the
truth: anchors and options, unknown keys kept), ``Boundary`` (mirrors
``options.boundary`` in the JSON), ``Features`` (feature curves constrain
the cross field), and as outputs the Shape, ``Summary`` (JSON: per strip
length, widths, area fraction; singularities; fold-overs) and ``Status``.
The DesignSession is a cache on the proxy (:mod:`design_session`), rebuilt
on demand after a document is reopened.

Recompute never changes ``DesignJson``: when a strip fails (InputError) the
design is kept, the error goes to the report view and ``Status``, the
object is marked invalid, and the strips before the failing one are shown.
"""

import contextlib
import json

import FreeCAD as App

from . import icon_path, import_stripweave, messages
from .design_session import SessionCache, design_key
from .surface_model import is_surface_model

TYPE_NAME = "StripWeave::Design"
BOUNDARY_MODES = ["aligned", "trimmed"]

# addProperty attribute bits (App::PropertyType)
_PROP_READONLY = 1
_PROP_OUTPUT = 8


def is_design(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", None) == TYPE_NAME


def designs_of(surface_model):
    """The Design objects built on ``surface_model``."""
    return [o for o in surface_model.InList if is_design(o) and o.Surface == surface_model]


def new_design_dict(surface_model=None):
    """An empty design file, with the model it is made on when known, and
    the boundary mode of the preferences."""
    import_stripweave()
    from stripweave.design import Design
    from . import preferences
    d = Design(options={"boundary": preferences.boundary_mode()})
    if surface_model is not None:
        d.model = _model_info(surface_model)
        d.options["feature_angle_deg"] = float(surface_model.FeatureAngle)
    return d.to_dict()


def _model_info(surface_model):
    info = {"label": surface_model.Source.Label if surface_model.Source else surface_model.Label}
    try:
        diag = json.loads(surface_model.Report).get("bbox_diagonal")
        if diag:
            info["bbox_diagonal"] = float(diag)
    except (ValueError, AttributeError):
        pass
    return info


class DesignModel:
    """Proxy of the ``Part::FeaturePython`` Design object."""

    Type = TYPE_NAME
    # class-level default: __init__ is not called when a document is restored
    _cache = None

    def __init__(self, obj):
        self.Type = TYPE_NAME
        self._add_properties(obj)
        obj.Proxy = self

    @staticmethod
    def _add_properties(obj):
        have = set(obj.PropertiesList)

        def add(ptype, name, group, tip, attr=0, read_only=False, hidden=False):
            if name not in have:
                obj.addProperty(ptype, name, group, tip, attr, read_only, hidden)
                return True
            return False

        add("App::PropertyLink", "Surface", "StripWeave", "The SurfaceModel the strips are woven on")
        add("App::PropertyString", "DesignJson", "StripWeave",
            "The design file (JSON): the strips' anchors and the options. The truth of this object")
        if add("App::PropertyEnumeration", "Boundary", "StripWeave",
               "Dual curves at open boundaries: 'aligned' (run along them) or 'trimmed' (end on them)"):
            obj.Boundary = BOUNDARY_MODES
        if add("App::PropertyBool", "Features", "StripWeave",
               "Feature curves constrain the cross field (strips align with sharp edges)"):
            obj.Features = True
        add("App::PropertyString", "Status", "Report", "Result of the last recompute", _PROP_OUTPUT, True)
        add("App::PropertyInteger", "StripCount", "Report", "Number of strips derived", _PROP_OUTPUT, True)
        add("App::PropertyString", "Summary", "Report",
            "Derived state as JSON: strips (length, widths, area fraction), singularities, fold-overs",
            _PROP_OUTPUT, True, True)
        # Edited through the tools (each edit an undoable transaction), not by hand.
        obj.setEditorMode("DesignJson", 1)

    # -- persistence: the type only; the session is a cache ------------------------
    def __getstate__(self):
        return {"Type": TYPE_NAME, "version": 1}

    def __setstate__(self, state):
        self.Type = TYPE_NAME
        self._cache = None
        return None

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        return self.__setstate__(state)

    def onDocumentRestored(self, obj):
        self._add_properties(obj)

    # -- the design ---------------------------------------------------------------
    def design(self, obj):
        """The Design in ``DesignJson`` (raises InputError if it does not parse)."""
        sw = import_stripweave()
        from stripweave.design import Design
        try:
            data = json.loads(obj.DesignJson) if obj.DesignJson else new_design_dict()
        except ValueError as exc:
            raise sw.InputError("design of '{}' is not valid JSON: {}".format(obj.Label, exc)) from None
        return Design.from_dict(data)

    def onChanged(self, obj, prop):
        if "Restore" in obj.State or getattr(self, "_syncing", False):
            return
        # Boundary mirrors options.boundary of the JSON, both ways.
        self._syncing = True
        try:
            if prop == "Boundary" and obj.DesignJson:
                data = _loads(obj.DesignJson)
                if data is not None and data.setdefault("options", {}).get("boundary") != obj.Boundary:
                    data["options"]["boundary"] = obj.Boundary
                    obj.DesignJson = json.dumps(data, indent=1)
            elif prop == "DesignJson":
                data = _loads(obj.DesignJson) or {}
                boundary = (data.get("options") or {}).get("boundary", "aligned")
                if boundary in BOUNDARY_MODES and boundary != obj.Boundary:
                    obj.Boundary = boundary
        finally:
            self._syncing = False

    # -- derived state --------------------------------------------------------------
    def cache(self):
        if self._cache is None:
            self._cache = SessionCache()
        return self._cache

    def surface_if_ready(self, obj):
        """The SurfaceModel's native surface if it is built and current, else None."""
        sm = obj.Surface
        if sm is None or not is_surface_model(sm):
            return None
        return sm.Proxy._surface if sm.Proxy.is_up_to_date(sm) else None

    def derived(self, obj):
        """The snapshot of the current design, or None when the session does
        not reflect it (not derived yet, or the design/surface changed)."""
        cache = self._cache
        d = cache.derived if cache is not None else None
        if d is None or cache.surface is None or cache.surface is not self.surface_if_ready(obj):
            return None
        try:
            return d if d.key == design_key(self.design(obj), obj.Features) else None
        except Exception:
            return None

    def sync(self, obj):
        """Derive the design now (blocking; builds the surface if needed) and
        return the snapshot.  Raises for a missing surface model."""
        sm = obj.Surface
        if sm is None or not is_surface_model(sm):
            raise ValueError("StripWeave: design '{}' has no SurfaceModel".format(obj.Label))
        surface = sm.Proxy.surface(sm)
        return self.cache().sync(surface, self.design(obj), obj.Features)

    def session(self, obj):
        """The DesignSession, derived now if needed (blocking)."""
        self.sync(obj)
        return self.cache().session_for_caller()

    def execute(self, obj):
        import Part
        sm = obj.Surface
        if sm is None or not is_surface_model(sm):
            # Its SurfaceModel was deleted (or never linked): say so once, in
            # one line; raising would print a traceback for a user's action.
            obj.Shape = Part.Shape()
            obj.StripCount = 0
            status = ("error: no SurfaceModel linked: the design keeps its strips; link a SurfaceModel in its "
                      "Surface property (or undo the deletion)")
            if obj.Status != status:
                obj.Status = status
                messages.error("design '{}' has no surface model: {}".format(obj.Label, status[7:]),
                               dialog=False)
            return
        if App.GuiUp and self.surface_if_ready(obj) is None:
            # The surface is (re)built on a worker thread; derive and publish
            # when it is there instead of freezing the GUI in a recompute.
            from . import derive_async
            obj.Status = "waiting for the surface model"
            derive_async.request(obj, then_recompute=True)
            return
        try:
            derived = self.sync(obj)
        except Exception as exc:
            obj.Status = "error: {}".format(exc)
            messages.error("design '{}': {}".format(obj.Label, exc), dialog=False)
            raise
        self.publish(obj, derived)
        if derived.error:
            messages.error("design '{}': {} (the design is kept; {} of {} strips shown)".format(
                obj.Label, derived.error, len(derived.strips), derived.requested), dialog=False)
            raise ValueError("StripWeave: " + derived.error)

    def publish(self, obj, derived):
        """Write the output properties from a snapshot (Summary last: the
        view provider redraws on it)."""
        old = self.summary(obj)
        summary = with_warnings(derived, old.get("fold_overs") if old else None)
        for line in summary["warnings"]:
            if line not in old.get("warnings", []):   # said once, in the report view
                messages.warning("design '{}': {}".format(obj.Label, line))
        obj.Shape = loops_shape(derived.strips)
        obj.StripCount = len(derived.strips)
        obj.Status = status_text(derived)
        obj.Summary = json.dumps(summary)

    def refresh_outputs(self, obj):
        """Publish the current snapshot if the stored outputs differ from it
        (after a background derivation: a reopened document shows what was
        saved until the design is derived again).  True if it published."""
        derived = self.derived(obj)
        if derived is None:
            return False
        if obj.Status == status_text(derived) and obj.StripCount == len(derived.strips):
            return False
        self.publish(obj, derived)
        return True

    def summary(self, obj):
        """The stored Summary as a dict ({} if none)."""
        return _loads(obj.Summary) or {}


def _loads(text):
    try:
        return json.loads(text) if text else None
    except ValueError:
        return None


def with_warnings(derived, previous_fold_overs):
    """The snapshot's summary with "warnings" (feedback.py: empty and sliver
    strips, fold-overs the last change added)."""
    from .feedback import mesh_scale, strip_warnings
    scale = getattr(derived, "_scale", None)
    if scale is None:
        scale = derived._scale = mesh_scale(derived.vertices, derived.triangles)
    summary = derived.summary()
    summary["warnings"] = strip_warnings(summary, scale[0], scale[1], previous_fold_overs)
    return summary


def status_text(derived):
    counts = derived.singularity_counts()
    text = "{} strip{}, singularities +1/4: {}, -1/4: {}, other: {}; fold-overs: {}".format(
        len(derived.strips), "" if len(derived.strips) == 1 else "s",
        counts["+1/4"], counts["-1/4"], counts["other"], derived.fold_overs)
    if derived.error:
        text = "error: {} ({} of {} strips derived); {}".format(
            derived.error, len(derived.strips), derived.requested, text)
    return text


def loops_shape(strips):
    """Compound of the loops as polyline wires (closed loops as closed wires)."""
    import Part
    wires = []
    for s in strips:
        pts = _dedupe([tuple(map(float, p)) for p in s["points"]])
        if len(pts) < 2:
            continue
        if s["closed"] and len(pts) > 2 and _dist(pts[0], pts[-1]) > 1e-9:
            pts.append(pts[0])
        try:
            wires.append(Part.makePolygon([App.Vector(*p) for p in pts]))
        except Exception as exc:  # a degenerate loop must not lose the others
            messages.log("loop not converted to a wire: {}".format(exc))
    return Part.Compound(wires) if wires else Part.Shape()


def _dist(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) ** 0.5


def _dedupe(pts, tol=1e-9):
    """Drop consecutive repeated points (makePolygon refuses zero-length edges)."""
    out = []
    for p in pts:
        if not out or _dist(out[-1], p) > tol:
            out.append(p)
    if len(out) > 2 and _dist(out[0], out[-1]) <= tol:
        out[-1] = out[0]
    return out


# -- creation and edits (each edit one document transaction) --------------------------

@contextlib.contextmanager
def transaction(doc, name):
    """``with transaction(doc, "Add strip"):`` one undo step; aborted on error."""
    doc.openTransaction(name)
    try:
        yield
    except BaseException:
        doc.abortTransaction()
        raise
    doc.commitTransaction()


def create(surface_model, design=None, doc=None, name="Design"):
    """Add a Design on ``surface_model`` (``design``: a dict, Design or None
    for an empty one) and return it.  Opens no transaction, does not recompute."""
    if not is_surface_model(surface_model):
        raise ValueError("StripWeave: '{}' is not a SurfaceModel".format(surface_model.Label))
    doc = doc or surface_model.Document
    obj = doc.addObject("Part::FeaturePython", name)
    DesignModel(obj)
    obj.Surface = surface_model
    obj.Label = "Design ({})".format(surface_model.Source.Label if surface_model.Source else surface_model.Label)
    data = _as_dict(design) if design is not None else new_design_dict(surface_model)
    obj.DesignJson = json.dumps(data, indent=1)
    if App.GuiUp and obj.ViewObject is not None:
        from .design_view import ViewProviderDesign
        ViewProviderDesign(obj.ViewObject)
    return obj


def _as_dict(design):
    if isinstance(design, dict):
        import_stripweave()
        from stripweave.design import Design
        return Design.from_dict(design).to_dict()  # validates, keeps unknown keys
    return design.to_dict()


def write_design(obj, data, name):
    """Replace the design in one transaction and recompute."""
    doc = obj.Document
    with transaction(doc, name):
        obj.DesignJson = json.dumps(data, indent=1)
        doc.recompute()


def add_strip(obj, anchors):
    """Add a strip through ``anchors`` ((x,y,z) or (x,y,z,dx,dy,dz), model
    units).  The loop is searched first: if no compatible loop exists the
    InputError propagates and the document is unchanged; otherwise one
    transaction "Add strip".  Returns the new strip's index."""
    proxy = obj.Proxy
    proxy.sync(obj)
    data, _derived = proxy.cache().add_strip(anchors)
    write_design(obj, data, "Add strip")
    return len(data["strips"]) - 1


def edit_strip(obj, index, anchors, name="Edit strip"):
    """Replace strip ``index``'s anchors (what a grab-and-drag's re-route,
    or an anchor deleted or made positional, does).  Derived first: if the
    design does not derive with them the InputError propagates and the
    document is unchanged; otherwise one transaction ``name``."""
    proxy = obj.Proxy
    proxy.sync(obj)
    data, _derived = proxy.cache().edit_strip(index, anchors)
    write_design(obj, data, name)


OPTION_NAMES = {"compatibility_band": "Set compatibility band", "boundary": "Set boundary mode"}


def set_options(obj, **options):
    """Set design options (``compatibility_band``: model units or None, the
    whole strip; ``boundary``: "aligned" or "trimmed") in one transaction,
    validated first (InputError, the document unchanged).  Does not
    recompute: the caller recomputes (the design tool derives in the
    background).  True if anything changed."""
    import_stripweave()
    from stripweave.design import Design
    unknown = set(options) - set(OPTION_NAMES)
    if unknown:
        raise ValueError("StripWeave: set_options takes {}, not {}".format(sorted(OPTION_NAMES), sorted(unknown)))
    data = json.loads(obj.DesignJson) if obj.DesignJson else new_design_dict(obj.Surface)
    current = {**Design.from_dict(data).options}
    changed = {k: v for k, v in options.items() if current.get(k) != v}
    if not changed:
        return False
    data.setdefault("options", {}).update(changed)
    data = Design.from_dict(data).to_dict()   # validates the new values
    name = OPTION_NAMES[next(iter(changed))] if len(changed) == 1 else "Set design options"
    with transaction(obj.Document, name):
        obj.DesignJson = json.dumps(data, indent=1)
    return True


def detect_symmetry(obj):
    """The symmetries of the design's surface (stripweave.symmetry.detect: reflections and
    rotations within design.md's tolerance, each with its RMS and max error in model units).
    Builds the surface if needed (blocking)."""
    import_stripweave()
    from stripweave.symmetry import detect
    from .design_session import SYMMETRY_TOLERANCE
    sm = obj.Surface
    if sm is None or not is_surface_model(sm):
        raise ValueError("StripWeave: design '{}' has no SurfaceModel".format(obj.Label))
    return detect(sm.Proxy.surface(sm), SYMMETRY_TOLERANCE)


def symmetry(obj):
    """The design's accepted symmetries (design.json's "symmetry"), [] when none."""
    return list(obj.Proxy.design(obj).symmetry or [])


def set_symmetry(obj, symmetries):
    """Accept ``symmetries`` (design.md's dicts; [] turns symmetry off: the key is dropped,
    so the design is as one made without it) in one transaction "Set symmetry", validated
    first (InputError, the document unchanged).  Strips added later get their images; the
    strips already there stay.  Does not recompute: the caller recomputes (the design is
    derived again, on a solver mesh made symmetric under the reflections).  True if
    anything changed."""
    import_stripweave()
    from stripweave.design import Design
    data = json.loads(obj.DesignJson) if obj.DesignJson else new_design_dict(obj.Surface)
    new = [dict(x) for x in symmetries] if symmetries else None
    if data.get("symmetry") == new:
        return False
    if new is None:
        data.pop("symmetry", None)
    else:
        data["symmetry"] = new
    data = Design.from_dict(data).to_dict()   # validates the entries
    with transaction(obj.Document, "Set symmetry" if new else "Turn symmetry off"):
        obj.DesignJson = json.dumps(data, indent=1)
    return True


def remove_strip(obj, index):
    """Remove strip ``index`` (transaction "Remove strip")."""
    design = obj.Proxy.design(obj)
    if not 0 <= index < len(design.strips):
        raise IndexError("StripWeave: design '{}' has no strip {}".format(obj.Label, index + 1))
    design.remove_strip(index)
    write_design(obj, design.to_dict(), "Remove strip")


def import_design(obj, path):
    """Replace the design by the file at ``path`` (validated first; the
    document is unchanged if it does not parse)."""
    import_stripweave()
    from stripweave.design import Design
    data = Design.load(path).to_dict()
    write_design(obj, data, "Import design")
    return data


def export_design(obj, path):
    """Write the design file (the model it was made on filled in when missing)."""
    design = obj.Proxy.design(obj)
    if obj.Surface is not None and is_surface_model(obj.Surface):
        for k, v in _model_info(obj.Surface).items():
            design.model.setdefault(k, v)
    design.save(path)
    return path


def icon():
    return icon_path("Design.svg")
