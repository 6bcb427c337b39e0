"""`stripweave batch` (issue 16): one process per model, statuses, summaries, the Dask path,
and the contact sheet as Chromium renders it. Generated models only, at 3000 triangles."""
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import psutil
import pytest

from models import box, torus

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAUNCHER = os.path.join(os.environ.get("STRIPWEAVE_BUILD", os.path.join(REPO, "build")), "stripweave")
SMALL = ["--target-triangles", "3000"]
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}   # the launcher sets its own


def run(*args):
    return subprocess.run([LAUNCHER, *args], capture_output=True, text=True, env=ENV, timeout=600)


def write_obj(shape, path, deflection):
    """A shape's tessellation as an OBJ mesh; returns its triangle count."""
    points, triangles = shape.tessellate(deflection)
    with open(path, "w", encoding="utf-8") as f:
        f.writelines(f"v {p.x} {p.y} {p.z}\n" for p in points)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles)
    return len(triangles)


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    """A folder as a user would have one: a STEP box, a torus mesh in a subfolder (suffix in
    capitals), a broken STL, and a MANIFEST.md that is no model."""
    root = tmp_path_factory.mktemp("corpus")
    os.makedirs(root / "meshes")
    box(10).exportStep(str(root / "box.step"))
    torus_triangles = write_obj(torus(10, 3), str(root / "meshes" / "torus.OBJ"), 0.3)
    (root / "broken.stl").write_text("solid broken\nthis is not an STL\nendsolid\n")
    (root / "MANIFEST.md").write_text("# not a model\n")
    return {"root": str(root), "torus_triangles": torus_triangles}


@pytest.fixture(scope="module")
def batch(corpus, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("batch") / "out")
    p = run("batch", corpus["root"], "--out", out, "--step", "--jobs", "2", *SMALL)
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
        summary = json.load(f)
    by_name = {os.path.basename(e["model"]): e for e in summary["models"]}
    return {"process": p, "out": out, "summary": summary, "by_name": by_name}


def test_finds_models_recursively_and_names_their_folders_uniquely(tmp_path):
    from stripweave.batch import find_models, output_names
    for folder in ("a", "b", "a/deep"):
        os.makedirs(tmp_path / folder, exist_ok=True)
    for name in ("a/torus.obj", "b/torus.obj", "a/deep/part.STEP", "a/part.stl", "b/README.md", "b/notes.txt"):
        (tmp_path / name).write_text("x")
    models = find_models([str(tmp_path), str(tmp_path / "a" / "torus.obj")])   # listed twice: once
    assert sorted(os.path.relpath(m, tmp_path) for m in models) == ["a/deep/part.STEP", "a/part.stl",
                                                                   "a/torus.obj", "b/torus.obj"]
    names = dict(zip((os.path.relpath(m, tmp_path) for m in models), output_names(models)))
    assert names == {"a/deep/part.STEP": "part_STEP", "a/part.stl": "part_stl", "a/torus.obj": "a_torus_obj",
                     "b/torus.obj": "b_torus_obj"}
    assert output_names(["x/box.step", "x/torus.obj"]) == ["box", "torus"]


