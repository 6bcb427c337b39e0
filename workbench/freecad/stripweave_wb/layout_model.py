"""The "StripWeave Layout" document object: a Design's regions and primal
quad layout (paper §4.2, §7), as ``stripweave.layout.compute_layout`` gives
them (layout.json, design.md).

App side (works under ``freecadcmd``)::

    from freecad.stripweave_wb import layout_model
    layout = layout_model.create(design)     # one transaction "Show layout"; recomputed
    layout.Valid, layout.Clean, layout.PatchCount, layout.Defects
    layout.Shape                             # compound: the layout's edges (wires) and vertices
    json.loads(layout.LayoutJson)            # layout.json

Inputs: ``Design`` (link) and the design's ``pins`` and ``edge_routes``
(design.json: primal vertices the user placed and edges the user routed,
paper §7; layout_pins.py edits them).  Outputs: ``Shape``, ``LayoutJson`` (layout.json,
what a reopened document shows), ``Valid``, ``Clean``, ``PatchCount``,
``Regions`` (counts by colour), ``Defects`` (one line per defect, with where)
and ``Status``.  The region colours (red: not a disc; orange and yellow:
§4.2) are drawn by the view provider (layout_view.py) over the refined
mesh kept in memory; they come back after a reopen with the next recompute.
"""

import json

import FreeCAD as App

from . import icon_path, messages
from .derived_object import PROP_OUTPUT, DerivedObject
from .proxy_state import property_adder

TYPE_NAME = "StripWeave::Layout"


