"""The "StripWeave Patches" document objects: a Layout's quad patches fitted
as B-spline (NURBS) faces (``stripweave.surfacing.refit_design``), sewn into
a shell (a solid when it closes), and the compound of their boundary wires.

App side (works under ``freecadcmd``)::

    from freecad.stripweave_wb import patches_model
    patches = patches_model.create(layout, tolerance=None)   # one transaction "Fit patches"
    patches.Shape            # the shell or solid of B-spline faces
    patches.Wires.Shape      # a PatchWires object: compound of each face's outer wire
    json.loads(patches.FitJson)   # report.json's "fit" block (two-sided deviation, coverage, ...)
    patches_model.export_step(patches, "out/patches.step")  # {"faces", "valid", "solids", ...}

Patches: inputs ``Layout`` (link) and ``Tolerance`` (model units; 0: 1e-3 of
the bounding-box diagonal); outputs ``Shape``, ``FitJson``, ``MaxDeviation``,
``Coverage``, ``ToleranceMet``, ``Closed`` and ``Status``.  Each face's
colour (view provider) is its patch's deviation over the tolerance: green
at 0, yellow at the tolerance, red at twice it (deviation.png's scale).
The Shape is saved in the FCStd, so a reopened document shows the patches
without fitting again.
"""

import json

import FreeCAD as App

from . import icon_path, messages
from .derived_object import PROP_OUTPUT, DerivedObject
from .proxy_state import StatelessViewProvider, TypeOnlyState, property_adder

TYPE_NAME = "StripWeave::Patches"
WIRES_TYPE_NAME = "StripWeave::PatchWires"


