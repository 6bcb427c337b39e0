"""Stages 4 and 5, regions and primalization (paper §4.2, §7): a design's quad layout.

    ds = DesignSession(surface, Design.load("design.json"))
    result = compute_layout(ds)        # the content of layout.json (design.md)
    result["valid"], result["summary"]["patches"]
    write_layout(result, "out/layout.json")

compute_layout returns, in model units:
    regions    [{"valence", "disc", "colour" (none|red|orange|yellow|crease), "total_curvature",
                 "ideal_valence", "area", "singularities", "excess_extrema" (curvature extrema of
                 one kind beyond the first), "crease_problem" (why a crease region is one), ...}]
    valid      no region is red (only then are there vertices, edges and patches)
    vertices   [{"position", "valence", "boundary", "placement", "clearance" (from the loops,
                 within its region), "inradius" (its region's largest clearance), "image_of" (under
                 the design's symmetry: the vertex it is the image of, else None), "pins" (indices
                 in design.json's "pins" of those in its region; the last places it)}]
    edges      [{"points", "vertices": [i, j], "sharp", "boundary", "length", "crossing_point" (where
                 it crosses its loop), "through" (the point of a hand route, design.json's
                 "edge_routes", it goes through; None), "route" (the index in "edge_routes" of
                 the route that names the edge, taken or refused; None)}]
    patches    [{"edges": [4], "reversed": [4], "corners": [4], "corner_angles_deg": [4], "area",
                 "inradius", "defects": [kind, ...]}] (in the order of the native layout(True))
    summary    {"patches", "irregular_vertices": {"3": n, ...}, "boundary_vertices": {...},
                "corner_deviation_deg": {"mean", "max"}, "euler": {"V", "E", "F", "chi"}}
    problems   what keeps the embedding from a clean quad layout (empty when it is one)
    clean      valid, crease-conforming and without defects
    crease_conformity  crease length on primal edges / total crease length (1 without creases)
    crease_conforming  no crease region, and at most 1e-6 of the diagonal of crease off the edges
    crease_off_edges   crease length off the primal edges, model units
    defects    the strict checks' counts (native layout_defects.h), DEFECT_KEYS
    defect_locations  [{"kind", "position" (model units), "patch" | "vertex" | "edges" (the
                 touching pair) | "triangles" (of an uncovered piece), "text"}]
    timings_ms {"regions", "layout"}
Vertices carry "defects" (valence2: valence 2 or 1, high_valence) and edges "defects" (overlapping_edges);
patches' kinds are non_quad, overlapping_edges (a side overlaps), creased, degenerate.
"""
import json

from ._native import native

REGION_KEYS = ("valence", "disc", "colour", "total_curvature", "ideal_valence", "euler_characteristic",
               "boundaries", "open_sides", "on_open_boundary", "genus", "area", "excess_extrema", "crease_problem", "crease_excess")


DEFECT_KEYS = ("non_quad_patches", "overlapping_edges", "valence2_vertices", "high_valence_vertices",
               "creased_patches", "degenerate_patches", "uncovered_triangles")
# Per count key: the location kind it is reported with, and its words (one, many).
DEFECT_WORDS = {
    "non_quad_patches": ("non_quad", "patch without 4 corners", "patches without 4 corners"),
    "overlapping_edges": ("overlapping_edges", "edge overlapping or touching another",
                          "edges overlapping or touching others"),
    "valence2_vertices": ("valence2", "vertex of valence 2 or 1", "vertices of valence 2 or 1"),
    "high_valence_vertices": ("high_valence", "vertex of valence above 6 that no part corner forces",
                              "vertices of valence above 6 that no part corner forces"),
    "creased_patches": ("creased", "patch over a crease", "patches over a crease"),
    "degenerate_patches": ("degenerate", "degenerate (tiny or thin) patch", "degenerate (tiny or thin) patches"),
    "uncovered_triangles": ("uncovered", "surface triangle in no patch or in two",
                            "surface triangles in no patch or in two"),
}


def _point(p):
    return "(" + ", ".join(f"{x:.4g}" for x in p) + ")"


def _location_text(loc):
    _, one, many = next(w for w in DEFECT_WORDS.values() if w[0] == loc["kind"])
    if "patch" in loc:
        what = f"patch {loc['patch']}: {one}"
    elif "vertex" in loc:
        what = f"vertex {loc['vertex']}: {one}"
    elif "edges" in loc:
        i, j = loc["edges"]
        what = f"edge {i} runs over itself" if i == j else f"edges {i} and {j} overlap or touch"
    else:
        what = f"{loc['triangles']} {one if loc['triangles'] == 1 else many}"
    return f"{what} at {_point(loc['position'])}"


def _crease_words(result):
    """What keeps a layout from being crease-conforming, in words (empty when it is)."""
    if result is None or result.get("crease_conforming", True):
        return []
    regions = result.get("regions", [])
    if isinstance(regions, dict):   # report.json's counts by colour
        n, kinds = int(regions.get("crease", 0)), []
    else:                           # layout.json's regions
        crease = [r for r in regions if r.get("colour") == "crease"]
        n, kinds = len(crease), sorted({r.get("crease_problem", "") for r in crease} - {"", "none"})
    words = f"{n} crease region{'s' if n != 1 else ''}"
    if kinds:
        words += " (" + ", ".join(kinds) + ")"
    return [f"not crease-conforming: {100 * result.get('crease_conformity', 0):.1f}% of the crease length "
            f"on primal edges; {words}"]