def test_a_broken_model_is_recorded_and_the_others_finish(batch, corpus):
    p, summary, by_name = batch["process"], batch["summary"], batch["by_name"]
    assert p.returncode == 0, p.stderr
    assert summary["format"] == "stripweave-batch" and summary["version"] == 1
    assert set(by_name) == {"box.step", "torus.OBJ", "broken.stl"}      # MANIFEST.md is no model
    for entry in summary["models"]:
        assert set(entry) >= {"model", "status", "error", "time_s", "peak_memory_mb", "report"}
    broken = by_name["broken.stl"]
    assert broken["status"] == "error" and broken["report"] is None
    assert "broken.stl" in broken["error"] and "\n" not in broken["error"]
    for name in ("box.step", "torus.OBJ"):
        entry = by_name[name]
        assert entry["status"] == "ok" and entry["error"] is None, entry["error"]
        report = entry["report"]
        assert report["patches"] > 0 and report["valid"] is True
        assert "fit" in report                                                # --step passed through
        assert 1500 < report["solver_triangles"] < 6000                       # --target-triangles passed through
        # the batch watches the whole process, so it sees at least the weave's own peak
        assert entry["peak_memory_mb"] >= 0.99 * report["peak_memory_mb"] > 0
        assert os.path.isfile(os.path.join(batch["out"], entry["out"], "preview.png"))
        with open(os.path.join(batch["out"], entry["out"], "weave.json"), encoding="utf-8") as f:
            printed = json.load(f)                                             # weave --json's output
        assert printed["patches"] == report["patches"] and "stopped" in printed
    assert by_name["torus.OBJ"]["report"]["input_triangles"] == corpus["torus_triangles"]
    assert by_name["box.step"]["report"]["input_triangles"] == 12            # 6 planar faces, 2 triangles each
    progress = [line for line in p.stderr.splitlines() if re.match(r"\[\d/3\] ", line)]
    assert len(progress) == 3 and any("ERROR" in line and "broken.stl" in line for line in progress)


def test_corner_deviation_p95_is_the_layouts_percentile(batch):
    entry = batch["by_name"]["box.step"]
    with open(os.path.join(batch["out"], entry["out"], "layout.json"), encoding="utf-8") as f:
        layout = json.load(f)
    deviations = [abs(a - 90.0) for p in layout["patches"] for a in p["corner_angles_deg"]]
    d = entry["report"]["corner_deviation_deg"]
    assert d["p95"] == pytest.approx(np.percentile(deviations, 95), abs=1e-9)
    assert d["mean"] - 1e-9 <= d["max"] and d["p95"] <= d["max"] + 1e-9
    # The figures say what they leave out: the patches that are no quad.
    quads = [p for p in layout["patches"] if p["quad"]]
    assert d["quads"] == len(quads) and d["patches"] == len(layout["patches"])
    all_corners = deviations + [90.0] * (4 * (len(layout["patches"]) - len(quads)))
    assert d["mean_all_patches"] == pytest.approx(np.mean(all_corners), abs=1e-9)


def test_patches_that_are_no_quad_do_not_flatter_the_corner_figures():
    """Two quads with perfect corners and two broken patches: the quads' mean is 0, but the
    report says 2 of 4 patches are quads, and the mean over all patches (each broken one as
    four corners 90 degrees off) is 45; the batch row shows both."""
    from stripweave.batch_report import COLUMNS, cells
    from stripweave.job import _corner_coverage
    square = {"quad": True, "corner_angles_deg": [90.0] * 4}
    broken = {"quad": False, "corner_angles_deg": []}
    cover = _corner_coverage({"patches": [square, square, broken, broken]})
    assert cover == {"quads": 2, "patches": 4, "mean_all_patches": pytest.approx(45.0)}
    assert _corner_coverage({"patches": []}) == {"quads": 0, "patches": 0, "mean_all_patches": 0.0}
    entry = {"model": "m.step", "status": "ok", "error": None, "time_s": 1.0, "peak_memory_mb": 100.0,
             "report": {"valid": True, "strips": 2, "patches": 4, "irregular_vertices": {},
                        "corner_deviation_deg": {"mean": 0.0, "max": 0.0, "p95": 0.0, **cover}}}
    row = dict(zip(COLUMNS, cells(entry)))
    assert row["corner dev. mean / p95 deg"] == "0.0 / 0.0 (2 no quad: all 45.0)"