def is_patches(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", None) == TYPE_NAME


def is_patch_wires(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", None) == WIRES_TYPE_NAME


def patches_of(layout):
    return [o for o in layout.InList if is_patches(o) and o.Layout == layout]


def compute(ds, params, task=None):
    """On the worker: the fit (_fit).  The native refit reports its stages to a
    Progress the panel polls, and Cancel stops it at the next stage or patch."""
    progress = None
    if task is not None:
        from . import import_stripweave
        progress = import_stripweave().Progress()
        task.cancel_hooks.append(progress.cancel)
        task.progress_fn = lambda: (progress.fraction(), progress.stage())
        task.report(0.0, "fitting B-spline patches")
    return _fit(ds, params, progress)


def _fit(ds, params, progress=None):
    """The refit (native) with the fitted shape as BRep text and per patch
    its control points' centre (to match the sewn shell's faces to the
    patches): plain data, picklable."""
    import numpy as np
    from stripweave.surfacing import fit_report, refit_design
    tolerance = params.get("tolerance") or None
    raw = refit_design(ds, tolerance=tolerance, return_brep=True, return_patches=True, progress=progress)
    if not raw.get("brep"):
        from . import import_stripweave
        raise import_stripweave().InputError("the fit gave no shell (no patch could be sewn)")
    centres = [np.asarray(p["control"], dtype=float).mean(axis=0).tolist() for p in raw["patches"]]
    return {"fit": fit_report(raw), "brep": raw["brep"], "centres": centres}


def face_colours(shape, fit, centres):
    """Per face of ``shape`` (r, g, b): its patch's deviation colour (the
    patch whose control points' centre is nearest the face's poles')."""
    import numpy as np
    from stripweave.preview import deviation_colour
    tol = float(fit["tolerance"])
    ratio = [max(p["max_deviation"], p.get("side_deviation", 0.0)) / tol for p in fit["per_patch"]]
    c = np.asarray(centres, dtype=float).reshape(-1, 3)
    out = []
    for face in shape.Faces:
        try:
            poles = np.asarray([[v.x, v.y, v.z] for row in face.Surface.getPoles() for v in row])
            centre = poles.mean(axis=0)
        except Exception:
            centre = np.asarray(face.CenterOfMass)
        k = int(np.argmin(np.linalg.norm(c - centre, axis=1))) if len(c) else -1
        out.append(tuple(deviation_colour(ratio[k])) if 0 <= k < len(ratio) else (0.6, 0.35, 0.75))
    return out


def fit_status(fit):
    from stripweave.surfacing import format_fit
    return format_fit(fit)


class PatchesModel(DerivedObject):
    """Proxy of the ``Part::FeaturePython`` Patches object."""

    TYPE_NAME = TYPE_NAME
    TITLE = "Fit patches"
    Type = TYPE_NAME

    def add_properties(self, obj):
        add = property_adder(obj)
        add("App::PropertyLink", "Layout", "StripWeave", "The Layout whose quad patches are fitted")
        add("App::PropertyLength", "Tolerance", "StripWeave",
            "Fit tolerance in model units (0: 1/1000 of the bounding-box diagonal)")
        add("App::PropertyString", "Status", "Report", "Result of the last recompute", PROP_OUTPUT, True)
        add("App::PropertyLength", "MaxDeviation", "Report",
            "Largest deviation, two-sided (source to patches and patches to source)", PROP_OUTPUT, True)
        add("App::PropertyFloat", "Coverage", "Report",
            "Fraction of the source area within tolerance of a patch", PROP_OUTPUT, True)
        add("App::PropertyBool", "ToleranceMet", "Report",
            "Both directions within tolerance and coverage at least 99.9%", PROP_OUTPUT, True)
        add("App::PropertyBool", "Closed", "Report", "The patches close into a solid", PROP_OUTPUT, True)
        add("App::PropertyString", "FitJson", "Report", "The fit report (report.json's \"fit\")",
            PROP_OUTPUT, True, True)
        add("App::PropertyString", "FaceColours", "Report", "Per face its deviation colour (JSON)",
            PROP_OUTPUT, True, True)

    def design_of(self, obj):
        from .layout_model import is_layout
        layout = obj.Layout
        if layout is None or not is_layout(layout):
            return None
        return layout.Proxy.design_of(layout)

    def parameters(self, obj):
        return {"tolerance": float(obj.Tolerance)}

    def compute(self, ds, params, task):
        return compute(ds, params, task)

    def publish(self, obj, result):
        import Part
        shape = Part.Shape()
        shape.importBrepFromString(result["brep"])
        if shape.ShapeType == "Compound" and len(shape.Solids) == 1:
            shape = shape.Solids[0]
        elif shape.ShapeType == "Compound" and len(shape.Shells) == 1 and not shape.Solids:
            shape = shape.Shells[0]
        fit = result["fit"]
        obj.Shape = shape
        obj.MaxDeviation = float(fit["max_deviation"])
        obj.Coverage = float(fit["coverage"])
        obj.ToleranceMet = bool(fit["tolerance_met"])
        obj.Closed = bool(fit["closed"])
        obj.Status = fit_status(fit)
        obj.FitJson = json.dumps(fit)
        obj.FaceColours = json.dumps(face_colours(shape, fit, result["centres"]))  # the view provider colours on it

    def clear(self, obj, status):
        import Part
        obj.Shape = Part.Shape()
        obj.Status = status

    def fit(self, obj):
        try:
            return json.loads(obj.FitJson) if obj.FitJson else {}
        except ValueError:
            return {}


class PatchWires(TypeOnlyState):
    """Proxy of the PatchWires object: the outer wire of every face of its
    Patches object, as one compound (recomputed with it)."""

    TYPE_NAME = WIRES_TYPE_NAME
    Type = WIRES_TYPE_NAME

    def __init__(self, obj):
        self.Type = WIRES_TYPE_NAME
        obj.addProperty("App::PropertyLink", "Patches", "StripWeave", "The fitted patches")
        obj.Proxy = self

    def execute(self, obj):
        import Part
        src = obj.Patches
        shape = src.Shape if src is not None else Part.Shape()
        wires = [f.OuterWire.copy() for f in shape.Faces] if not shape.isNull() else []
        obj.Shape = Part.Compound(wires) if wires else Part.Shape()


class ViewProviderPatches(StatelessViewProvider):
    """Part's view provider with each face in its deviation colour."""

    ICON = "FitPatches.svg"

    def updateData(self, obj, prop):
        if prop in ("FaceColours", "Shape"):
            self.colour()

    def colour(self):
        obj = getattr(self, "Object", None)
        try:
            colours = json.loads(obj.FaceColours) if obj is not None and obj.FaceColours else []
            if colours and len(colours) == len(obj.Shape.Faces):
                obj.ViewObject.DiffuseColor = [tuple(c) + (0.0,) for c in colours]
        except Exception as exc:
            messages.log("patch colours not set: {}".format(exc))

    def claimChildren(self):
        obj = getattr(self, "Object", None)
        return [o for o in (obj.InList if obj is not None else []) if is_patch_wires(o)]


class ViewProviderPatchWires(StatelessViewProvider):
    ICON = "FitPatches.svg"


def create(layout, tolerance=None, doc=None, name="Patches"):
    """Fit the Layout's patches: a Patches object (the shell or solid) and
    its PatchWires, in one transaction "Fit patches", recomputed (headless:
    fitted at once; GUI: in the background).  An existing Patches object of
    the layout is reused (its tolerance set)."""
    from .design_model import transaction
    from .layout_model import is_layout
    if not is_layout(layout):
        raise ValueError("StripWeave: '{}' is not a Layout".format(getattr(layout, "Label", layout)))
    doc = doc or layout.Document
    existing = patches_of(layout)
    with transaction(doc, "Fit patches"):
        if existing:
            obj = existing[0]
            if tolerance is not None:
                obj.Tolerance = float(tolerance)
            obj.touch()
        else:
            obj = doc.addObject("Part::FeaturePython", name)
            PatchesModel(obj)
            obj.Layout = layout
            obj.Tolerance = float(tolerance or 0.0)
            obj.Label = "Patches ({})".format(layout.Design.Label if layout.Design else layout.Label)
            wires = doc.addObject("Part::FeaturePython", "PatchWires")
            PatchWires(wires)
            wires.Patches = obj
            wires.Label = "Patch wires"
            if App.GuiUp and obj.ViewObject is not None:
                ViewProviderPatches(obj.ViewObject)
                ViewProviderPatchWires(wires.ViewObject)
                wires.ViewObject.LineColor = (0.1, 0.1, 0.1)
                wires.ViewObject.LineWidth = 2.0
                from .layout_model import hide_inputs
                layout.ViewObject.Visibility = False
                if layout.Design is not None:
                    hide_inputs(layout.Design)
        doc.recompute()
    return obj


def wires_of(patches):
    found = [o for o in patches.InList if is_patch_wires(o)]
    return found[0] if found else None


def export_step(patches, path):
    """Write the Patches object's shell or solid as STEP (AP214; ".step" is
    added to a path without it) and read it back; returns {"path", "faces",
    "faces_read_back", "valid", "solids", "shells"}.  Raises InputError when
    there is nothing to export."""
    from . import import_stripweave
    sw = import_stripweave()
    if not is_patches(patches):
        raise sw.InputError("'{}' is not a StripWeave Patches object (run Fit patches)".format(
            getattr(patches, "Label", patches)))
    shape = patches.Shape
    if shape.isNull() or not shape.Faces:
        raise sw.InputError("'{}' has no fitted faces to export ({})".format(patches.Label, patches.Status))
    return export_shape(shape, path)


def export_shape(shape, path):
    """export_step's work on a shape (no document access: any thread)."""
    import Part
    from stripweave.files import atomic_path
    if not path.lower().endswith((".step", ".stp")):
        path += ".step"   # FreeCAD reads a file back by its extension
    with atomic_path(path) as tmp:   # a full disk leaves no half-written STEP
        shape.exportStep(tmp)
    back = Part.Shape()
    back.read(path)
    return {"path": path, "faces": len(shape.Faces), "faces_read_back": len(back.Faces),
            "valid": bool(back.isValid()), "solids": len(back.Solids), "shells": len(back.Shells)}


def icon():
    return icon_path("FitPatches.svg")
