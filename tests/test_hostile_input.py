"""Hostile input (issue 23): no crash, hang, runaway, traceback or silent misread, on any
file, design or option, and nothing lost when two writers meet. Every input is generated
here; cases that would kill or hang the test process run in a subprocess with a timeout."""
import json
import os
import stat
import struct
import subprocess
import sys
import threading

import numpy as np
import pytest

import stripweave as sw
# Not `from conftest import ...`: with the whole tree collected, tests/gui/conftest.py may
# hold the module name `conftest`.
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.environ.get("STRIPWEAVE_BUILD", os.path.join(REPO, "build"))
FREECAD_LIB = "/usr/lib/freecad-python3/lib"
from models import box

LAUNCHER = os.path.join(BUILD, "stripweave")
ENV = {**os.environ, "PYTHONPATH": os.pathsep.join([FREECAD_LIB, os.path.join(REPO, "workbench"), BUILD,
                                                     os.path.join(REPO, "tests")])}


def run_python(code, timeout=120):
    """Run `code` in a fresh interpreter: a signal or a hang there fails the test, not the suite."""
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=ENV, timeout=timeout)


def error_in_subprocess(call, timeout=60):
    """The InputError message `call` gives in a fresh interpreter (a hang there times out)."""
    r = run_python(f"import stripweave as sw\nfrom stripweave.design import Design\ntry:\n    {call}\n"
                   f"except sw.InputError as e:\n    print(e)\n", timeout=timeout)
    return r.stdout + r.stderr[-300:]


def run_cli(*args, timeout=300):
    return subprocess.run([LAUNCHER, *args], capture_output=True, text=True, env=ENV, timeout=timeout)


@pytest.fixture(scope="module")
def box_mesh():
    s = sw.from_shape(box(10), target_triangles=2000)
    return s.vertices.copy(), s.triangles.copy()


@pytest.fixture(scope="module")
def box_stl(tmp_path_factory, box_mesh):
    path = str(tmp_path_factory.mktemp("hostile") / "box.stl")
    sw.write_mesh(path, *box_mesh)
    return path


def _refused(path, text, pattern):
    """Reading a mesh file of this text is an InputError matching `pattern`."""
    path.write_text(text)
    with pytest.raises(sw.InputError, match=pattern):
        sw.read_mesh(str(path))


# --- 1. crashes by signal: numbers checked where they enter ----------------------------

@pytest.mark.parametrize("anchor", ["1e307,0,0", "5,5,1e307", "-1e300,5,5,1,0,0"])
def test_anchor_near_the_double_range_is_refused_not_a_signal(box_stl, anchor):
    """A coordinate of 1e307 overflowed the closest-point search into GMP's SIGFPE."""
    r = run_cli("loop", box_stl, f"--anchor={anchor}", "--target-triangles", "2000")
    assert r.returncode == 1, (r.returncode, r.stderr)
    assert r.stderr.count("\n") == 1 and "bounding-box diagonals from the model's centre" in r.stderr


def test_design_anchor_near_the_double_range_is_refused_not_a_signal(box_stl):
    r = run_python(f"""
import stripweave as sw
from stripweave.design import Design
from stripweave.strips import DesignSession
s = sw.load({box_stl!r}, target_triangles=2000)
try:
    DesignSession(s, Design([[(1e307, 5, 5)]]))
except sw.InputError as e:
    print("InputError:", e)
""")
    assert r.returncode == 0, (r.returncode, r.stderr[-500:])
    assert "InputError: strip 1" not in r.stdout and "off the part" in r.stdout


def test_anchor_direction_near_the_double_range_is_normalized(box_mesh):
    from stripweave.loops import LoopSession
    session = LoopSession(sw.from_mesh(*box_mesh, target_triangles=0))
    huge, unit = session.loops([(5, 5, 10, 1e307, 1e307, 0)])[0], session.loops([(5, 5, 10, 1, 1, 0)])[0]
    assert huge["cost"] == pytest.approx(unit["cost"])


def test_mesh_coordinates_near_the_double_range_are_refused(box_mesh):
    v, t = box_mesh
    with pytest.raises(sw.InputError, match="bounding-box diagonal is not a finite size"):
        sw.from_mesh(v * 1e300, t, target_triangles=0)


