"""`stripweave bench`: timings and sizes of every pipeline stage, as JSON.

Each stage is run `repeat` times; the JSON holds the median and the 95th
percentile of each stage's milliseconds, with the sizes the stage produced.
Later stages (graph, loops, strips, layout, refit) add their own sections.

symmetry (issue 21): symmetry_ms {median, p95, runs}, detection alone (bench_symmetry).

refit (issue 7): refit_s {median, p95, runs} is the surfacing stage alone (patch
network -> fitted B-spline patches -> sewn shell, no STEP file) on the bench's
strip design when its layout is valid, else on an auto-woven design (weave.auto_weave),
with refit_patches and a "refit" block (which design, deviation against the
tolerance, patches over creases, shell validity). Target: 10 s for 100 patches.

memory_mb {part: {"rss", "peak", "stage_peak"}}: resident memory after the surface, loops,
strips and refit parts, the peak so far and each part's own peak (memory.py, issue 22); the
loops part adds graph_mb (g') and workspace_mb (the search scratch space), the strips part
design_memory_mb (DesignState.memory_bytes: strips, field, parameterization, mask and the
state kept from before the last edit). With job=True (`bench --job`) "job" holds the main
job's memory (job_memory): `weave MODEL --auto --step` run in a child process with stage
peaks, and the resident memory of Python with the job's imports alone (the workbench and
the native library with OCCT: its baseline), and with FreeCAD's Part besides. `bench --scale` is bench_scale.py.
"""
import json
import subprocess
import sys
import tempfile
import os
import statistics
import time

import numpy as np

from .surface import load


def percentile(values, q):
    """The q-th percentile (0..100) by linear interpolation between order statistics."""
    s = sorted(values)
    if not s:
        return None
    pos = (len(s) - 1) * q / 100.0
    lo = int(pos)
    hi = min(lo + 1, len(s) - 1)
    return s[lo] + (s[hi] - s[lo]) * (pos - lo)


def summary(values):
    return {"median": statistics.median(values), "p95": percentile(values, 95), "runs": len(values)}


def bench_surface(path, repeat=3, **options):
    """Time the surface stage on a model file."""
    runs = []
    surface = None
    for _ in range(max(1, repeat)):
        surface = load(path, **options)
        runs.append(dict(surface.timings_ms))
    stages = {}
    for run in runs:
        for stage, ms in run.items():
            stages.setdefault(stage, []).append(ms)
    totals = [sum(run.values()) for run in runs]
    report = surface.report()
    return surface, {
        "model": os.path.basename(path),
        "input_triangles": surface.input_triangles,
        "triangles": report["triangles"],
        "vertices": report["vertices"],
        "brep_faces": report["brep_faces"],
        "feature_curves": report["feature_curves"],
        "surface_ms": {"total": summary(totals), **{k: summary(v) for k, v in stages.items()}},
    }


def random_surface_points(surface, count, seed=1):
    """Points spread over the surface by area (a fixed seed: runs are comparable)."""
    rng = np.random.default_rng(seed)
    v, t = surface.vertices, surface.triangles
    area = 0.5 * np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1)
    tri = rng.choice(len(t), size=count, p=area / area.sum())
    r1, r2 = rng.random(count), rng.random(count)
    s = np.sqrt(r1)
    w = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)
    return np.einsum("ij,ijk->ik", w, v[t[tri]])


def bench_loops(surface, hover_points=50, anchor_pairs=10, boundary="aligned"):
    """Graph build, hover (best loop over all directions) and two-anchor loops."""
    from ._native import native
    from .loops import LoopSession
    session = LoopSession(surface, boundary=boundary)
    result = dict(session.stats())
    # A query that finds no loop is timed all the same and counted.
    hover, hover_failed = [], 0
    for p in random_surface_points(surface, hover_points, seed=1):
        start = time.perf_counter()
        try:
            session.native.best_loop(list(p), True)
        except native.InputError:
            hover_failed += 1
        hover.append((time.perf_counter() - start) * 1000.0)
    result["hover_ms"] = {**summary(hover), "no_loop": hover_failed}
    if anchor_pairs < 1:
        return result
    pairs = random_surface_points(surface, 2 * anchor_pairs, seed=2).reshape(anchor_pairs, 2, 3)
    two, two_failed = [], 0
    for a, b in pairs:
        start = time.perf_counter()
        try:
            session.native.loops([list(a), list(b)], 1, True)
        except native.InputError:
            two_failed += 1
        two.append((time.perf_counter() - start) * 1000.0)
    result["two_anchor_ms"] = {**summary(two), "no_loop": two_failed}
    result["workspace_mb"] = round(session.native.workspace_bytes / 2**20, 1)
    return result


