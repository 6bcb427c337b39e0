"""Pinned primal vertices (paper §7, manual): a Layout's vertex dragged
within its region becomes a pin of its Design (design.json's ``pins``,
model units), which the layout moves that region's vertex to.

App side (works under ``freecadcmd``)::

    from freecad.stripweave_wb import layout_pins
    layout_pins.move_vertex(layout, k, (x, y, z))   # transaction "Move layout vertex"
    layout_pins.route_edge(layout, k, (x, y, z))    # transaction "Re-route layout edge"
    layout_pins.remove_pin(layout, i)                # transaction "Remove layout pin"
    layout_pins.remove_route(layout, i)              # transaction "Remove edge route"
    layout_pins.clear_pins(layout)                   # transaction "Clear layout pins" (and routes)
    layout_pins.pins_of(layout.Design)               # [[x, y, z], ...]
    layout_pins.routes_of(layout.Design)             # [{"through": p, "across": q}, ...]

Inputs: a Layout object (layout_model.py) whose layout.json is current,
the index of one of its vertices, a point on the part.  Output: the
Design's DesignJson with the pins changed (so the FCStd and an exported
design.json keep them); the Layout recomputes from it.  Each region holds
one primal vertex, so a region holds at most one pin that matters: moving
vertex k replaces every pin lying in k's region (the one that placed it).

Edges likewise (paper §7: "where within a dual loop corridor a patch
boundary should lie"): edge k re-routed through a point of its corridor
becomes an edge route of the Design (design.json's ``edge_routes``:
{"through": the point, "across": where edge k crosses its loop}, which
names the edge whatever route it takes); a new route of an edge replaces
its old one.
"""

import json

import numpy as np

from . import import_stripweave
from .design_model import transaction

MOVE = "Move layout vertex"
ROUTE = "Re-route layout edge"
REMOVE_PIN = "Remove layout pin"
REMOVE_ROUTE = "Remove edge route"
CLEAR = "Clear layout pins"


def pins_of(design):
    """The Design's pins as [[x, y, z], ...] (model units)."""
    return [list(p) for p in design.Proxy.design(design).pins]


def routes_of(design):
    """The Design's edge routes as [{"through": [x, y, z], "across": [x, y, z]}, ...]."""
    return [dict(r) for r in design.Proxy.design(design).edge_routes]


def _write_pins(design, pins, name, routes=None):
    """Replace the Design's pins (and, if given, its edge routes) in one
    transaction ``name`` and recompute (the design's strips and options are
    kept, the JSON validated)."""
    import_stripweave()
    from stripweave.design import Design
    data = json.loads(design.DesignJson)
    data["pins"] = [[float(c) for c in p] for p in pins]
    if not data["pins"]:
        del data["pins"]
    if routes is not None:
        data["edge_routes"] = [{k: [float(c) for c in r[k]] for k in ("through", "across")} for r in routes]
        if not data["edge_routes"]:
            del data["edge_routes"]
    data = Design.from_dict(data).to_dict()
    doc = design.Document
    with transaction(doc, name):
        design.DesignJson = json.dumps(data, indent=1)
        doc.recompute()


def region_of_point(mesh, point, centroids=None):
    """The region (layout.json index) of the solver triangle nearest
    ``point`` (centroid distance: pins lie on the surface, so the nearest
    centroid is the triangle under them up to a solver edge), or -1 on a
    loop.  ``mesh``: LayoutModel.mesh (with "region"); ``centroids``: its
    triangles' centroids if the caller keeps them (a drag asks per move)."""
    if centroids is None:
        centroids = mesh["vertices"][mesh["triangles"]].mean(axis=1)
    i = int(np.argmin(np.linalg.norm(centroids - np.asarray(point, dtype=float), axis=1)))
    return int(mesh["region"][i])


