"""Stages 4 and 5, regions and primalization (paper §4.2, §7): a design's quad layout.

    ds = DesignSession(surface, Design.load("design.json"))
    result = compute_layout(ds)        # the content of layout.json (design.md)
    result["valid"], result["summary"]["patches"]
    write_layout(result, "out/layout.json")

compute_layout returns, in model units:
    regions    [{"valence", "disc", "colour" (none|red|orange|yellow), "total_curvature",
                 "ideal_valence", "area", "singularities", ...}]
    valid      no region is red (only then are there vertices, edges and patches)
    vertices   [{"position", "valence", "boundary", "placement", "clearance" (from the loops,
                 within its region), "inradius" (its region's largest clearance)}]
    edges      [{"points", "vertices": [i, j], "sharp", "boundary", "length"}]
    patches    [{"edges": [4], "reversed": [4], "corners": [4], "corner_angles_deg": [4], "area"}]
    summary    {"patches", "irregular_vertices": {"3": n, ...}, "boundary_vertices": {...},
                "corner_deviation_deg": {"mean", "max"}, "euler": {"V", "E", "F", "chi"}}
    problems   what keeps the embedding from a clean quad layout (empty when it is one)
    timings_ms {"regions", "layout"}
"""
import json

from ._native import native

REGION_KEYS = ("valence", "disc", "colour", "total_curvature", "ideal_valence", "euler_characteristic",
               "boundaries", "genus", "area")


def _region(r):
    out = {k: r[k] for k in REGION_KEYS}
    out["singularities"] = [{"position": s["position"], "index": s["index"]} for s in r["singularities"]]
    return out


def layout_json(raw):
    """layout.json content from the native layout dict (DesignState.layout or native.layout)."""
    return {
        "regions": [_region(r) for r in raw["regions"]],
        "valid": bool(raw["valid"]),
        "vertices": raw["vertices"],
        "edges": [{**{k: v for k, v in e.items() if k != "points"}, "points": e["points"].tolist()}
                  for e in raw["edges"]],
        "patches": raw["patches"],
        "summary": raw["summary"],
        "problems": list(raw["problems"]),
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
        return "\n".join(lines)
    s = result["summary"]
    irregular = ", ".join(f"{n} of valence {v}" for v, n in sorted(s["irregular_vertices"].items())) or "none"
    e = s["euler"]
    lines.append(f"layout: {s['patches']} patches, {e['V']} vertices, {e['E']} edges; "
                 f"irregular vertices: {irregular}")
    lines.append(f"corner angles: deviate from 90 deg by {s['corner_deviation_deg']['mean']:.1f} deg on average, "
                 f"{s['corner_deviation_deg']['max']:.1f} at most")
    lines.append(f"Euler check: V - E + F = {e['V'] - e['E'] + e['F']} (surface: {e['chi']})")
    for p in result["problems"]:
        lines.append(f"problem: {p}")
    t = result["timings_ms"]
    lines.append(f"regions {t['regions']:.0f} ms, layout {t['layout']:.0f} ms")
    return "\n".join(lines)