def test_summary_md_has_a_row_per_model_and_totals(batch):
    from stripweave.batch_report import COLUMNS
    with open(os.path.join(batch["out"], "summary.md"), encoding="utf-8") as f:
        text = f.read()
    rows = [line for line in text.splitlines() if line.startswith("| ")]
    header, body = rows[0], rows[2:]
    assert [c.strip() for c in header.strip("|").split(" | ")] == list(COLUMNS)
    assert len(body) == 3
    cells = {os.path.basename(r.split(" | ")[0][2:]): [c.strip() for c in r.strip("|").split(" | ")] for r in body}
    assert all(len(c) == len(COLUMNS) for c in cells.values())
    box_report = batch["by_name"]["box.step"]["report"]
    assert cells["box.step"][COLUMNS.index("solver triangles")] == str(box_report["solver_triangles"])
    assert cells["box.step"][COLUMNS.index("patches")] == str(box_report["patches"])
    assert cells["box.step"][COLUMNS.index("status")] == "ok"
    assert cells["broken.stl"][COLUMNS.index("status")].startswith("error: ")
    assert cells["broken.stl"][COLUMNS.index("valid")] == "n/a"
    assert "3 models: 2 ok, 1 error, 0 timeout, 0 crash; 2 valid" in text


def test_an_older_report_shows_na_not_a_flattering_number():
    """A fit without the two-sided keys had a one-sided max_deviation: it must not pass as
    the fit's maximum."""
    from stripweave.batch_report import COLUMNS, cells
    entry = {"model": "old.step", "status": "ok", "error": None, "time_s": 1.0, "peak_memory_mb": 100.0,
             "report": {"valid": True, "strips": 3, "patches": 6, "irregular_vertices": {"3": 8},
                        "corner_deviation_deg": {"mean": 1.0, "max": 2.0},
                        "fit": {"max_deviation": 0.001, "rms_deviation": 0.0005}}}
    row = dict(zip(COLUMNS, cells(entry)))
    assert row["fit max / tolerance"] == "n/a / n/a" and row["coverage"] == "n/a"
    assert row["clean"] == "n/a" and row["defects"] == "n/a" and row["input triangles"] == "n/a"
    assert row["corner dev. mean / p95 deg"] == "1.0 / n/a"


def test_a_partial_fit_shows_its_whole_part_figures_marked_partial():
    """A run that failed with a region red on one component still fitted the others: the row
    shows that fit's figures (coverage of the whole part, the set-aside component uncovered),
    marked partial; a failed fit without them stays n/a."""
    from stripweave.batch_report import COLUMNS, cells
    fit = {"max_deviation_source_to_patches": 43.0, "max_deviation_patches_to_source": 1e-9,
           "tolerance": 0.06, "tolerance_met": False, "coverage": 0.336, "set_aside_components": [0],
           "error": "the layout is not valid: ..."}
    entry = {"model": "pair.step", "status": "error", "error": "the layout is not valid: ...", "time_s": 1.0,
             "peak_memory_mb": 100.0, "report": {"valid": False, "fit": fit}}
    row = dict(zip(COLUMNS, cells(entry)))
    assert row["fit max / tolerance"] == "43 / 0.06 not met (partial: components 0 set aside)"
    assert row["coverage"] == "33.6%"
    del fit["set_aside_components"]
    row = dict(zip(COLUMNS, cells(entry)))
    assert row["fit max / tolerance"] == "n/a" and row["coverage"] == "n/a"


def test_index_html_links_every_picture(batch):
    with open(os.path.join(batch["out"], "index.html"), encoding="utf-8") as f:
        page = f.read()
    for name in ("box.step", "torus.OBJ"):
        folder = batch["by_name"][name]["out"]
        for picture in ("preview.png", "deviation.png"):
            assert f'src="{folder}/{picture}"' in page                     # relative to OUT
            assert os.path.isfile(os.path.join(batch["out"], folder, picture))
    assert page.count('class="card failed"') == 1


def _screenshot(page, png):
    p = subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", f"--screenshot={png}",
                        "--window-size=1280,900", "--hide-scrollbars", f"file://{page}"],
                       capture_output=True, text=True, timeout=180)
    assert os.path.isfile(png), p.stderr
    from PIL import Image
    return np.asarray(Image.open(png).convert("RGB"), dtype=float)


