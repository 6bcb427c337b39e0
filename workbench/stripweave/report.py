"""Human-readable surface report (the `info` text and the FreeCAD report view)."""

INFO_KEYS = ("vertices", "triangles", "components", "genus", "boundary_loops",
             "feature_curves", "feature_edges", "brep_faces", "bbox_diagonal")


def info_dict(surface):
    """The `info --json` object: the keys of design.md, plus `warnings`."""
    report = surface.report()
    out = {key: report[key] for key in INFO_KEYS}
    out["warnings"] = list(report["warnings"])
    return out


def format_report(report):
    """Text lines for a report dict (from Surface.report() or info_dict())."""
    source = f"B-rep with {report['brep_faces']} faces" if report["brep_faces"] else "mesh"
    lines = [
        f"StripWeave surface ({source})",
        f"  solver mesh     {report['vertices']} vertices, {report['triangles']} triangles",
        f"  topology        {report['components']} component(s), genus {report['genus']}, "
        f"{report['boundary_loops']} boundary loop(s)",
        f"  sharp features  {report['feature_curves']} curve(s), {report['feature_edges']} mesh edges",
        f"  size            bounding-box diagonal {report['bbox_diagonal']:.6g}",
    ]
    for sym in report.get("symmetry", ()):
        lines.append("  symmetry        " + format_symmetry(sym))
    if "symmetry" in report and not report["symmetry"]:
        lines.append("  symmetry        none found")
    for warning in report.get("warnings", []):
        lines.append(f"  warning: {warning}")
    return "\n".join(lines)


def format_symmetry(sym):
    """One line for a symmetry dict (symmetry.py): what, where, and its errors."""
    def v(x):
        return "(" + ", ".join(f"{c:.4g}" for c in x) + ")"
    if sym["kind"] == "reflection":
        what = f"reflection in the plane through {v(sym['point'])} with normal {v(sym['normal'])}"
    else:
        what = f"rotation of order {sym['order']} about the axis through {v(sym['point'])} along {v(sym['axis'])}"
    return f"{what}; {sym.get('source', 'given')}, error RMS {sym['rms_error']:.3g}, max {sym['max_error']:.3g}"
