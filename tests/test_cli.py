"""The `stripweave` launcher and its JSON contracts (design.md)."""
import json
import math
import os
import re
import subprocess

import numpy as np
import pytest

from models import box, torus, winding_numbers

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAUNCHER = os.path.join(os.environ.get("STRIPWEAVE_BUILD", os.path.join(REPO, "build")), "stripweave")
INFO_KEYS = {"vertices", "triangles", "components", "genus", "boundary_loops", "feature_curves", "feature_edges",
             "brep_faces", "bbox_diagonal"}


def run(*args):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # the launcher sets its own
    return subprocess.run([LAUNCHER, *args], capture_output=True, text=True, env=env, timeout=300)


@pytest.fixture(scope="module")
def torus_step(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("models") / "torus.step")
    torus(10, 3).exportStep(path)
    return path


def test_info_json_has_the_contract_keys(torus_step):
    p = run("info", torus_step, "--json", "--target-triangles", "5000")
    assert p.returncode == 0, p.stderr
    info = json.loads(p.stdout)
    assert INFO_KEYS <= set(info)
    assert info["genus"] == 1 and info["feature_curves"] == 0 and info["brep_faces"] == 1
    assert info["bbox_diagonal"] == pytest.approx((26 ** 2 * 2 + 6 ** 2) ** 0.5, rel=1e-3)


def test_info_text(tmp_path):
    path = str(tmp_path / "box.brep")
    box(10).exportBrep(path)
    p = run("info", path, "--target-triangles", "2000")
    assert p.returncode == 0, p.stderr
    assert "12 curve(s)" in p.stdout and "genus 0" in p.stdout


def test_info_on_a_mesh_file_and_an_fcstd(tmp_path):
    import FreeCAD
    import Mesh
    mesh_path = str(tmp_path / "box.stl")
    Mesh.Mesh(box(10).tessellate(0.01)).write(mesh_path)
    p = run("info", mesh_path, "--json", "--target-triangles", "3000")
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["feature_curves"] == 12

    doc = FreeCAD.newDocument("clitest")
    doc.addObject("Part::Box", "Box")
    doc.recompute()
    fcstd = str(tmp_path / "box.FCStd")
    doc.saveAs(fcstd)
    FreeCAD.closeDocument(doc.Name)
    p = run("info", fcstd, "--json", "--target-triangles", "2000")
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["brep_faces"] == 6


def test_bad_input_gives_one_line_error_and_nonzero_exit(tmp_path):
    bad = tmp_path / "bad.step"
    bad.write_text("not a step file\n")
    p = run("info", str(bad))
    assert p.returncode != 0
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "not a valid STEP file" in lines[0]
    p = run("info", str(tmp_path / "nothing.obj"))
    assert p.returncode != 0 and "does not exist" in p.stderr


def test_bench_json(torus_step):
    p = run("bench", torus_step, "--repeat", "2", "--target-triangles", "5000", "--job")
    assert p.returncode == 0, p.stderr
    bench = json.loads(p.stdout)
    assert bench["triangles"] > 3000 and bench["input_triangles"] > 0
    stages = bench["surface_ms"]
    for stage in ("read", "tessellate", "remesh", "curvature", "total"):
        assert stages[stage]["median"] >= 0 and stages[stage]["p95"] >= stages[stage]["median"]
        assert stages[stage]["runs"] == 2
    # The surfacing stage (issue 7): the refit of the bench design, or of an auto-woven one.
    assert bench["refit_patches"] > 0
    assert 0 < bench["refit_s"]["median"] <= bench["refit_s"]["p95"] and bench["refit_s"]["runs"] == 2
    assert bench["refit"]["design"] in ("bench", "auto") and bench["refit"]["valid_shell"]
    # What each part holds (issue 22): resident memory after it and the peak so far.
    assert list(bench["memory_mb"]) == ["surface", "loops", "strips", "refit"]
    assert all(0 < m["rss"] <= m["stage_peak"] <= m["peak"] for m in bench["memory_mb"].values())
    assert bench["graph_mb"] > 0 and bench["workspace_mb"] > 0
    assert set(bench["design_memory_mb"]) == {"strips", "field", "parameterization", "mask", "previous"}
    # The main job's parts, in a child process: each stage's rss and own peak, the job's peak
    # (the largest stage peak) and the imports' baseline below all of them.
    job = bench["job"]
    assert list(job["stages"])[:5] == ["surface", "symmetry", "graph", "design", "weave"]
    assert job["peak"] >= max(m["stage_peak"] for m in job["stages"].values())
    assert 0 < job["imports"] < min(m["rss"] for m in job["stages"].values())
    assert job["freecad_imports"] > job["imports"]


