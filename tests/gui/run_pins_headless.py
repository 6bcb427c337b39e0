"""Pinned layout vertices (layout_pins.py) under freecadcmd, run by
tests/gui/test_pins_headless.py: three great circles on Part.makeSphere(5)
(eight octant vertices); the (+,+,+) vertex is moved to P1, then to P2 (the
second pin replaces the first: same region), the (-,-,-) vertex to P3 (a
second pin); the edge from the (+,+,+) vertex to the (+,+,-) one is routed
through T1, then T2 (the second route replaces the first: same edge);
Clear removes pins and routes; undo restores them; both are in the
exported design.json and survive save / reopen; in the reopened document
the route is removed alone, and a pin it does not have is refused.  On a
cube, whose edges follow its creases, a route is kept in the design but the
layout refuses it and says so in its Status.  Writes JSON to
$STRIPWEAVE_HEADLESS_RESULT and exits with os._exit."""

import json
import os
import sys
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

result = {"error": None}
WORKDIR = os.environ.get("STRIPWEAVE_HEADLESS_WORKDIR", "/tmp")
GREAT_CIRCLES = [[(5, 0, 0, 0, 1, 0)], [(0, 5, 0, 0, 0, 1)], [(0, 0, 5, 1, 0, 0)]]
TRIANGLES = 8000


def on_sphere(d):
    n = sum(c * c for c in d) ** 0.5
    return [5 * c / n for c in d]


P1, P2, P3 = on_sphere((0.8, 0.3, 0.52)), on_sphere((0.35, 0.75, 0.5)), on_sphere((-0.3, -0.5, -0.8))
# Points of the (+,+,+) and (+,+,-) octants, off the edge between their vertices.
T1, T2 = on_sphere((0.9, 0.15, 0.35)), on_sphere((0.2, 0.9, -0.35))


def edge_between(layout, a, b):
    lj = json.loads(layout.LayoutJson)
    sign = lambda p: tuple(1 if c > 0 else -1 for c in p)
    for k, e in enumerate(lj["edges"]):
        if {sign(lj["vertices"][i]["position"]) for i in e["vertices"]} == {a, b}:
            return k, e
    return None, None


def octant(layout, signs):
    """(index, vertex) of the layout vertex in the octant of ``signs``."""
    lj = json.loads(layout.LayoutJson)
    for i, v in enumerate(lj["vertices"]):
        if all((c > 0) == (s > 0) for c, s in zip(v["position"], signs)):
            return i, v
    return None, None


def state(layout, design):
    lj = json.loads(layout.LayoutJson)
    _, a = octant(layout, (1, 1, 1))
    _, b = octant(layout, (-1, -1, -1))
    routed = [e for e in lj["edges"] if e.get("through") is not None]
    _, between = edge_between(layout, (1, 1, 1), (1, 1, -1))
    return {"routes": routes_of(design), "routed": routed, "between": between,
            "pins": pins_of(design), "placements": sorted(v["placement"] for v in lj["vertices"]),
            "ppp": a, "mmm": b, "patches": layout.PatchCount, "clean": layout.Clean,
            "undo": (design.Document.UndoNames or [None])[0]}


