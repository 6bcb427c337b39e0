"""The main job (issue 6): part in, layout out. `stripweave.weave(...)` and `stripweave weave`.

    import stripweave as sw
    report = sw.weave("part.step", out="woven")            # automatic, from an empty design
    report = sw.weave(shape, design="design.json", auto=True, out="woven", max_strips=30)
    report["valid"], report["patches"], report["paths"]["preview"]

Stages: surface (load, remesh) -> loop engine (elastica graph) -> design (the given strips,
re-derived) -> weave (automatic completion, weave.py) -> layout (regions and the primal
quad layout, layout.compute_layout) -> files. With `out`, writes
    design.json   the design (reloads; hand-editable; auto-added strips say why in "added_by")
    layout.json   regions, vertices, edges, patches (design.md)
    report.json   the keys of design.md, and input_triangles, solver_triangles,
                  corner_deviation_deg["p95"] and memory_mb {stage: {"rss", "peak"}}: the
                  resident memory after each stage and the peak so far, and with
                  STRIPWEAVE_STAGE_PEAKS=1 each stage's own peak (memory.py, README)
    preview.png   the layout on the shaded model (preview.py)
    patches.step  with step=True, when the build has the surfacing stage
    deviation.png with step=True: the patches coloured by their fit's deviation (preview.py)
The returned dict is report.json's content plus "paths", "log" (one entry per added
strip), "taken_back" (per added strip weaving took back at the end, weave._take_back),
"stopped" (why weaving ended), "work" (units spent, weave.py),
"defect_locations" (layout.json's, for the CLI to say where), "why_red" (an invalid
layout: which red regions remain, where, and what to try; else None), "why_crease" (the
same for the crease regions of a valid layout that is not crease-conforming) and
"cancelled_queries" (loop queries cut by the timeout: the only machine-dependent step
besides the wall-clock safety net).
"""
import contextlib
import functools
import json
import os
import sys
import time
from dataclasses import dataclass

from ._native import native
from .design import Design
from .files import atomic_path, check_out_dir, out_lock, write_atomic
from .layout import write_layout
from .memory import StageMemory
from .strips import DesignSession
from .weave import WeaveOptions, auto_weave, crease_regions, red_regions, why_crease, why_red

REPORT_KEYS = ("valid", "strips", "patches", "regions", "irregular_vertices", "corner_deviation_deg",
               "bbox_diagonal", "timings_ms")


def _surface_of(model, progress, surface_options):
    from .surface import from_shape, load
    if isinstance(model, native.Surface):
        return model
    if isinstance(model, (str, os.PathLike)):
        if not os.path.exists(model):
            raise native.InputError(f"model file {os.fspath(model)} does not exist")
        return load(model, progress=progress, **surface_options)
    if hasattr(model, "exportBrepToString") or (hasattr(model, "Shape") and hasattr(model.Shape, "exportBrepToString")):
        return from_shape(getattr(model, "Shape", model), progress=progress, **surface_options)
    raise native.InputError(f"weave needs a model file, a Part shape or a Surface, got {type(model).__name__}")


def _layout_of(ds):
    """(layout.json's content, the native layout with its per-triangle details or None):
    layout.layout_json of the design's layout where the build has it, the details kept for
    preview.png and deviation.png (one layout for the three); else the regions alone (no
    primal layout: empty vertices, edges and patches) and None."""
    try:
        from .layout import layout_json
    except ImportError:
        layout_json = None
    if layout_json is not None:
        details = ds.native.layout(True)
        return layout_json(details), details
    start = time.perf_counter()
    sing = ds.singularities()
    r = native.regions(ds.loop_session.native, native.design_loops(ds.native), [x["vertex"] for x in sing],
                       [round(4 * x["index"]) for x in sing], False)
    keys = ("valence", "disc", "colour", "total_curvature")
    ms = (time.perf_counter() - start) * 1000.0
    return {"regions": [{k: g[k] for k in keys} for g in r["regions"]], "valid": bool(r["valid"]),
            "vertices": [], "edges": [], "patches": [],
            "summary": {"patches": 0, "irregular_vertices": {}, "corner_deviation_deg": {"mean": 0.0, "max": 0.0},
                        "euler": {}},
            "timings_ms": {"regions": ms, "layout": 0.0}}, None