def test_loop_json_contract(torus_step):
    p = run("loop", torus_step, "--anchor", "13,0,0,0,0,1", "--json", "--target-triangles", "8000")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert out["time_ms"] >= 0
    (loop,) = out["loops"]
    assert {"cost", "length", "closed", "points", "max_turn_deg"} <= set(loop)
    assert loop["closed"] and loop["length"] == pytest.approx(2 * math.pi * 3, rel=0.02)
    # The points are the meridian through the anchor, in model units: on the torus (3 from
    # its core circle), in the plane y = 0 of the anchor's direction, as long as reported.
    p = np.asarray(loop["points"])
    assert p.shape[1] == 3 and np.allclose(p[0], p[-1])
    assert np.abs(np.hypot(np.hypot(p[:, 0], p[:, 1]) - 10, p[:, 2]) - 3).max() < 0.03  # a mesh chord sags 0.02
    assert np.abs(p[:, 1]).max() < 0.3
    assert np.linalg.norm(np.diff(p, axis=0), axis=1).sum() == pytest.approx(loop["length"], rel=1e-9)
    assert np.linalg.norm(p - (13, 0, 0), axis=1).min() < 0.5
    assert winding_numbers(p) in {(0, 1), (0, -1)}
    assert 0 <= loop["max_turn_deg"] <= 30  # the default turn limit


@pytest.fixture(scope="module")
def fat_torus_step(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("models") / "fat-torus.step")
    torus(10, 4).exportStep(path)
    return path


TEXT_LOOP = re.compile(r"^(\d+)\. loop: length (\S+), cost (\S+) \(", re.M)


def test_loop_alternatives_and_text(fat_torus_step):
    """Three alternatives at a point of the inner equator of a torus (R 10, r 4): the meridian
    (2 pi 4), the inner equator (2 pi 6) and a loop winding twice around the tube: three
    homotopy classes, cheapest first, each through the anchor; the text lists the same three."""
    anchor = (6, 0, 0)
    args = ("loop", fat_torus_step, "--anchor", "6,0,0", "--alternatives", "3", "--target-triangles", "8000")
    p = run(*args, "--json")
    assert p.returncode == 0, p.stderr
    loops = json.loads(p.stdout)["loops"]
    assert len(loops) == 3
    costs = [l["cost"] for l in loops]
    assert costs == sorted(costs) and len(set(costs)) == 3
    classes = [tuple(map(abs, winding_numbers(l["points"]))) for l in loops]
    assert classes == [(0, 1), (1, 0), (0, 2)]
    assert loops[0]["length"] == pytest.approx(2 * math.pi * 4, rel=0.02)
    assert loops[1]["length"] == pytest.approx(2 * math.pi * 6, rel=0.02)
    for loop in loops:
        points = np.asarray(loop["points"])
        assert loop["closed"] and np.allclose(points[0], points[-1])
        step = np.linalg.norm(np.diff(points, axis=0), axis=1).mean()
        assert np.linalg.norm(points - anchor, axis=1).min() < step  # through the anchor's vertex

    p = run(*args)
    assert p.returncode == 0, p.stderr
    listed = TEXT_LOOP.findall(p.stdout)
    assert [int(n) for n, _, _ in listed] == [1, 2, 3]
    assert [float(length) for _, length, _ in listed] == pytest.approx([l["length"] for l in loops], rel=1e-5)
    assert [float(cost) for _, _, cost in listed] == pytest.approx(costs, rel=1e-3)
    assert "search took" in p.stdout


def test_loop_bad_anchor(torus_step):
    p = run("loop", torus_step, "--anchor", "40,0,0", "--target-triangles", "4000")
    assert p.returncode != 0 and "off the part" in p.stderr
    p = run("loop", torus_step, "--anchor", "13,0", "--target-triangles", "4000")
    assert p.returncode != 0 and "X,Y,Z" in p.stderr


def test_weave_crease_pairs_flag_reaches_the_weave(tmp_path):
    """`--crease-pairs` (off by default) gives a square pocket's rim the pair of crossing loops no
    single loop replaces: with it the layout is crease-conforming and design.json says which
    strips came as a pair; without it a crease region is left (weave._crease_pair)."""
    import FreeCAD  # noqa: F401  (before Part)
    import Part
    path = str(tmp_path / "pocket.step")
    Part.makeBox(40, 40, 8).cut(Part.makeBox(14, 14, 4, FreeCAD.Vector(13, 13, 4))).removeSplitter().exportStep(path)
    reports = {}
    for flag in ([], ["--crease-pairs"]):
        out = str(tmp_path / ("pairs" if flag else "single"))
        r = run("weave", path, "--auto", "--target-triangles", "15000", "--out", out, "--json", *flag)
        assert r.returncode == 0, r.stderr
        design = json.load(open(os.path.join(out, "design.json")))
        reasons = [s.get("added_by", {}).get("reason") for s in design["strips"]]
        reports[bool(flag)] = (json.loads(r.stdout.strip().splitlines()[-1]), reasons)
    (single, single_reasons), (pairs, pair_reasons) = reports[False], reports[True]
    assert "crease region (a pair)" not in single_reasons and not single["crease_conforming"]
    assert pair_reasons.count("crease region (a pair)") == 2
    assert pairs["crease_conforming"] and pairs["clean"]