def pins_in_region(layout_obj, vertex, pins):
    """Indices of ``pins`` (the Design's) lying in the region of layout
    vertex ``vertex``: the layout's own answer, layout.json's vertex key
    "pins" (the rule that applies pins; the Layout recomputes with its
    Design, so its pins are these). A layout stored by an older version,
    without the key: the pins on the solver triangles of that region, or,
    without the region mesh in memory (a reopened document before its
    recompute), those nearer to that vertex than to any other vertex."""
    layout = layout_obj.Proxy.layout(layout_obj)
    vertices = layout.get("vertices", [])
    if "pins" in vertices[vertex]:
        return [int(i) for i in vertices[vertex]["pins"] if 0 <= int(i) < len(pins)]
    mesh = layout_obj.Proxy.mesh(layout_obj)
    if mesh is not None and "region" in mesh:
        region = int(vertices[vertex]["region"])
        return [i for i, p in enumerate(pins) if region_of_point(mesh, p) == region]
    positions = np.asarray([v["position"] for v in vertices], dtype=float)
    return [i for i, p in enumerate(pins)
            if int(np.argmin(np.linalg.norm(positions - np.asarray(p), axis=1))) == vertex]


def move_vertex(layout_obj, vertex, point):
    """Pin layout vertex ``vertex`` at surface point ``point``: the pin
    replaces those in its region (undo step "Move layout vertex").  Returns
    the Design's new pins.  ValueError (nothing changed) for a vertex the
    layout does not have."""
    layout = layout_obj.Proxy.layout(layout_obj)
    vertices = layout.get("vertices", [])
    if not 0 <= int(vertex) < len(vertices):
        raise ValueError("StripWeave: layout '{}' has no vertex {}".format(layout_obj.Label, vertex))
    design = layout_obj.Design
    pins = pins_of(design)
    replaced = set(pins_in_region(layout_obj, int(vertex), pins))
    pins = [p for i, p in enumerate(pins) if i not in replaced] + [[float(c) for c in point]]
    _write_pins(design, pins, MOVE)
    return pins


def route_edge(layout_obj, edge, point):
    """Route layout edge ``edge`` through surface point ``point`` (undo step
    "Re-route layout edge"); the route replaces the edge's earlier one.
    Returns the Design's new routes.  ValueError (nothing changed) for an
    edge the layout does not have."""
    layout = layout_obj.Proxy.layout(layout_obj)
    edges = layout.get("edges", [])
    if not 0 <= int(edge) < len(edges):
        raise ValueError("StripWeave: layout '{}' has no edge {}".format(layout_obj.Label, edge))
    design = layout_obj.Design
    # The layout names the route that is the edge's (its "route": the native
    # rule that applies routes), so the editor replaces that one.
    routes = [r for i, r in enumerate(routes_of(design)) if i != edges[int(edge)].get("route")]
    routes.append({"through": [float(c) for c in point],
                   "across": [float(c) for c in edges[int(edge)]["crossing_point"]]})
    _write_pins(design, pins_of(design), ROUTE, routes)
    return routes


def remove_pin(layout_obj, index):
    """Remove the Design's pin ``index`` (undo step "Remove layout pin"):
    its region's vertex goes back to its automatic place.  ValueError
    (nothing changed) for a pin the Design does not have."""
    design = layout_obj.Design
    pins = pins_of(design)
    if not 0 <= int(index) < len(pins):
        raise ValueError("StripWeave: design '{}' has no pin {}".format(design.Label, int(index) + 1))
    del pins[int(index)]
    _write_pins(design, pins, REMOVE_PIN)
    return pins


def remove_route(layout_obj, index):
    """Remove the Design's edge route ``index`` (undo step "Remove edge
    route"): its edge is routed automatically again.  ValueError (nothing
    changed) for a route the Design does not have."""
    design = layout_obj.Design
    routes = routes_of(design)
    if not 0 <= int(index) < len(routes):
        raise ValueError("StripWeave: design '{}' has no edge route {}".format(design.Label, int(index) + 1))
    del routes[int(index)]
    _write_pins(design, pins_of(design), REMOVE_ROUTE, routes)
    return routes


def clear_pins(layout_obj):
    """Remove every pin and edge route of the Layout's Design (undo step
    "Clear layout pins"); the vertices and edges go back to their automatic
    places.  False if there were none."""
    design = layout_obj.Design
    if not pins_of(design) and not routes_of(design):
        return False
    _write_pins(design, [], CLEAR, [])
    return True