def make_report(ds, layout, timings_ms):
    """report.json (design.md): the figures come from layout.json, so they always agree."""
    colours = {"red": 0, "orange": 0, "yellow": 0, "crease": 0, "none": 0}
    for g in layout["regions"]:
        colours[g["colour"]] += 1
    summary = layout.get("summary", {})
    irregular = {str(k): int(v) for k, v in sorted(summary.get("irregular_vertices", {}).items(),
                                                    key=lambda kv: int(kv[0]))}
    deviation = summary.get("corner_deviation_deg", {"mean": 0.0, "max": 0.0})
    # The strict checks (layout.json's; a build without the layout stage has none: not clean).
    defects = {k: int(v) for k, v in layout.get("defects", {}).items()}
    return {"valid": bool(layout["valid"]), "clean": bool(layout.get("clean", False)), "defects": defects,
            "crease_conformity": float(layout.get("crease_conformity", 0.0)),
            "crease_conforming": bool(layout.get("crease_conforming", False)),
            "strips": len(ds.design.strips), "patches": len(layout["patches"]),
            "regions": colours, "irregular_vertices": irregular,
            "corner_deviation_deg": {"mean": float(deviation["mean"]), "max": float(deviation["max"]),
                                     "p95": _corner_deviation_p95(layout), **_corner_coverage(layout)},
            "input_triangles": int(ds.surface.input_triangles), "solver_triangles": len(ds.surface.triangles),
            "bbox_diagonal": float(ds.design.model.get("bbox_diagonal") or ds.surface.report()["bbox_diagonal"]),
            "timings_ms": {k: round(float(v), 1) for k, v in timings_ms.items()}}


def _describe(sym):
    kind = "reflection" if sym["kind"] == "reflection" else f"rotation of order {sym['order']}"
    return f"{kind} ({sym['source']}, max error {sym['max_error']:.3g})"


def symmetry_report(ds, layout, symmetries):
    """report.json's "symmetry": each symmetry (design.md's keys, model units) with how far the
    result is from respecting it: "loops_max_error", the largest distance from a strip's
    loop mapped by the symmetry to the nearest loop of the design, and "layout_max_error",
    from a mapped layout vertex to the nearest layout vertex (None without vertices)."""
    from .symmetry import layout_symmetry_error, loops_symmetry_error
    loops = [s["points"] for s in ds.strips()]
    out = []
    for sym in symmetries:
        entry = dict(sym)
        entry["loops_max_error"] = loops_symmetry_error(loops, sym) if loops else 0.0
        entry["layout_max_error"] = layout_symmetry_error(layout, sym)
        out.append(entry)
    return out


def _corner_coverage(layout):
    """What the corner figures leave out, so that they cannot flatter: mean, max and p95 are
    over the quad patches' corners only (a patch that is no quad has no quad corners), so
    "quads" says over how many of the "patches" they are, and "mean_all_patches" counts each
    patch that is no quad as four corners 90 degrees off (a layout of few good quads among
    many broken patches otherwise reads as a good one). README: report.json's added keys."""
    patches = layout["patches"]
    quads = [p for p in patches if p.get("quad", True) and p.get("corner_angles_deg")]
    total = sum(abs(a - 90.0) for p in quads for a in p["corner_angles_deg"]) + 4 * 90.0 * (len(patches) - len(quads))
    corners = sum(len(p["corner_angles_deg"]) for p in quads) + 4 * (len(patches) - len(quads))
    return {"quads": len(quads), "patches": len(patches), "mean_all_patches": total / corners if corners else 0.0}


def _corner_deviation_p95(layout):
    """The 95th percentile of |angle - 90| over the quad patches' corners (layout.json's
    corner_angles_deg; non-quads have none, as in the mean): a few bad corners that the
    mean averages away show here. 0 without quads."""
    deviations = sorted(abs(a - 90.0) for p in layout["patches"] for a in p.get("corner_angles_deg", ()))
    if not deviations:
        return 0.0
    rank = 0.95 * (len(deviations) - 1)   # linear interpolation between order statistics
    low = int(rank)
    high = min(low + 1, len(deviations) - 1)
    return float(deviations[low] + (rank - low) * (deviations[high] - deviations[low]))


def _export_step(ds, tolerance, path, symmetries=(), symmetry_tolerance=None, set_aside_red=False):
    """Fit NURBS patches to the design's primal layout and write them as STEP (the surfacing
    stage). Returns the "fit" block of report.json (model units: design.md's two-sided
    deviations, coverage, seam figures, per patch, shell facts) and, per surface triangle,
    the fraction of its source area not within tolerance of a fitted patch (deviation.png).
    symmetries: the ones the weave used (design.md dicts, model units): the patches are fitted
    exactly symmetric (native symmetric_fit.h); symmetry_tolerance: model units;
    set_aside_red: fit the components that hold no red region (refit_design)."""
    from .surfacing import fit_report, refit_design
    options = {}
    if symmetries:
        options["symmetries"] = [dict(s) for s in symmetries]
        if symmetry_tolerance:
            options["symmetry_tolerance"] = symmetry_tolerance
    result = refit_design(ds, tolerance=tolerance, step_path=path, set_aside_red=set_aside_red, **options)
    return fit_report(result), result.get("triangle_uncovered")