def test_index_html_renders_in_chromium(batch):
    """The contact sheet is not blank, and its pictures show: the same page with the
    images' links broken has far less ink."""
    page = os.path.join(batch["out"], "index.html")
    with open(page, encoding="utf-8") as f:
        html = f.read()
    blind = os.path.join(batch["out"], "index_without_pictures.html")
    with open(blind, "w", encoding="utf-8") as f:
        f.write(html.replace('src="', 'src="missing-'))
    shot = _screenshot(page, os.path.join(batch["out"], "index.png"))
    without = _screenshot(blind, os.path.join(batch["out"], "index_without_pictures.png"))
    assert shot.shape[:2] == (900, 1280)
    assert shot.std() > 20.0                                              # not blank

    def ink(image):   # the share of pixels that are not near white
        return float(np.mean(image.min(axis=2) < 200))

    def coloured(image):   # ... and of those in colour (the shaded models; text is grey)
        return float(np.mean(image.max(axis=2) - image.min(axis=2) > 40))
    # four pictures of about 186 x 140 pixels, a third to a half of each the model
    assert ink(shot) > ink(without) + 0.02
    # The previews are mostly grey (dimmed stripes, shaded base), so colour is compared as a ratio:
    # the shaded models at least half as much colour again as the page's own red and green text.
    assert coloured(shot) > 1.5 * coloured(without)


WRAPPER = """#!/bin/sh
# A launcher for the tests: models named crash_* die by SIGSEGV, slow_* sleep in a tree of
# processes; the others run the real launcher.
case "$(basename "$2")" in
  crash_*) kill -SEGV $$ ;;
  slow_*) sleep 297 & sleep 297 ; exit 0 ;;
esac
exec {launcher} "$@"
"""


@pytest.fixture(scope="module")
def wrapper(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("wrapper") / "launcher.sh")
    with open(path, "w", encoding="utf-8") as f:
        f.write(WRAPPER.format(launcher=LAUNCHER))
    os.chmod(path, 0o755)
    return [path], ENV


def test_timeouts_and_crashes_are_recorded_and_the_batch_goes_on(corpus, wrapper, tmp_path):
    from stripweave.batch import run_batch
    for name in ("slow_part.stl", "crash_part.stl"):
        (tmp_path / name).write_text("solid x\nendsolid\n")
    torus_path = os.path.join(corpus["root"], "meshes", "torus.OBJ")
    out = str(tmp_path / "out")
    models = [torus_path, str(tmp_path / "slow_part.stl"), str(tmp_path / "crash_part.stl")]
    summary = run_batch(models, out, time_limit_s=0.5, weave_args=SMALL, command=wrapper, progress=None)
    status = {os.path.basename(e["model"]): (e["status"], e["error"]) for e in summary["models"]}
    assert status == {"torus.OBJ": ("timeout", "time limit of 0.5 s exceeded"),
                      "slow_part.stl": ("timeout", "time limit of 0.5 s exceeded"),
                      "crash_part.stl": ("crash", "killed by SIGSEGV")}
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
        assert json.load(f) == json.loads(json.dumps(summary))           # the file is the whole batch
    # the timeout killed the whole process group, not only its leader
    left = [p for p in psutil.process_iter(["cmdline"]) if (p.info["cmdline"] or [])[-1:] == ["297"]]
    assert not left


KILLED_BATCH = """
import sys
sys.path[:0] = {path!r}
from stripweave.batch import run_batch
run_batch({models!r}, {out!r}, weave_args={small!r}, command=({command!r}, {env!r}), progress=None)
"""


