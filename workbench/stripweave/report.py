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
    for warning in report.get("warnings", []):
        lines.append(f"  warning: {warning}")
    return "\n".join(lines)