def _set_aside(ds, layout, components):
    """What the STEP leaves out of an invalid layout, as native code decides it: the layout
    of the components that hold no red region (layout_with(set_aside_red=True); native
    layout/set_aside.h), and the report's ids of the components it sets aside. A red region
    has no layout (paper §4.2), but the loops of different components never meet, so the
    others' layout is the one they would have alone: an assembly whose weave leaves one solid
    red still gets the other solids' patches (issue 18: everything it has is written).
    Returns ([], None) for a valid layout, a one-component part, or when every component
    holds a red region (native code then returns the full invalid layout)."""
    if layout["valid"] or not components:
        return [], None
    import numpy as np
    from .components import triangle_components
    aside = ds.native.layout_with([], True, [], True)
    if not aside["valid"]:
        return [], None
    flags = np.array([bool(r["set_aside"]) for r in aside["regions"]] + [False])
    region = np.asarray(aside["triangle_region"], dtype=np.int64)
    parent = np.asarray(aside["parent_triangle"], dtype=np.int64)
    marked = np.unique(parent[flags[np.where(region < 0, len(flags) - 1, region)]])
    if not len(marked):
        return [], None
    ids = triangle_components(ds.surface.triangles, len(ds.surface.vertices))
    return sorted(set(int(c) for c in ids[marked])), aside


@dataclass
class _Output:
    """Where a weave writes and how it reports: the folder, the paths written so far (by
    name), whether pictures are rendered, the progress line and the stage clock."""
    out: str
    paths: dict
    preview: bool
    say: object
    lap: object


@dataclass
class _FitSettings:
    """What the surfacing stage is asked for: the tolerance (model units; None: 1e-3 of the
    diagonal), the symmetries the weave used and their tolerance (a fraction of the diagonal)."""
    tolerance: float
    symmetries: list
    symmetry_tolerance: float


def _write_step(ds, layout, details, report, components, red_text, output, fit):
    """weave's surfacing stage: patches.step, report.json's "fit" block and deviation.png.

    A valid layout is fitted whole. An invalid one is fitted without the components that hold
    a red region when some component holds none (_set_aside): everything the weave
    has is written, and the error still says the layout is not valid. Otherwise there is no
    STEP, and "fit" holds only the reason. Returns the error to raise once report.json is
    written (it names the folder), or None."""
    paths, out, lap = output.paths, output.out, output.lap
    paths["step"] = os.path.join(out, "patches.step")
    set_aside, aside = _set_aside(ds, layout, components)
    invalid = f"cannot fit patches: the layout is not valid: {red_text}"
    if not layout["valid"] and not set_aside:
        return _no_step(report, invalid, output)
    diagonal = report["bbox_diagonal"]
    tol = fit.tolerance if fit.tolerance is not None else 1e-3 * diagonal
    try:
        report["fit"], uncovered = _export_step(ds, tol, paths["step"], fit.symmetries,
                                               fit.symmetry_tolerance * diagonal, set_aside_red=bool(set_aside))
    except native.InputError as exc:
        # With components set aside, the others have no patch to fit either (a stray
        # triangle beside the red part): the layout's own message.
        return _no_step(report, invalid if set_aside else str(exc), output)
    lap("step")
    if set_aside:
        report["fit"]["set_aside_components"] = set_aside
        details = aside if details is not None else None
    if output.preview:
        output.say("rendering deviation.png")
        from .preview import render_deviation
        paths["deviation"] = os.path.join(out, "deviation.png")
        with atomic_path(paths["deviation"]) as tmp:
            render_deviation(tmp, ds, report["fit"], details=details, uncovered=uncovered)
        lap("deviation")
    if not set_aside:
        return None
    # Everything it has is written; the layout is still not valid, and says so.
    message = (f"the layout is not valid: {red_text}; patches.step holds the {report['fit']['faces']} "
               f"patches of the components without a red region (components "
               f"{', '.join(str(c) for c in set_aside)} set aside; coverage "
               f"{100 * report['fit']['coverage']:.1f} % of the part)")
    report["fit"]["error"] = message
    return native.InputError(f"{message} (design, layout and report are in {out})")


