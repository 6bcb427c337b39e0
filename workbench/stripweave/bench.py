"""`stripweave bench`: timings and sizes of every pipeline stage, as JSON.

Each stage is run `repeat` times; the JSON holds the median and the 95th
percentile of each stage's milliseconds, with the sizes the stage produced.
Later stages (graph, loops, strips, layout, refit) add their own sections.
"""
import os
import statistics

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


def run_bench(path, repeat=3, **options):
    _, result = bench_surface(path, repeat=repeat, **options)
    return result