def test_triangle_index_beyond_32_bits_is_refused_not_wrapped(box_mesh):
    v, t = box_mesh
    t = t.astype(np.int64)
    t[0, 0] = 2 ** 32 + 1
    with pytest.raises(sw.InputError, match="refers to vertex 4294967297"):
        sw.from_mesh(v, t, target_triangles=0)


def test_fractional_triangle_index_is_refused_not_truncated(box_mesh):
    v, t = box_mesh
    t = t.astype(float)
    t[3, 1] += 0.5
    with pytest.raises(sw.InputError, match="whole numbers"):
        sw.from_mesh(v, t, target_triangles=0)


@pytest.mark.parametrize("angle", [500.0, float("nan"), 0.0, -10.0, 180.0])
def test_feature_angle_outside_0_180_is_refused(box_mesh, angle):
    with pytest.raises(sw.InputError, match=r"feature angle must be within \(0, 180\)"):
        sw.from_mesh(*box_mesh, target_triangles=0, feature_angle_deg=angle)


def test_feature_angle_outside_0_180_is_refused_for_a_brep():
    with pytest.raises(sw.InputError, match="feature angle"):
        sw.from_shape(box(10), target_triangles=0, feature_angle_deg=500)


@pytest.mark.parametrize("target", [-1, -30000, 10 ** 7])
def test_target_triangles_out_of_range_is_refused(box_mesh, target):
    with pytest.raises(sw.InputError, match="target triangle count"):
        sw.from_mesh(*box_mesh, target_triangles=target)


def test_target_triangles_too_big_for_an_int_is_an_input_error(box_mesh):
    with pytest.raises(sw.InputError, match="target_triangles must be"):
        sw.from_mesh(*box_mesh, target_triangles=2 ** 40)


def test_keeping_a_mesh_over_the_solver_limit_is_refused_with_a_reason():
    """--target-triangles 0 on a 2M-triangle mesh ran for minutes: over 1M triangles it says why not."""
    n = 710  # a 710 x 710 grid: 1,008,200 triangles
    x, y = np.meshgrid(np.arange(n + 1, dtype=float), np.arange(n + 1, dtype=float))
    v = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    t = np.concatenate([np.stack([i, i + 1, i + n + 2], 1), np.stack([i, i + n + 2, i + n + 1], 1)])
    with pytest.raises(sw.InputError, match="1008200 triangles; a target of 0 keeps them all"):
        sw.from_mesh(v, t, target_triangles=0)


# --- 2. hangs and runaways ------------------------------------------------------------------

@pytest.mark.parametrize("far", [1e3, 1e7, 1e307])
def test_outlier_vertex_is_removed_with_a_count(box_mesh, far):
    """One stray vertex at 1e7 drove the remesher past 4 GB; at 1e3 it made 2.3x the target."""
    v, t = box_mesh
    v = v.copy()
    v[0] = [far, 0, 0]
    r = sw.from_mesh(v, t, target_triangles=2000).report()
    assert any(w.startswith("removed 1 outlier vertex") for w in r["warnings"]), r["warnings"]
    assert r["bbox_diagonal"] == pytest.approx(10 * 3 ** 0.5, rel=1e-9)
    assert 1500 < r["triangles"] < 2700
    assert r["components"] == 1 and r["boundary_loops"] == 1  # the hole the outlier's fan leaves


def test_a_cone_tip_is_not_an_outlier():
    """A sampled point with no near neighbour: the apex of a fan 20 times taller than wide stays."""
    k = 64
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    v = np.vstack([np.stack([np.cos(a), np.sin(a), np.zeros(k)], 1), [[0, 0, 20], [0, 0, 0]]])
    t = [[i, (i + 1) % k, k] for i in range(k)] + [[(i + 1) % k, i, k + 1] for i in range(k)]
    r = sw.from_mesh(v, np.array(t), target_triangles=0).report()
    assert not any("outlier" in w for w in r["warnings"])
    assert r["bbox_diagonal"] == pytest.approx((8 + 400) ** 0.5)