def _no_step(report, message, output):
    """No STEP: report.json's "fit" says why, and the error names the folder, where the design
    and its layout are still worth having."""
    report["fit"] = {"error": message}
    del output.paths["step"]
    output.lap("step")
    return native.InputError(f"{message} (design, layout and report are in {output.out})")


def _keep_backup(design_path, target):
    """A weave into the folder of its own design file keeps the given design as design.json.bak."""
    if design_path is not None and os.path.exists(target) and os.path.samefile(design_path, target):
        with open(target, "rb") as f:
            write_atomic(target + ".bak", f.read())


def _releasing_locks(run):
    """Give `run` an ExitStack (_locks) that is closed however it ends: the output folder's
    lock is never left held by a failed run in a long FreeCAD session."""
    @functools.wraps(run)
    def wrapper(*args, **kwargs):
        with contextlib.ExitStack() as locks:
            return run(*args, _locks=locks, **kwargs)
    return wrapper


@_releasing_locks
def weave(model, design=None, auto=True, out=None, max_strips=None, patches=0, features=True, boundary=None,
          seed=0, step=False, tolerance=None, verbose=False, progress=None, target_triangles=30000,
          feature_angle_deg=None, preview=True, symmetry=None, symmetry_tolerance=1e-3, symmetric_mesh=True, _locks=None,
          **weave_options):
    """Weave a quad layout on a model; see the module doc.

    model       a model file path, a Part shape (or object with .Shape) or a Surface
    design      None (start empty), a Design, or a design.json path: its strips are kept, first
    auto        complete the design automatically (False: just evaluate the given design)
    out         folder for design.json, layout.json, report.json, preview.png (None: write nothing)
    max_strips  strips at most (the given ones included; None: 40 beyond the cuts the part's
                handles and holes ask for, weave.cuts_to_discs); patches: target patch count (0: coarse)
    features    align to sharp feature curves; boundary: "aligned" | "trimmed" (default: the design's)
    seed        varies which seed points are tried first (deterministic)
    budget, time_limit_s, refine, uncovered, ...: see weave.WeaveOptions (budget: deterministic
                work units; time_limit_s: the wall-clock safety net)
    step        also fit patches and write patches.step (needs the surfacing stage)
    symmetry    "auto" (detect), "none", a symmetry dict or list of them (symmetry.py), or None
                (the design's "symmetry", else none): every strip weaving adds comes with its
                images (paper §5.8); symmetry_tolerance: the error accepted, in diagonals;
                symmetric_mesh: weave on a solver mesh made exactly symmetric under the
                reflections, or the one rotation (symmetry.symmetric_surface)
    """
    timings = {}
    memory = StageMemory()
    clock = time.perf_counter()

    def lap(stage):
        nonlocal clock
        now = time.perf_counter()
        timings[stage] = timings.get(stage, 0.0) + (now - clock) * 1000.0
        memory.note(stage)
        clock = now

    def say(text):
        if verbose:
            print(f"stripweave weave: {text}", file=sys.stderr, flush=True)

    design_path = os.fspath(design) if isinstance(design, (str, os.PathLike)) else None
    if design_path is not None:
        design = Design.load(design_path)
    if out is not None:
        check_out_dir(out)  # an unusable folder is found before the work, not after
    design = design.copy() if design is not None else Design()
    if boundary is not None:
        if boundary not in ("aligned", "trimmed"):
            raise native.InputError(f"boundary must be 'aligned' or 'trimmed', got {boundary!r}")
        design.options["boundary"] = boundary
    surface_options = {"target_triangles": target_triangles,
                       "feature_angle_deg": float(feature_angle_deg if feature_angle_deg is not None
                                                  else design.options["feature_angle_deg"])}
    say("loading the model")
    surface = _surface_of(model, progress, surface_options)
    lap("surface")
    if isinstance(model, (str, os.PathLike)):
        design.model.setdefault("path", os.path.abspath(os.fspath(model)))
    design.model["bbox_diagonal"] = surface.report()["bbox_diagonal"]
    from .symmetry import resolve
    symmetries = resolve(surface, symmetry, design.symmetry, symmetry_tolerance)
    if symmetry is not None or design.symmetry is not None:
        design.symmetry = symmetries
    lap("symmetry")
    if symmetries:
        say(f"symmetry: {', '.join(_describe(x) for x in symmetries)}")
        if symmetric_mesh:
            from .symmetry import symmetric_surface
            surface = symmetric_surface(surface, symmetries)
    say(f"{len(surface.triangles)} triangles; building the elastica graph")
    from .loops import LoopSession
    loop_session = LoopSession(surface, progress=progress, **design.loop_options())
    lap("graph")
    given = len(design.strips)
    ds = DesignSession(surface, design, loop_session=loop_session, features=features)
    lap("design")
    log, stopped, work, cancelled, taken_back = [], "not asked (auto off)", 0.0, 0, []
    cap = max_strips        # the strip cap weaving had (why_red's hint; "max strips" needs auto)
    if auto:
        result = auto_weave(ds, WeaveOptions(max_strips=max_strips, patches=patches, seed=seed, verbose=verbose,
                                             symmetry=tuple(symmetries), symmetry_tolerance=symmetry_tolerance,
                                             **weave_options))
        log, stopped, work, cancelled = result.log, result.stopped, result.work, result.cancelled_queries
        taken_back = result.taken_back
        cap = result.max_strips
    # No loop query follows: the search scratch space (as large as g') goes back before the
    # layout needs its memory.
    loop_session.native.release_workspaces()
    lap("weave")
    say("primal layout")
    layout, details = _layout_of(ds)
    # The design is derived and its layout computed: nothing after this needs g' (the files,
    # the pictures and the fit read the strips' paths and the layout), which is some 100 MB
    # at 30K triangles and would sit under the pictures' and the fit's peaks. (A build without
    # the layout stage has no details: preview.png then embeds the loops again, on g'.)
    if details is not None:
        loop_session.native.release_graph()
    lap("layout")
    report = make_report(ds, layout, {})
    red_text = None
    if not report["valid"]:
        # Where the layout stays invalid and what to try (issue 18): in report.json and every message.
        every_red = red_regions(ds, limit=None)
        report["red_regions"] = every_red[:5]
        red_text = why_red(report["red_regions"], report["regions"]["red"], stopped, cap,
                           weave_options.get("budget", WeaveOptions.budget))
    crease_text = None
    if report["valid"] and not report.get("crease_conforming", True):
        # A valid layout that does not follow the creases: where and what to try, as for red.
        report["crease_regions"] = crease_regions(ds)
        crease_text = why_crease(report["crease_regions"], report["regions"].get("crease", 0), stopped,
                                 weave_options.get("budget", WeaveOptions.budget))
    from .components import component_report
    components = component_report(ds.surface, layout, every_red if not report["valid"] else ())
    if components:      # an assembly or a multi-component file: each part's own figures
        report["components"] = components
    if symmetry is not None or design.symmetry is not None:   # asked for (even "none"): say what was used
        report["symmetry"] = symmetry_report(ds, layout, symmetries)
    paths = {}
    step_error = None
    if out is not None:
        _locks.enter_context(out_lock(out))  # two runs into one folder write one after the other
        paths = {name: os.path.join(out, f"{name}.{ext}") for name, ext in
                 (("design", "json"), ("layout", "json"), ("report", "json"), ("preview", "png"))}
        _keep_backup(design_path, paths["design"])
        ds.design.save(paths["design"])
        write_layout(layout, paths["layout"])
        lap("files")
        if preview:
            say("rendering preview.png")
            from .preview import render_design
            with atomic_path(paths["preview"]) as tmp:   # a full disk leaves no truncated picture
                render_design(tmp, ds, layout, regions=details)
            lap("preview")
        else:
            del paths["preview"]
        if step:
            say("fitting patches (STEP)")
            step_error = _write_step(ds, layout, details, report, components, red_text,
                                     _Output(out, paths, preview, say, lap),
                                     _FitSettings(tolerance, symmetries, symmetry_tolerance))
    timings.update({f"strips_{k}": v for k, v in ds.timings_ms().items()})
    timings.update({f"layout_{k}": v for k, v in layout.get("timings_ms", {}).items()})
    timings["total"] = sum(v for k, v in timings.items() if "_" not in k)
    report["timings_ms"] = {k: round(float(v), 1) for k, v in timings.items()}
    report["peak_memory_mb"] = memory.peak_mb()
    report["memory_mb"] = memory.stages
    if out is not None:
        write_atomic(paths["report"], json.dumps(report, indent=2) + "\n")
    _locks.close()
    if step_error is not None:
        raise step_error
    say(f"{report['strips']} strips ({given} given), {report['patches']} patches, "
        f"{'valid' if report['valid'] else 'INVALID'}, {timings['total'] / 1000:.1f} s")
    return {**report, "paths": paths, "log": log, "taken_back": taken_back, "stopped": stopped, "work": work,
            "cancelled_queries": cancelled,
            "defect_locations": layout.get("defect_locations", []), "why_red": red_text, "why_crease": crease_text,
            "surface": surface, "design": ds.design}
