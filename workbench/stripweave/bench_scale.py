"""`stripweave bench --scale`: large inputs against the physical limit (issue 22), as JSON.

    run_scale(sizes=(100_000, 1_000_000, 5_000_000), folder=None) -> dict

One shape (a torus with gentle bumps, generated with numpy), subdivided to about each
size in triangles and written as a binary STL in a temporary folder. Per size, each part
runs in a fresh process, so its peak memory is its own:
    floor_s      reading the same file with numpy alone: np.fromfile of the STL records and
                 np.unique welding of their corners (the physical floor of a load)
    load_s       read + weld + sanitize (the surface stage's "read" and "sanitize")
    load_ratio   load_s / floor_s
    proxy_s      building the solver surface from the clean mesh at the default target
                 (features, simplification and remeshing, curvature)
    hover_ms     best loop through 50 random points of the proxy (median, p95)
    graph_s      the elastica graph on the proxy
    weave_s      `weave --auto` end to end (load, proxy, graph, weaving, layout; no files)
    peak_mb      peak resident memory of the load-and-hover process and of the weave's
and the triangle counts of the input and the proxy.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

STL_RECORD = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])


def torus_grid(triangles):
    """(vertices, triangles) of a bumpy torus with about `triangles` triangles: a grid of
    n x m quads (n = 2.5 m, the ratio of its circles), each split in two."""
    m = max(3, int(round(np.sqrt(triangles / 5.0))))
    n = max(3, int(round(triangles / (2.0 * m))))
    u = np.linspace(0, 2 * np.pi, n, endpoint=False)[:, None]
    v = np.linspace(0, 2 * np.pi, m, endpoint=False)[None, :]
    r = 1.0 + 0.06 * np.sin(5 * u) * np.sin(3 * v)   # bumps the layout should see
    x = (2.5 + r * np.cos(v)) * np.cos(u)
    y = (2.5 + r * np.cos(v)) * np.sin(u)
    z = r * np.sin(v) + 0.0 * u
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    a = i * m + j
    b = ((i + 1) % n) * m + j
    c = ((i + 1) % n) * m + (j + 1) % m
    d = i * m + (j + 1) % m
    tris = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, tris


def write_binary_stl(path, vertices, triangles):
    """A binary STL of the mesh (float32 corners, as every STL holds)."""
    records = np.zeros(len(triangles), dtype=STL_RECORD)
    corners = vertices[triangles].astype(np.float32)
    n = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    records["normal"] = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    records["corners"] = corners
    with open(path, "wb") as f:
        f.write(b"stripweave bench --scale".ljust(80, b" "))
        f.write(np.uint32(len(triangles)).tobytes())
        records.tofile(f)


def numpy_floor(path):
    """Seconds to read the STL's records with numpy and weld their corners (np.unique)."""
    start = time.perf_counter()
    with open(path, "rb") as f:
        f.seek(84)
        records = np.fromfile(f, dtype=STL_RECORD)
    corners = records["corners"].reshape(-1, 3)
    _, inverse = np.unique(corners, axis=0, return_inverse=True)
    triangles = inverse.reshape(-1, 3)
    assert len(triangles) == len(records)
    return time.perf_counter() - start


def _peak_mb():
    import resource
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1)


def measure_load(path, hover_points=50):
    """In this process: the floor, the load and proxy of the surface stage, hover on the proxy."""
    from .bench import bench_loops
    from .surface import load
    floor = numpy_floor(path)
    start = time.perf_counter()
    surface = load(path)
    total = time.perf_counter() - start
    t = {k: v / 1000.0 for k, v in surface.timings_ms.items()}
    load_s = t.get("read", 0.0) + t.get("sanitize", 0.0)
    result = {"input_triangles": int(surface.input_triangles), "proxy_triangles": len(surface.triangles),
              "floor_s": round(floor, 3), "load_s": round(load_s, 3), "load_ratio": round(load_s / floor, 2),
              "proxy_s": round(total - load_s, 3), "surface_stages_s": {k: round(v, 3) for k, v in t.items()}}
    loops = bench_loops(surface, hover_points=hover_points, anchor_pairs=0)
    result["graph_s"] = round(loops["graph_build_s"], 3)
    result["hover_ms"] = {k: (round(v, 2) if isinstance(v, float) else v) for k, v in loops["hover_ms"].items()}
    result["graph_mb"] = round(loops["graph_mb"], 1)
    result["load_peak_mb"] = _peak_mb()
    return result


def measure_weave(path):
    """In this process: `weave --auto` end to end, without files."""
    from .job import weave
    start = time.perf_counter()
    report = weave(path, auto=True, out=None)
    return {"weave_s": round(time.perf_counter() - start, 2), "weave_valid": bool(report["valid"]),
            "weave_patches": int(report["patches"]), "weave_strips": int(report["strips"]),
            "weave_peak_mb": _peak_mb()}


def _child(kind, path, timeout):
    """Run measure_<kind>(path) in a fresh interpreter; its JSON, or an "error"."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    code = (f"import json, stripweave.bench_scale as b\n"
            f"print('@@' + json.dumps(b.measure_{kind}({path!r})))\n")
    try:
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {f"{kind}_error": f"over {timeout} s"}
    for line in r.stdout.splitlines():
        if line.startswith("@@"):
            return json.loads(line[2:])
    return {f"{kind}_error": (r.stderr.strip().splitlines() or ["exit %d" % r.returncode])[-1]}


def run_scale(sizes=(100_000, 1_000_000, 5_000_000), folder=None, weave=True, timeout=1800):
    """The scale benchmark (module doc); `folder` keeps the generated STL files."""
    results = []
    with tempfile.TemporaryDirectory(prefix="stripweave-scale-") as tmp:
        where = folder or tmp
        os.makedirs(where, exist_ok=True)
        for size in sizes:
            path = os.path.join(where, f"torus-{size}.stl")
            vertices, triangles = torus_grid(size)
            write_binary_stl(path, vertices, triangles)
            del vertices, triangles
            entry = {"requested": size, "file_mb": round(os.path.getsize(path) / 2**20, 1)}
            entry.update(_child("load", path, timeout))
            if weave:
                entry.update(_child("weave", path, timeout))
            results.append(entry)
            if folder is None:
                os.remove(path)
    return {"shape": "bumpy torus, binary STL", "scale": results}