def test_an_unreferenced_far_vertex_does_not_scale_the_repairs(box_mesh):
    """A vertex no triangle uses, at 1e7, made every triangle of a 10 mm box 'zero-area'."""
    v, t = box_mesh
    r = sw.from_mesh(np.vstack([v, [[1e7, 0, 0]]]), t, target_triangles=0).report()
    assert r["warnings"] == ["dropped 1 unreferenced vertex"]
    assert r["components"] == 1 and r["boundary_loops"] == 0


def test_off_face_claiming_a_billion_corners_is_refused_at_once(tmp_path):
    _refused(tmp_path / "lying.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n999999999 0 1 2\n",
             r"lying.off.*line 6: the face claims 999999999 corners")


def test_off_header_counts_beyond_the_file_size_are_refused_before_allocating(tmp_path):
    _refused(tmp_path / "counts.off", "OFF\n999999999 999999999 0\n0 0 0\n",
             "line 2: the header announces 999999999 vertices")


@pytest.mark.parametrize("element,line", [("vertex", 3), ("face", 7)])
def test_ply_header_counts_beyond_the_file_size_are_refused_with_their_line(tmp_path, element, line):
    """CGAL said only 'not a valid PLY file' for a header announcing a billion elements."""
    counts = {"vertex": 3, "face": 1, element: 999999999}
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {counts['vertex']}\nproperty float x\n"
              f"property float y\nproperty float z\nelement face {counts['face']}\n"
              "property list uchar int vertex_indices\nend_header\n").encode()
    path = tmp_path / "lying.ply"
    path.write_bytes(header + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"\x03" + struct.pack("<3i", 0, 1, 2))
    with pytest.raises(sw.InputError, match=f"line {line}: the header announces 999999999 {element} elements"):
        sw.read_mesh(str(path))


@pytest.mark.parametrize("special", ["fifo", "/dev/zero", "/dev/urandom"])
@pytest.mark.parametrize("ext", ["stl", "off", "step"])
def test_only_regular_files_are_opened(tmp_path, special, ext):
    """A FIFO, /dev/zero or /dev/urandom named .stl was read forever."""
    path = str(tmp_path / f"special.{ext}")
    if special == "fifo":
        os.mkfifo(path)
    else:
        os.symlink(special, path)
    assert "not a regular file" in error_in_subprocess(f"sw.load({path!r})")


def test_design_file_that_is_a_fifo_is_refused(tmp_path):
    path = str(tmp_path / "design.json")
    os.mkfifo(path)
    assert "not a regular file" in error_in_subprocess(f"Design.load({path!r})")


def test_red_regions_have_a_bounded_reserve(box_mesh):
    """Red regions were exempt from the budget: a model where no loop helps looped forever."""
    from stripweave.design import Design
    from stripweave.strips import DesignSession
    from stripweave.weave import WeaveOptions, auto_weave
    ds = DesignSession(sw.from_mesh(*box_mesh, target_triangles=0), Design())
    result = auto_weave(ds, WeaveOptions(budget=0.5, red_reserve=1.0, refine=False))
    assert result.stopped.endswith("(red regions remain)")
    # A sphere asks for no cut: the allowance is the reserve alone, and the stop names it (not the clock).
    assert "red allowance of 0.5 units spent" in result.stopped
    assert result.assessment["colours"]["red"] > 0
    assert len(ds.design.strips) <= 1


def test_weave_options_refuse_a_nan_time_limit_and_reserve():
    from stripweave.weave import WeaveOptions
    for bad in ({"time_limit_s": float("nan")}, {"red_reserve": float("inf")}, {"red_reserve": 0.5}):
        with pytest.raises(sw.InputError):
            WeaveOptions(**bad).check()


# --- 3. silent misreads ----------------------------------------------------------------------

def _binary_stl(triangles, count):
    data = b"\0" * 80 + struct.pack("<I", count)
    for tri in triangles:
        data += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *p) for p in tri) + b"\0\0"
    return data


def _fan(n):
    return [((0, 0, 0), (1, i, 0), (1, i + 1, 0)) for i in range(n)]