def bench_strips(surface, loop_session=None, strips=6, repeat=3, seed=3, sessions=None):
    """Cross field, parameterization and strip extraction for a design of several strips.

    The design is grown as a user would: at seeded random points, the best loop compatible
    with the strips so far (points where no compatible loop passes are skipped). The design
    is then re-derived `repeat` times; field_ms is the cross-field solve, param_ms the
    parameterization plus the extraction of every strip."""
    from ._native import native
    from .strips import DesignSession
    session = DesignSession(surface, loop_session=loop_session)
    if sessions is not None:
        sessions.append(session)
    tried = 0
    for p in random_surface_points(surface, 8 * strips, seed=seed):
        if len(session.design.strips) >= strips:
            break
        tried += 1
        try:
            session.add_strip([tuple(p)])
        except native.InputError:
            pass
    field, param, extraction, regions, layout = [], [], [], [], []
    steps = {}
    for _ in range(max(1, repeat)):
        session.native.set_strips(session.design.anchor_lists())
        t = session.timings_ms()
        for name, ms in session.native.parameterization_timings_ms.items():
            steps.setdefault(name, []).append(ms)
        field.append(t["field"])
        param.append(t["parameterization"] + t["extraction"])
        extraction.append(t["extraction"])
        raw = session.native.layout()
        regions.append(raw["time_ms"])
        layout.append(raw["layout_ms"])
    result = session.strips_json()
    return {
        "design_memory_mb": {k: round(v / 2**20, 2) for k, v in session.native.memory_bytes.items()},
        "design_strips": len(session.design.strips),
        "design_points_tried": tried,
        "singularities": len(result["singularities"]),
        "index_sum": result["index_sum"],
        "euler_characteristic": result["euler_characteristic"],
        "fold_overs": result["fold_overs"],
        "strip_area_fraction": [round(s["area_fraction"], 4) for s in result["strips"]],
        "field_ms": summary(field),
        "param_ms": summary(param),
        "extraction_ms": summary(extraction),
        # Where the parameterization's time goes (medians): cut and comb, energy and
        # constraints, elimination order, KKT system, factorization, solve, output.
        "param_steps_ms": {name: round(statistics.median(ms), 2) for name, ms in steps.items()},
        # The arrangement and regions of the design's loops, and primalization (only for a
        # valid design: otherwise layout_ms times the check alone).
        "design_valid": bool(raw["valid"]),
        "patches": raw["summary"]["patches"],
        "regions_ms": summary(regions),
        "layout_ms": summary(layout),
    }


def bench_refit(session, repeat=3):
    """The surfacing stage on the session's layout, else on an auto-woven design.

    Returns refit_s (seconds: median, p95, runs), refit_patches and a "refit" block; refit_s
    is None when neither design has a valid layout."""
    from ._native import native
    from .strips import DesignSession
    from .surfacing import refit_design
    from .weave import WeaveOptions, auto_weave
    which = "bench"
    if not session.native.patch_network()["patches"]:
        which = "auto"
        session = DesignSession(session.surface)
        auto_weave(session, WeaveOptions())
    runs, result = [], None
    for _ in range(max(1, repeat)):
        start = time.perf_counter()
        try:
            result = refit_design(session)
        except native.InputError as e:
            return {"refit_s": None, "refit_patches": 0, "refit": {"design": which, "error": str(e)}}
        runs.append(time.perf_counter() - start)
    return {
        "refit_s": summary(runs),
        "refit_patches": len(result["per_patch"]),
        "refit": {
            "design": which,
            "strips": len(session.design.strips),
            "max_deviation": result["max_deviation"],
            "tolerance": result["tolerance"],
            "tolerance_met": result["tolerance_met"],
            "creased_patches": result["creased_patches"],
            "tolerance_met_uncreased": result["tolerance_met_uncreased"],
            "max_seam_gap": result["max_seam_gap"],
            "max_seam_angle_deg_regular": result["max_seam_angle_deg_regular"],
            "valid_shell": result["valid_shell"],
            "timings_ms": result["timings_ms"],
        },
    }