def test_a_killed_batch_leaves_what_it_had_and_no_jobs(corpus, wrapper, tmp_path):
    """summary.json is rewritten after every model; SIGTERM stops the batch and kills its
    running job (in a process group of its own, the signal would not reach it)."""
    (tmp_path / "slow_part.stl").write_text("solid x\nendsolid\n")
    out = str(tmp_path / "out")
    models = [os.path.join(corpus["root"], "box.step"), str(tmp_path / "slow_part.stl")]
    script = KILLED_BATCH.format(path=sys.path, models=models, out=out, small=SMALL, command=wrapper[0],
                                 env=wrapper[1])
    batch = subprocess.Popen([sys.executable, "-c", script], stderr=subprocess.PIPE, text=True)
    summary_path = os.path.join(out, "summary.json")
    models_done = []
    for _ in range(3000):        # until the box is done (bounded: the box takes seconds)
        if batch.poll() is not None:
            break
        try:
            with open(summary_path, encoding="utf-8") as f:
                models_done = json.load(f)["models"]
        except (OSError, ValueError):
            pass
        if models_done:
            break
        time.sleep(0.1)
    time.sleep(0.5)              # the slow job has started
    batch.send_signal(signal.SIGTERM)
    assert batch.wait(timeout=60) == 128 + signal.SIGTERM, batch.stderr.read()
    with open(summary_path, encoding="utf-8") as f:
        summary = json.load(f)
    assert [(os.path.basename(e["model"]), e["status"]) for e in summary["models"]] == [("box.step", "ok")]
    left = [p for p in psutil.process_iter(["cmdline"]) if (p.info["cmdline"] or [])[-1:] == ["297"]]
    assert not left


def test_a_memory_limit_kills_the_job_with_an_error_naming_it(corpus, tmp_path):
    """The job is killed once its process tree passes the limit, and the entry names it. 40 MB:
    below any run of the job (its imports alone take 55 MB), so the kill never depends on how
    lean the stages have become (120 MB stopped being exceeded on the small torus)."""
    from stripweave.batch import run_batch
    torus_path = os.path.join(corpus["root"], "meshes", "torus.OBJ")
    summary = run_batch([torus_path], str(tmp_path / "out"), memory_limit_mb=40, weave_args=SMALL, progress=None)
    entry = summary["models"][0]
    assert entry["status"] == "error" and entry["error"].startswith("memory limit of 40 MB exceeded")
    assert entry["peak_memory_mb"] > 40 and entry["report"] is None


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def dask_cluster():
    """A Dask scheduler and one worker (2 threads) on loopback, as subprocesses."""
    address = f"tcp://127.0.0.1:{_free_port()}"
    python = sys.executable
    scheduler = subprocess.Popen([python, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                  "--port", address.rsplit(":", 1)[1], "--no-dashboard"],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    worker = subprocess.Popen([python, "-m", "distributed.cli.dask_worker", address, "--host", "127.0.0.1",
                               "--nthreads", "2", "--nworkers", "1", "--no-dashboard", "--no-nanny"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        from distributed import Client
        with Client(address, timeout=60) as client:
            client.wait_for_workers(1, timeout=60)
        yield address
    finally:
        for proc in (worker, scheduler):
            os.killpg(proc.pid, signal.SIGTERM)
        for proc in (worker, scheduler):
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()


def test_the_dask_path_gives_the_same_statuses(batch, corpus, dask_cluster, tmp_path):
    out = str(tmp_path / "out")
    models = [os.path.join(corpus["root"], name) for name in ("box.step", "broken.stl")]
    p = run("batch", *models, "--out", out, "--scheduler", dask_cluster, *SMALL)
    assert p.returncode == 0, p.stderr
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
        summary = json.load(f)
    local = batch["by_name"]
    for entry in summary["models"]:
        name = os.path.basename(entry["model"])
        assert (entry["status"], entry["error"]) == (local[name]["status"], local[name]["error"])
    box_entry = summary["models"][0]
    assert box_entry["report"]["patches"] == local["box.step"]["report"]["patches"]   # deterministic weave
    assert os.path.isfile(os.path.join(out, "box", "preview.png"))