def is_layout(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", None) == TYPE_NAME


def layouts_of(design):
    return [o for o in design.InList if is_layout(o) and o.Design == design]


def compute(ds, params=None, task=None):
    """On the worker: layout.json of the DesignSession with the pins and
    edge routes of ``params`` and, for drawing, the solver mesh with per triangle its
    region, its region's colour and its patch (of the refined triangles the
    arrangement cut it into, the last: as preview.png)."""
    import numpy as np
    from stripweave.layout import layout_json
    if task is not None:
        task.report(0.1, "regions and primal layout")
    # Pins are not part of the derived state's key (they shape the layout only):
    # the session may hold older ones, so the layout sets those it is computed for.
    ds.design.pins = [list(map(float, p)) for p in (params or {}).get("pins", [])]
    ds.design.edge_routes = [{k: list(map(float, r[k])) for k in ("through", "across")}
                             for r in (params or {}).get("edge_routes", [])]
    ds.apply_hand_placed()
    raw = ds.native.layout(True)
    data = layout_json(raw)
    colours = np.array([r["colour"] for r in raw["regions"]] + ["none"])
    region = np.asarray(raw["triangle_region"], dtype=np.int64)
    parent = np.asarray(raw["parent_triangle"], dtype=np.int64)
    count = len(ds.surface.triangles)
    colour = np.full(count, "none", dtype=colours.dtype)
    colour[parent] = colours[np.where(region < 0, len(colours) - 1, region)]
    patch = np.full(count, -1, dtype=np.int64)
    patch[parent] = np.asarray(raw["patch_of_triangle"], dtype=np.int64)
    region_of = np.full(count, -1, dtype=np.int64)
    region_of[parent] = region
    mesh = {"vertices": np.asarray(ds.surface.vertices, dtype=float).reshape(-1, 3),
            "triangles": np.asarray(ds.surface.triangles, dtype=np.int64).reshape(-1, 3),
            "colour": colour.tolist(), "patch": patch, "region": region_of}
    return {"layout": data, "mesh": mesh}


def region_counts(layout):
    counts = {}
    for r in layout["regions"]:
        counts[r["colour"]] = counts.get(r["colour"], 0) + 1
    return counts


def defect_lines(layout):
    return [loc["text"] for loc in layout.get("defect_locations", [])] + list(layout.get("problems", []))


def layout_shape(layout):
    """Compound of the layout's edges (polyline wires) and vertices (points)."""
    import Part
    from .design_model import _dedupe
    shapes = []
    for e in layout["edges"]:
        pts = _dedupe([tuple(map(float, p)) for p in e["points"]])
        if len(pts) >= 2:
            try:
                shapes.append(Part.makePolygon([App.Vector(*p) for p in pts]))
            except Exception as exc:
                messages.log("layout edge not converted to a wire: {}".format(exc))
    shapes += [Part.Vertex(App.Vector(*map(float, v["position"]))) for v in layout["vertices"]]
    return Part.Compound(shapes) if shapes else Part.Shape()


def status_text(layout):
    counts = region_counts(layout)
    regions = ", ".join("{} {}".format(n, c) for c, n in sorted(counts.items()))
    if not layout["valid"]:
        return "invalid: red regions are not discs (add strips that split them); regions: " + regions
    s = layout["summary"]
    irregular = ", ".join("{} of valence {}".format(n, v) for v, n in sorted(s["irregular_vertices"].items()))
    text = "{} patches, {}; irregular vertices: {}; corners {:.1f} deg off on average; regions: {}".format(
        s["patches"], "clean" if layout["clean"] else "NOT clean ({} defects)".format(
            sum(layout["defects"].values())), irregular or "none", s["corner_deviation_deg"]["mean"], regions)
    refused = route_problems(layout)
    return text + ("; " + "; ".join(refused) if refused else "")


def route_problems(layout):
    """The layout's problems with the design's hand routes (an edge route it could not take)."""
    return [p for p in layout.get("problems", []) if p.startswith("edge route ")]


class LayoutModel(DerivedObject):
    """Proxy of the ``Part::FeaturePython`` Layout object."""

    TYPE_NAME = TYPE_NAME
    TITLE = "Layout"
    Type = TYPE_NAME

    def add_properties(self, obj):
        add = property_adder(obj)
        add("App::PropertyLink", "Design", "StripWeave", "The Design whose layout this is")
        add("App::PropertyString", "Status", "Report", "Result of the last recompute", PROP_OUTPUT, True)
        add("App::PropertyBool", "Valid", "Report", "No red region: the layout has patches", PROP_OUTPUT, True)
        add("App::PropertyBool", "Clean", "Report", "Valid and without defects", PROP_OUTPUT, True)
        add("App::PropertyInteger", "PatchCount", "Report", "Patches of the layout", PROP_OUTPUT, True)
        add("App::PropertyString", "Regions", "Report", "Regions by colour (§4.2)", PROP_OUTPUT, True)
        add("App::PropertyStringList", "Defects", "Report", "The layout's defects, with where", PROP_OUTPUT, True)
        add("App::PropertyString", "LayoutJson", "Report", "layout.json of the design (design.md)",
            PROP_OUTPUT, True, True)

    def design_of(self, obj):
        from .design_model import is_design
        d = obj.Design
        return d if d is not None and is_design(d) else None

    def parameters(self, obj):
        """The design's pins and edge routes: moving a vertex or an edge changes the layout,
        not the derived design."""
        design = self.design_of(obj)
        try:
            d = design.Proxy.design(design) if design is not None else None
            return {"pins": d.pins if d else [], "edge_routes": d.edge_routes if d else []}
        except Exception:   # a DesignJson that does not parse: the design's recompute says why
            return {"pins": [], "edge_routes": []}

    def compute(self, ds, params, task):
        return compute(ds, params, task)

    def publish(self, obj, result):
        layout = result["layout"]
        obj.Shape = layout_shape(layout)
        obj.Valid = bool(layout["valid"])
        obj.Clean = bool(layout["clean"])
        obj.PatchCount = len(layout["patches"])
        obj.Regions = ", ".join("{} {}".format(n, c) for c, n in sorted(region_counts(layout).items()))
        obj.Defects = defect_lines(layout)
        obj.Status = status_text(layout)
        for problem in route_problems(layout):   # the user asked for it: say why it was not done
            messages.warning("Layout '{}': {}".format(obj.Label, problem))
        obj.LayoutJson = json.dumps(layout)   # last: the view provider redraws on it

    def clear(self, obj, status):
        import Part
        obj.Shape = Part.Shape()
        obj.Valid = obj.Clean = False
        obj.PatchCount = 0
        obj.Status = status

    def layout(self, obj):
        """layout.json as stored ({} if none)."""
        try:
            return json.loads(obj.LayoutJson) if obj.LayoutJson else {}
        except ValueError:
            return {}

    def mesh(self, obj):
        """The refined mesh with region colours and patches if current, else None."""
        result = self.kept(obj)
        return result["mesh"] if result is not None else None


def hide_inputs(design):
    """Hide what the layout is drawn over (the design's stripes, the surface
    model's curves and the part): they lie on the same surface and would
    show through it (GUI)."""
    sm = design.Surface
    for o in (design, sm, getattr(sm, "Source", None)):
        if o is not None and o.ViewObject is not None:
            o.ViewObject.Visibility = False


def create(design, doc=None, name="Layout"):
    """The Layout of ``design`` (an existing one is reused), made in one
    transaction "Show layout" and recomputed.  Headless: computed at once
    (the design is derived first); GUI: in the background."""
    from .design_model import is_design, transaction
    if not is_design(design):
        raise ValueError("StripWeave: '{}' is not a Design".format(getattr(design, "Label", design)))
    existing = layouts_of(design)
    if existing:
        obj = existing[0]
        obj.touch()
        obj.Document.recompute()
        return obj
    doc = doc or design.Document
    with transaction(doc, "Show layout"):
        obj = doc.addObject("Part::FeaturePython", name)
        LayoutModel(obj)
        obj.Design = design
        obj.Label = "Layout ({})".format(design.Label)
        if App.GuiUp and obj.ViewObject is not None:
            from .layout_view import ViewProviderLayout
            ViewProviderLayout(obj.ViewObject)
            hide_inputs(design)
        doc.recompute()
    return obj


def icon():
    return icon_path("Layout.svg")