def bench_symmetry(surface, repeat=3):
    """Symmetry detection (symmetry.detect, paper §5.8): symmetry_ms {median, p95, runs} and
    what it found (kind, order, max error in diagonals)."""
    from .symmetry import detect
    runs, found = [], []
    for _ in range(max(1, repeat)):
        start = time.perf_counter()
        found = detect(surface)
        runs.append((time.perf_counter() - start) * 1000.0)
    return {"symmetry_ms": summary(runs),
            "symmetries": [{"kind": s["kind"], "order": s.get("order", 2),
                            "max_error": s["max_error"] / surface.bbox_diagonal} for s in found]}


# What the main job imports before it loads a model (the native library brings OCCT and CGAL):
# the baseline of its memory; and the same with FreeCAD's Part, which the job needs only for
# a model given as a FreeCAD shape.
_IMPORTS = "from stripweave import cli, job, preview, surfacing; from stripweave._native import native"
_FREECAD = "import FreeCAD, Part; " + _IMPORTS


def _imports_mb(code, env, timeout_s):
    """The resident memory of a Python that ran `code` alone (MB), None if it failed."""
    p = subprocess.run([sys.executable, "-c", code + "; from stripweave.memory import resident_memory_mb; "
                        "print(resident_memory_mb())"], capture_output=True, text=True, env=env, timeout=timeout_s)
    return float(p.stdout.split()[-1]) if p.returncode == 0 and p.stdout.split() else None


def job_memory(path, target_triangles=None, timeout_s=1800):
    """The main job's memory, MB: `weave MODEL --auto --step` in a child process with stage
    peaks (memory.py): {"stages": report.json's memory_mb, "peak": its peak, "imports": the
    resident memory of a Python that imported what the job imports (the workbench and the
    native library with OCCT) alone, "freecad_imports": the same with FreeCAD's Part}. An
    error in the job gives {"error": its last line}."""
    from .memory import STAGE_PEAKS_ENV
    env = {**os.environ, STAGE_PEAKS_ENV: "1"}
    imports = {"imports": _imports_mb(_IMPORTS, env, timeout_s), "freecad_imports": _imports_mb(_FREECAD, env, timeout_s)}
    with tempfile.TemporaryDirectory() as out:
        argv = [sys.executable, "-m", "stripweave.cli", "weave", os.fspath(path), "--auto", "--step", "--out", out]
        if target_triangles is not None:
            argv += ["--target-triangles", str(target_triangles)]
        p = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=timeout_s)
        try:
            with open(os.path.join(out, "report.json")) as f:
                report = json.load(f)
        except (OSError, ValueError):
            lines = (p.stderr or p.stdout).strip().splitlines()
            return {**imports, "error": lines[-1] if lines else f"exit status {p.returncode}"}
    return {**imports, "peak": report["peak_memory_mb"], "stages": report["memory_mb"]}


def run_bench(path, repeat=3, loops=True, strips=True, refit=True, job=False, **options):
    """Every stage's figures; memory_mb gives the resident memory after each part, the peak so
    far and the part's own peak (MB), so what each part holds shows as the step between two
    entries' rss, and what it needs while it runs as the step to its stage_peak."""
    from .memory import StageMemory
    meter = StageMemory(stage_peaks=True)
    memory = meter.stages

    def note(part):
        meter.note(part)

    surface, result = bench_surface(path, repeat=repeat, **options)
    note("surface")
    result.update(bench_symmetry(surface, repeat=repeat))
    if loops:
        result.update(bench_loops(surface))
        note("loops")
        if strips:
            sessions = []
            result.update(bench_strips(surface, repeat=repeat, sessions=sessions))
            note("strips")
            if refit:
                result.update(bench_refit(sessions[0], repeat=repeat))
                note("refit")
    result["memory_mb"] = memory
    if job:
        result["job"] = job_memory(path, target_triangles=options.get("target_triangles"))
    return result