def format_defects(clean, defects, locations, first=3, result=None):
    """'clean: ...', or 'NOT clean; defects:' and a line per kind, e.g. '  3 patches without 4
    corners (first at (..), ..)': counted in words, with the model-unit locations of the first
    few, and (given the layout `result`) what keeps it from being crease-conforming."""
    if clean:
        return "clean: no layout defects, crease-conforming"
    parts = _crease_words(result) if result is not None and result.get("valid") else []
    for key in DEFECT_KEYS:
        n = defects.get(key, 0)
        if not n:
            continue
        kind, one, many = DEFECT_WORDS[key]
        located = [_point(loc["position"]) for loc in locations if loc["kind"] == kind]
        where = list(dict.fromkeys(located))[:first]   # pairs of edges often touch at one point
        at = ""
        if len(located) == 1:
            at = f" at {where[0]}"
        elif located:   # uncovered triangles are located per piece, overlaps per pair
            places = f" in {len(located)} places" if len(located) != n else ""
            at = f"{places} (first at " + ", ".join(where) + ")"
        parts.append(f"{n} {one if n == 1 else many}{at}")
    if not parts:
        return "NOT clean: the layout is not valid"
    return "NOT clean; defects:\n" + "\n".join("  " + p for p in parts)


def _region(r):
    out = {k: r[k] for k in REGION_KEYS}
    out["singularities"] = [{"position": s["position"], "index": s["index"]} for s in r["singularities"]]
    return out


def layout_json(raw):
    """layout.json content from the native layout dict (DesignState.layout or native.layout)."""
    defects = {k: int(raw["defects"][k]) for k in DEFECT_KEYS}
    locations = [{**loc, "text": _location_text(loc)} for loc in raw["defect_locations"]]
    return {
        "regions": [_region(r) for r in raw["regions"]],
        "valid": bool(raw["valid"]),
        "vertices": raw["vertices"],
        "edges": [{**{k: v for k, v in e.items() if k != "points"}, "points": e["points"].tolist()}
                  for e in raw["edges"]],
        "patches": raw["patches"],
        "summary": raw["summary"],
        "problems": list(raw["problems"]),
        "clean": bool(raw["valid"]) and not any(defects.values()) and bool(raw["crease_conforming"]),
        "crease_conformity": float(raw["crease_conformity"]),
        "crease_conforming": bool(raw["crease_conforming"]),
        "crease_off_edges": float(raw["crease_off_edges"]),
        "defects": defects,
        "defect_locations": locations,
        "crossings": raw["crossings"],
        "timings_ms": {"regions": raw["time_ms"], "layout": raw["layout_ms"]},
    }


def compute_layout(design_session):
    """The regions and, for a valid design, the primal quad layout of a DesignSession."""
    return layout_json(design_session.native.layout())


def write_layout(result, path):
    """Write layout.json atomically (files.write_atomic: a reader never sees half a file)."""
    from .files import write_atomic
    return write_atomic(path, json.dumps(result))


def format_summary(result):
    """A few lines for people."""
    colours = {}
    for r in result["regions"]:
        colours[r["colour"]] = colours.get(r["colour"], 0) + 1
    lines = [f"regions: {len(result['regions'])} ("
             + ", ".join(f"{n} {c}" for c, n in sorted(colours.items())) + ")"]
    if not result["valid"]:
        lines.append("layout: invalid (red regions are not discs: add strips that split them)")
        lines.append(format_defects(result["clean"], result["defects"], result["defect_locations"], result=result))
        return "\n".join(lines)
    s = result["summary"]
    irregular = ", ".join(f"{n} of valence {v}" for v, n in sorted(s["irregular_vertices"].items())) or "none"
    e = s["euler"]
    lines.append(f"layout: {s['patches']} patches, {e['V']} vertices, {e['E']} edges; "
                 f"irregular vertices: {irregular}")
    quads = sum(1 for p in result["patches"] if p.get("quad", True))
    lines.append(f"corner angles: deviate from 90 deg by {s['corner_deviation_deg']['mean']:.1f} deg on average, "
                 f"{s['corner_deviation_deg']['max']:.1f} at most"
                 + (f", over the {quads} quads of {s['patches']} patches (the others have no quad corners)"
                    if quads < s["patches"] else ""))
    lines.append(f"Euler check: V - E + F = {e['V'] - e['E'] + e['F']} (surface: {e['chi']})")
    lines.append(format_defects(result["clean"], result["defects"], result["defect_locations"], result=result))
    for p in result["problems"]:
        lines.append(f"problem: {p}")
    t = result["timings_ms"]
    lines.append(f"regions {t['regions']:.0f} ms, layout {t['layout']:.0f} ms")
    return "\n".join(lines)