try:
    import FreeCAD as App
    import Part
    from freecad.stripweave_wb import design_model, layout_model, surface_model
    from freecad.stripweave_wb.layout_pins import (clear_pins, move_vertex, pins_of, remove_pin, remove_route,
                                                   route_edge, routes_of)

    doc = App.newDocument("PinsHeadless")
    doc.UndoMode = 1
    part = doc.addObject("Part::Feature", "Sphere")
    part.Shape = Part.makeSphere(5)
    sm = surface_model.create(part, target_triangles=TRIANGLES)
    doc.recompute()
    from stripweave.design import Design
    design = design_model.create(sm, Design(GREAT_CIRCLES))
    doc.recompute()
    layout = layout_model.create(design)
    result["points"] = {"P1": P1, "P2": P2, "P3": P3}
    result["solver_edge"] = (4 * 3.141592653589793 * 25 / TRIANGLES * 4 / 3 ** 0.5) ** 0.5
    result["before"] = state(layout, design)
    k, _ = octant(layout, (1, 1, 1))
    move_vertex(layout, k, P1)
    result["first"] = state(layout, design)
    k, _ = octant(layout, (1, 1, 1))
    move_vertex(layout, k, P2)
    result["replaced"] = state(layout, design)
    k, _ = octant(layout, (-1, -1, -1))
    move_vertex(layout, k, P3)
    result["second"] = state(layout, design)
    result["points"].update({"T1": T1, "T2": T2})
    k, _ = edge_between(layout, (1, 1, 1), (1, 1, -1))
    route_edge(layout, k, T1)
    result["routed"] = state(layout, design)
    k, _ = edge_between(layout, (1, 1, 1), (1, 1, -1))
    route_edge(layout, k, T2)
    result["rerouted"] = state(layout, design)
    try:
        route_edge(layout, 99, T1)
        result["bad_edge"] = None
    except Exception as exc:
        result["bad_edge"] = "{}: {}".format(type(exc).__name__, exc)
    try:
        move_vertex(layout, 99, P3)
        result["bad_vertex"] = None
    except Exception as exc:
        result["bad_vertex"] = "{}: {}".format(type(exc).__name__, exc)
    path = os.path.join(WORKDIR, "pinned_design.json")
    design_model.export_design(design, path)
    with open(path) as f:
        exported = json.load(f)
        result["exported_pins"] = exported.get("pins")
        result["exported_routes"] = exported.get("edge_routes")
    result["cleared_returned"] = clear_pins(layout)
    result["cleared"] = state(layout, design)
    doc.undo()
    doc.recompute()
    result["undone"] = state(layout, design)
    fcstd = os.path.join(WORKDIR, "pins.FCStd")
    doc.saveAs(fcstd)
    App.closeDocument(doc.Name)
    doc = App.openDocument(fcstd)
    design = [o for o in doc.Objects if design_model.is_design(o)][0]
    result["reopened_pins"] = pins_of(design)
    result["reopened_routes"] = routes_of(design)
    layout = [o for o in doc.Objects if layout_model.is_layout(o)][0]
    doc.UndoMode = 1
    remove_route(layout, 0)
    result["route_removed"] = {"routes": routes_of(design), "pins": pins_of(design),
                               "undo": (doc.UndoNames or [None])[0]}
    try:
        remove_pin(layout, 5)
        result["bad_pin"] = None
    except Exception as exc:
        result["bad_pin"] = "{}: {}".format(type(exc).__name__, exc)
    # A cube's edges follow its creases: a route of one is kept in the design but the
    # layout refuses it, and its Status says why.
    cube_doc = App.newDocument("RouteOnCrease")
    box = cube_doc.addObject("Part::Feature", "Box")
    box.Shape = Part.makeBox(10, 10, 10)
    cube_sm = surface_model.create(box, target_triangles=TRIANGLES)
    cube_doc.recompute()
    cube_design = design_model.create(cube_sm, Design([[(5, 5, 10, 1, 0, 0)], [(5, 3, 0, 0, 1, 0)],
                                                       [(3, 0, 5, 1, 0, 0)]]))
    cube_doc.recompute()
    cube_layout = layout_model.create(cube_design)
    route_edge(cube_layout, 0, (5.0, 5.0, 10.0))
    result["crease_route"] = {"routes": routes_of(cube_design), "status": cube_layout.Status,
                              "clean": cube_layout.Clean}
except Exception:
    result["error"] = traceback.format_exc()
finally:
    with open(os.environ.get("STRIPWEAVE_HEADLESS_RESULT", "/tmp/pins_headless.json"), "w") as f:
        json.dump(result, f, indent=1, default=str)
    os._exit(0)