@pytest.mark.parametrize("count", [10, 30])
def test_binary_stl_whose_count_disagrees_with_its_data_is_refused(tmp_path, count):
    """A header count smaller than the data was read as its first triangles, silently."""
    path = tmp_path / "lying.stl"
    path.write_bytes(_binary_stl(_fan(20), count))
    with pytest.raises(sw.InputError, match=f"byte 80: the binary STL header counts {count} triangles.*20 triangles"):
        sw.read_mesh(str(path))


def test_binary_stl_whose_header_starts_with_solid_is_read_as_binary(tmp_path):
    path = tmp_path / "solid.stl"
    path.write_bytes(b"solid exported" + _binary_stl(_fan(20), 20)[14:])
    v, t = sw.read_mesh(str(path))
    assert len(t) == 20 and len(v) == 60


def test_ascii_stl_with_a_corrupt_number_names_the_line(tmp_path):
    _refused(tmp_path / "bad.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
             "vertex 0 1e+ 0\nendloop\nendfacet\nendsolid s\n", "line 6: y '1e\\+' is not a finite number")


@pytest.mark.parametrize("face,problem", [("f 1.5 2 3", "'1.5' does not start with a whole vertex number"),
                                          ("f a b c", "'a' does not start with a whole vertex number"),
                                          ("f 1 2 9", "'9' refers to no vertex"),
                                          ("f 0 1 2", "'0' refers to no vertex")])
def test_obj_face_index_that_is_not_a_vertex_is_refused_with_its_line(tmp_path, face, problem):
    """OBJ `f 1.5 2 3` was read as `f 1 2 3`, and indices CGAL could not parse were skipped."""
    _refused(tmp_path / "bad.obj", f"# generated\nv 0 0 0\nv 1 0 0\nv 0 1 0\n{face}\n",
             f"bad.obj': line 5: the corner {problem}")


def test_obj_corner_forms_and_relative_indices(tmp_path):
    path = tmp_path / "forms.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1 2/1/1 3//1\nf -4 -2 -1\n")
    v, t = sw.read_mesh(str(path))
    assert t.tolist() == [[0, 1, 2], [0, 2, 3]]


def _polygon_area_and_normals(v, t):
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    return 0.5 * np.linalg.norm(n, axis=1).sum(), n[:, 2]


