"""StripWeave: quad patch layouts by Dual Strip Weaving (Campen & Kobbelt 2014).

The Python face of the native library. Works in FreeCAD (GUI and freecadcmd)
and in Debian's /usr/bin/python3 with FreeCAD's library folder on sys.path.

    import stripweave as sw
    surf = sw.load("part.step", target_triangles=30000)
    print(sw.format_report(surf.report()))
    surf.vertices, surf.triangles          # solver mesh, model units
    surf.k_min, surf.k_max, surf.d_min, surf.d_max, surf.normals
    surf.feature_curves, surf.boundary_loops

See stripweave.surface for every way to load a model and the options.

The main job, part in, quad layout out (stripweave.job, issue 6):

    report = sw.weave("part.step", out="woven")     # automatic weaving from scratch
    report = sw.weave(shape, design="design.json", auto=True, out="woven", max_strips=30, patches=120)
    report["valid"], report["patches"], report["irregular_vertices"], report["paths"]["preview"]

weave() takes a model file, a Part shape or a Surface; `design` (a Design or a design.json
path) is kept and completed; with `out` it writes design.json, layout.json, report.json and
preview.png there. The result is report.json's content plus "paths", "log" (why each strip
was added), "stopped", "surface" and "design". examples/weave_macro.py is a FreeCAD macro.
"""
from ._native import native as _native
from .report import format_report, info_dict
from .surface import SurfaceOptions, from_mesh, from_object, from_shape, load, make_options
from .job import weave

InputError = _native.InputError
Cancelled = _native.Cancelled
Progress = _native.Progress
Surface = _native.Surface
read_mesh = _native.read_mesh
write_mesh = _native.write_mesh

__all__ = ["load", "from_shape", "from_mesh", "from_object", "make_options", "SurfaceOptions",
           "Surface", "Progress", "InputError", "Cancelled", "format_report", "info_dict",
           "read_mesh", "write_mesh", "weave"]