@pytest.mark.parametrize("ext", ["obj", "off"])
def test_concave_polygon_is_ear_clipped_not_fanned(tmp_path, ext):
    """An L-shaped hexagon fanned from its reflex-side corner folds a cap over its notch."""
    corners = [(2, 2, 0), (0, 2, 0), (0, 0, 0), (3, 0, 0), (3, 1, 0), (2, 1, 0)]  # area 5; fan from 0 folds
    path = tmp_path / f"ell.{ext}"
    if ext == "obj":
        path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in corners) + "f 1 2 3 4 5 6\n")
    else:
        path.write_text("OFF\n6 1 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in corners) + "6 0 1 2 3 4 5\n")
    v, t = sw.read_mesh(str(path))
    area, nz = _polygon_area_and_normals(v, t)
    assert len(t) == 4
    assert area == pytest.approx(5.0)
    assert np.all(nz > 0)  # none folded over


def test_self_crossing_polygon_is_refused(tmp_path):
    _refused(tmp_path / "bowtie.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 2 2 0\nv 1 3 0\nf 1 2 3 4 5\n",
             "line 6: the face of 5 corners crosses itself")


@pytest.mark.parametrize("corrupt,problem", [("1.0 2,0 3.0", "y '2,0'"), ("1.0 2.0", "the line ends where z"),
                                             ("1.0 nan 3", "y 'nan'")])
def test_corrupt_off_number_is_refused_with_its_line(tmp_path, corrupt, problem):
    """A corrupted OFF number shifted every later coordinate."""
    _refused(tmp_path / "corrupt.off", f"OFF\n4 2 0\n0 0 0\n1 0 0\n{corrupt}\n0 1 0\n3 0 1 2\n3 0 2 3\n",
             f"line 5: {problem}")


def test_off_with_fewer_lines_than_its_counts_is_refused(tmp_path):
    _refused(tmp_path / "short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n", "ends after 1 of its 2 faces")


@pytest.mark.parametrize("count", [0, -3])
def test_loop_alternatives_below_one_are_refused(box_mesh, count):
    from stripweave.loops import LoopSession
    with pytest.raises(sw.InputError, match="alternatives must be a whole number, 1 or more"):
        LoopSession(sw.from_mesh(*box_mesh, target_triangles=0)).loops([(5, 5, 10)], alternatives=count)


def test_two_anchors_at_one_point_with_different_tangents_are_refused(box_mesh):
    from stripweave.design import Design
    from stripweave.loops import LoopSession
    from stripweave.strips import DesignSession
    surface = sw.from_mesh(*box_mesh, target_triangles=0)
    with pytest.raises(sw.InputError, match="anchors 1 and 2 are at one point with different tangents"):
        LoopSession(surface).loops([(5, 5, 10, 1, 0, 0), (5, 5, 10, 0, 1, 0)])
    with pytest.raises(sw.InputError, match="strip 1: anchors 1 and 2 are at one point"):
        DesignSession(surface, Design([[(5, 5, 10, 1, 0, 0), (5, 5, 10, 0, 1, 0)]]))


# --- 4. tracebacks -----------------------------------------------------------------------------

def _design_text(**options):
    return json.dumps({"format": "stripweave-design", "version": 1, "options": options,
                       "strips": [{"anchors": [{"point": [5, 5, 10], "direction": None}]}]})


@pytest.mark.parametrize("content,problem", [
    (b"\xff\xfe{not utf-8", "not UTF-8"),
    (b"[" * 100000 + b"]" * 100000, "nests its JSON too deeply"),
    (_design_text(k=4.5).encode(), "options.k must be a whole number"),
    (_design_text(max_turn_deg=float("nan")).encode(), "options.max_turn_deg"),
    (_design_text(feature_angle_deg=500).encode(), "options.feature_angle_deg"),
    (json.dumps({"format": "stripweave-design", "version": 1, "model": [1], "strips": []}).encode(), "'model'"),
    (b'{"format": "stripweave-design", "version": 1, "strips": [{"anchors": [{"point": [1' + b"0" * 400 +
     b', 0, 0]}]}]}', "point must be a list of three numbers"),
])
def test_bad_design_file_is_a_one_line_input_error(tmp_path, content, problem):
    path = tmp_path / "design.json"
    path.write_bytes(content)
    with pytest.raises(sw.InputError, match=problem):
        from stripweave.design import Design
        Design.load(str(path))


def test_cli_prints_no_traceback_for_a_bad_design(tmp_path, box_stl):
    path = tmp_path / "design.json"
    path.write_bytes(b"\xff\xfe{not utf-8")
    r = run_cli("layout", box_stl, "--design", str(path), "--out", str(tmp_path / "o"))
    assert r.returncode == 1
    assert "Traceback" not in r.stderr and r.stderr.count("\n") == 1 and "not UTF-8" in r.stderr


# --- 5. files ----------------------------------------------------------------------------------------

def _design(n):
    from stripweave.design import Design
    return Design([[(i, n, 0)] for i in range(300)], model={"writer": n})


def test_concurrent_saves_never_corrupt_or_mix(tmp_path):
    """100 trials of two concurrent saves: 0 invalid or mixed files (the shared `.tmp` name gave 7 of 12)."""
    from stripweave.design import Design
    path = str(tmp_path / "design.json")
    designs = [_design(0), _design(1)]
    bad = 0
    for _ in range(100):
        barrier = threading.Barrier(2)
        errors = []

        def save(d):
            barrier.wait()
            try:
                d.save(path)
            except Exception as exc:   # a failed save is a corruption too
                errors.append(exc)
        threads = [threading.Thread(target=save, args=(d,)) for d in designs]
        for th in threads:
            th.start()
        for th in threads:
            th.join()
        loaded = Design.load(path)
        writers = {a.point[1] for s in loaded.strips for a in s.anchors}
        bad += bool(errors) or len(writers) != 1 or loaded.model["writer"] not in writers
    assert bad == 0
    assert [f for f in os.listdir(tmp_path) if f != "design.json"] == []  # no temporary left behind


def test_save_through_a_symlink_keeps_the_link_and_the_mode(tmp_path):
    target = tmp_path / "real.json"
    _design(0).save(str(target))
    os.chmod(target, 0o600)
    link = tmp_path / "design.json"
    os.symlink(target, link)
    _design(1).save(str(link))
    assert os.path.islink(link) and os.readlink(link) == str(target)
    assert stat.S_IMODE(os.stat(target).st_mode) == 0o600
    from stripweave.design import Design
    assert Design.load(str(target)).model["writer"] == 1


def test_unusable_out_is_refused_before_the_work(tmp_path):
    """The model is not even read: the folder is checked first (it was found after all the work)."""
    blocker = tmp_path / "file"
    blocker.write_text("a file where a folder is wanted")
    r = run_cli("weave", str(tmp_path / "no-model.step"), "--auto", "--out", str(blocker / "out"))
    assert r.returncode == 1 and "cannot write to the output folder" in r.stderr and "no-model" not in r.stderr
    with pytest.raises(sw.InputError, match="output folder"):
        sw.weave(str(tmp_path / "no-model.step"), out=str(blocker / "out"))


def test_out_lock_serializes_two_writers(tmp_path):
    from stripweave.files import out_lock
    order = []
    inside = threading.Event()

    def second():
        inside.wait()
        with out_lock(tmp_path):
            order.append("second")
    th = threading.Thread(target=second)
    th.start()
    with out_lock(tmp_path):
        inside.set()
        th.join(0.5)          # it cannot get in while the first holds the lock
        order.append("first")
    th.join()
    assert order == ["first", "second"]


def test_weave_into_the_folder_of_its_own_design_keeps_a_backup(tmp_path, box_stl):
    from stripweave.design import Design
    given = Design([[(5, 5, 10, 1, 0, 0)]])
    given.save(str(tmp_path / "design.json"))
    before = (tmp_path / "design.json").read_bytes()
    sw.weave(box_stl, design=str(tmp_path / "design.json"), auto=False, out=str(tmp_path), preview=False,
             target_triangles=2000)
    assert (tmp_path / "design.json.bak").read_bytes() == before
    assert json.loads((tmp_path / "report.json").read_text())["strips"] == 1


# --- 6. the bidirectional search under an asymmetric g' mask ------------------------------

@pytest.mark.parametrize("seed", [0, 3])
def test_hover_equals_dijkstra_with_an_asymmetric_mask(seed):
    """The backward half checked node m, not reverse(m), against the mask: with a mask not
    closed under reverse, hover used disabled nodes and found costlier loops than Dijkstra."""
    from models import torus
    from stripweave.loops import LoopSession
    surface = sw.from_shape(torus(), target_triangles=3000)
    session = LoopSession(surface)
    n = session.stats()["gprime_nodes"]
    disabled = [int(x) for x in np.random.default_rng(seed).choice(n, n // 5, replace=False)]
    session.native.set_disabled(disabled)
    costs = {}
    for algorithm in ("bidirectional", "dijkstra", "astar"):
        session.algorithm = algorithm
        loop = session.best_loop(surface.vertices[100])
        costs[algorithm] = loop["cost"]
        assert not set(loop["nodes"]) & set(disabled)
    assert costs["bidirectional"] == pytest.approx(costs["dijkstra"], rel=1e-12)
    assert costs["astar"] == pytest.approx(costs["dijkstra"], rel=1e-12)


def test_a_failed_picture_write_leaves_the_old_file_and_names_the_path(tmp_path):
    """On a full disk the error named no file and left a truncated preview.png."""
    import errno
    from stripweave.files import atomic_path
    path = tmp_path / "preview.png"
    path.write_bytes(b"the old picture")
    with pytest.raises(sw.InputError, match=f"cannot write {path}: No space left on device"):
        with atomic_path(str(path)) as tmp:
            assert tmp.endswith(".png") and os.path.dirname(tmp) == str(tmp_path)
            with open(tmp, "wb") as f:
                f.write(b"half a pic")
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert path.read_bytes() == b"the old picture"
    assert os.listdir(tmp_path) == ["preview.png"]


# --- 7. loose-face B-reps are sewn ------------------------------------------------------------

def _loose_box(tmp_path, ext, shells):
    """A box written as 6 faces that share no edge (each face copied alone), or as 6 single-face
    shells: how some exporters write an unsewn part."""
    import Part
    faces = [f.copy() for f in box(10).Faces]
    parts = [Part.Shell([f]) for f in faces] if shells else faces
    path = str(tmp_path / f"loose.{ext}")
    shape = Part.makeCompound(parts)
    shape.exportIges(path) if ext == "iges" else shape.exportStep(path)
    return path


@pytest.mark.parametrize("ext,shells", [("iges", False), ("step", False), ("step", True)])
def test_loose_face_box_is_sewn_with_a_warning(tmp_path, ext, shells):
    """Loose faces had no creases and no shared borders: weave found 6 components, no feature
    curve, and reported a valid layout of 0 patches."""
    r = run_cli("info", _loose_box(tmp_path, ext, shells), "--json", "--target-triangles", "3000")
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert (info["components"], info["genus"], info["boundary_loops"]) == (1, 0, 0)
    assert info["feature_curves"] == 12            # the box's 12 edges, creases again
    sewn = [w for w in info["warnings"] if w.startswith("sewed")]
    assert len(sewn) == 1 and "sewed 24 of 24 free edges" in sewn[0] and "0 free edges remain" in sewn[0]


def test_an_open_sheet_is_not_sewn_and_says_nothing(tmp_path):
    """A real boundary (a box without its lid, edges shared) stays free: no repair, no warning."""
    import Part
    path = str(tmp_path / "open.step")
    Part.Shell(box(10).Faces[:5]).exportStep(path)
    s = sw.load(path, target_triangles=2000)
    r = s.report()
    assert (r["components"], r["boundary_loops"]) == (1, 1)
    assert not [w for w in r["warnings"] if "sewed" in w]


# --- 8. the memory guard ----------------------------------------------------------------------

def test_memory_guard_refuses_a_target_beyond_the_limit_before_the_work(box_stl):
    """A fake small limit (STRIPWEAVE_MEMORY_LIMIT_MB): the same run that fits is refused with
    one line once its estimate is over the limit, before any allocation (no exhaustion)."""
    ok = run_cli("info", box_stl, "--target-triangles", "2000", "--memory-limit", "400")
    assert ok.returncode == 0, ok.stderr
    r = run_cli("info", box_stl, "--target-triangles", "1000000", "--memory-limit", "400", timeout=60)
    assert r.returncode == 1 and r.stderr.count("\n") == 1, r.stderr
    assert "1000000 solver triangles" in r.stderr and "more than the 400 MB allowed" in r.stderr


def test_memory_guard_refuses_the_elastica_graph_beyond_the_limit(box_mesh, monkeypatch):
    """The graph is weaving's largest allocation: it has a check of its own, with the same limit."""
    from stripweave.loops import LoopSession
    surface = sw.from_mesh(*box_mesh, target_triangles=20000)
    monkeypatch.setenv("STRIPWEAVE_MEMORY_LIMIT_MB", "300")   # the surface fits, its graph does not
    with pytest.raises(sw.InputError, match=r"the elastica graph of \d+ triangles \(k = 4\) needs about \d+ MB, "
                                            r"more than the 300 MB allowed"):
        LoopSession(surface)
    monkeypatch.setenv("STRIPWEAVE_MEMORY_LIMIT_MB", "0.5x")
    with pytest.raises(sw.InputError, match="STRIPWEAVE_MEMORY_LIMIT_MB must be a positive number"):
        sw.from_mesh(*box_mesh, target_triangles=2000)


@pytest.mark.parametrize("limit", ["0", "-5", "nan", "inf"])
def test_memory_limit_option_out_of_range_is_refused(box_stl, limit):
    r = run_cli("info", box_stl, f"--memory-limit={limit}")
    assert r.returncode == 1 and r.stderr.count("\n") == 1 and "--memory-limit must be a positive" in r.stderr


# --- 9. floating-point traps inside native calls ----------------------------------------------

def test_sigfpe_inside_a_native_call_is_an_input_error_and_the_process_lives():
    """GMP raises SIGFPE on a division by zero (and aborts if the handler returns): inside a
    binding it must become an InputError, on the caller's thread and on parallel_for's workers,
    again and again (the signal must not stay blocked), and floating-point traps a host enabled
    must not fire inside the call."""
    r = run_python("""
import stripweave as sw
from stripweave._native import native
for kind in ["gmp", "gmp", "gmp-worker", "raise", "gmp"]:
    try:
        native._fp_trap_test(kind)
        print("no error", kind)
    except sw.InputError as e:
        print("InputError", kind, "floating-point trap" in str(e))
native._fp_trap_test("float")
print("alive")
""", timeout=60)
    assert r.returncode == 0, (r.returncode, r.stderr[-500:])
    assert r.stdout.split("\n") == ["InputError gmp True", "InputError gmp True", "InputError gmp-worker True",
                                    "InputError raise True", "InputError gmp True", "alive", ""]


def test_sigfpe_outside_native_calls_keeps_its_default_action():
    """The handler passes a SIGFPE raised outside any native call on (here: the default action)."""
    r = run_python("""
import os, signal
from stripweave._native import native
try:
    native._fp_trap_test("gmp")
except Exception:
    pass
os.kill(os.getpid(), signal.SIGFPE)
print("survived")
""", timeout=60)
    assert r.returncode == -8 and "survived" not in r.stdout


# --- 10. two writers into one folder ----------------------------------------------------------

def test_two_concurrent_weave_runs_into_one_out_never_mix(tmp_path, box_stl):
    """Two `weave` processes with different designs into one --out: both succeed (the second waits
    on the folder's lock) and design.json, layout.json and report.json come from one run."""
    from stripweave.design import Design
    designs = {1: Design([[(5, 5, 10, 1, 0, 0)]]), 2: Design([[(5, 5, 10, 1, 0, 0)], [(5, 5, 10, 0, 1, 0)]])}
    out = tmp_path / "out"
    for trial in range(3):
        procs = []
        for n, d in designs.items():
            d.save(str(tmp_path / f"d{n}.json"))
            procs.append(subprocess.Popen(
                [LAUNCHER, "weave", box_stl, "--design", str(tmp_path / f"d{n}.json"), "--out", str(out),
                 "--target-triangles", "2000", "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                text=True, env=ENV))
        results = [p.communicate(timeout=300) for p in procs]
        for p, (stdout, stderr) in zip(procs, results):
            assert p.returncode == 0, stderr
        design = Design.load(str(out / "design.json"))
        report = json.loads((out / "report.json").read_text())
        layout = json.loads((out / "layout.json").read_text())
        n = len(design.strips)
        assert n in designs and report["strips"] == n
        assert len(layout["patches"]) == report["patches"]
        # the run whose design survived wrote these very files: its own --json summary says so
        summary = json.loads(results[n - 1][0])
        assert (summary["patches"], summary["strips"]) == (report["patches"], report["strips"])
        assert summary["paths"]["design"] == str(out / "design.json")


def test_concurrent_saves_from_two_processes_never_show_a_reader_a_broken_file(tmp_path):
    """Two processes save different designs 100 times each into one path while this one reads it:
    every read is valid JSON from a single writer (0 corrupt or mixed files)."""
    path = str(tmp_path / "design.json")
    from stripweave.design import Design
    _design(0).save(path)
    code = ("import sys\nsys.path.insert(0, {tests!r})\nfrom test_hostile_input import _design\n"
            "d = _design({n})\nfor _ in range(100):\n    d.save({path!r})\n")
    procs = [subprocess.Popen([sys.executable, "-c", code.format(tests=os.path.join(REPO, "tests"), n=n, path=path)],
                              env=ENV, stderr=subprocess.PIPE, text=True) for n in (0, 1)]
    reads = bad = 0
    while any(p.poll() is None for p in procs) or reads < 100:
        loaded = Design.load(path)
        writers = {a.point[1] for s in loaded.strips for a in s.anchors}
        bad += len(writers) != 1 or loaded.model["writer"] not in writers or len(loaded.strips) != 300
        reads += 1
    for p in procs:
        assert p.wait() == 0, p.stderr.read()
    assert bad == 0 and reads >= 100
    assert os.listdir(tmp_path) == ["design.json"]
