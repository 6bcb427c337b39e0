"""Large parts (issue 22): the native streaming readers (PLY, STL), the O(n) weld, and the
proxy (paper §8.1): the solver surface is a proxy of the full-resolution original, which the
refit measures against. Every model is generated here."""
import struct

import numpy as np
import pytest

import stripweave as sw

# A unit square as two triangles, a concave pentagon beside it (ear-clipped into three).
SQUARE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
PENTAGON = [(2, 0, 0), (4, 0, 0), (4, 2, 0), (3, 1, 0), (2, 2, 0)]  # notch at (3, 1): area 3
POINTS = SQUARE + PENTAGON
FACES = [[0, 1, 2, 3], [4, 5, 6, 7, 8]]


def _area_and_up(v, t):
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
    return 0.5 * np.linalg.norm(n, axis=1).sum(), bool(np.all(n[:, 2] > 0))


def _ply_binary(order, faces_first=False):
    """A binary PLY with extra vertex properties (normal, colour), an extra element (edge)
    and face lists of 4 and 5 corners, in either byte order."""
    e = "<" if order == "little" else ">"
    vertex_header = ("element vertex 9\nproperty double x\nproperty float nx\nproperty double y\n"
                     "property double z\nproperty uchar red\nproperty list uchar int texture\n")
    face_header = "element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
    edge_header = "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    vertices = b"".join(struct.pack(e + "dfddBB", x, 0.5, y, z, 200, 1) + struct.pack(e + "i", 7)
                        for x, y, z in POINTS)
    faces = b"".join(struct.pack(e + "BB", 1, len(f)) + struct.pack(e + f"{len(f)}i", *f) for f in FACES)
    edges = struct.pack(e + "2i", 0, 1)
    parts = [(face_header, faces), (vertex_header, vertices)] if faces_first else \
        [(vertex_header, vertices), (edge_header, edges), (face_header, faces)]
    header = f"ply\nformat binary_{order}_endian 1.0\ncomment generated\n" + "".join(h for h, _ in parts) + \
        "end_header\n"
    return header.encode() + b"".join(d for _, d in parts)


def _ply_ascii():
    header = ("ply\r\nformat ascii 1.0\r\nobj_info test\r\nelement vertex 9\r\nproperty float x\r\n"
              "property float y\r\nproperty float z\r\nproperty uchar alpha\r\nelement face 2\r\n"
              "property list uchar uint vertex_index\r\nend_header\r\n")
    body = "".join(f"{x} {y} {z} 255\r\n" for x, y, z in POINTS) + "\r\n" + \
        "".join(f"{len(f)} {' '.join(map(str, f))}\r\n" for f in FACES)
    return (header + body).encode()


@pytest.mark.parametrize("kind", ["little", "big", "ascii", "faces_first"])
def test_ply_reader_skips_extra_properties_and_elements_and_clips_polygons(tmp_path, kind):
    data = _ply_ascii() if kind == "ascii" else _ply_binary("little" if kind == "faces_first" else kind,
                                                            faces_first=kind == "faces_first")
    path = tmp_path / "shape.ply"
    path.write_bytes(data)
    v, t = sw.read_mesh(str(path))
    assert np.allclose(v, POINTS)
    assert len(t) == 2 + 3
    area, up = _area_and_up(v, t)
    assert area == pytest.approx(1 + 3) and up   # the pentagon's notch is not folded over


def _refused(tmp_path, data, pattern, name="bad.ply"):
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(sw.InputError, match=pattern):
        sw.read_mesh(str(path))


def test_ply_binary_index_out_of_range_names_its_byte(tmp_path):
    data = bytearray(_ply_binary("little"))
    data[-4:] = struct.pack("<i", 99)   # the pentagon's last corner
    offset = len(data) - 4
    _refused(tmp_path, bytes(data), f"bad.ply': byte {offset}: face 1 refers to vertex 99")


def test_ply_ascii_errors_name_their_line(tmp_path):
    text = _ply_ascii().decode().replace("4 2 0 255", "4 2x 0 255")
    _refused(tmp_path, text.encode(), r"line 18: y '2x' is not a finite number")
    text = _ply_ascii().decode().replace("4 0 1 2 3", "4 0 1 2 3 9")
    _refused(tmp_path, text.encode(), "line 22: more numbers on the line than its element's properties")


@pytest.mark.parametrize("change,pattern", [
    (lambda d: d + b"\0\0", "2 bytes after the last element"),
    (lambda d: d[:-3], "byte .*: the file ends where a list item is due"),
    (lambda d: d.replace(b"vertex_indices", b"corners"), "line 14: the face element has no list property"),
    (lambda d: d.replace(b"format binary_little_endian 1.0", b"format binary_middle 1.0"),
     "line 2: unknown PLY format"),
    (lambda d: d.replace(b"property float nx", b"property quad nx"), "line 6: unknown property type 'quad'"),
    (lambda d: d.replace(b"end_header\n", b""), "ends without 'end_header'|unknown header keyword"),
])
def test_ply_reader_refuses_what_it_cannot_read_exactly(tmp_path, change, pattern):
    _refused(tmp_path, change(_ply_binary("little")), pattern)


def test_ply_list_lengths_are_checked_before_reading_them(tmp_path):
    """A face claiming 4 billion corners is refused at its count, not read."""
    data = bytearray(_ply_binary("little").replace(b"list uchar int vertex_indices", b"list uint int vertex_indices"))
    header_end = data.index(b"end_header\n") + len(b"end_header\n")
    # Rebuild the faces with uint counts, the first claiming 2**32 - 1 corners.
    body = bytes(data[header_end:])
    vertices_and_edge = body[:9 * 34 + 8]
    faces = struct.pack("<BI", 1, 2**32 - 1) + struct.pack("<4i", *FACES[0])
    _refused(tmp_path, bytes(data[:header_end]) + vertices_and_edge + faces, "a face of 4294967295 corners")


# --- the weld and the load of a soup ---------------------------------------------------

def _torus_soup(n=40, m=16):
    from stripweave.bench_scale import torus_grid
    v, t = torus_grid(2 * n * m)
    return v, t


def test_binary_stl_loads_welded_like_its_arrays(tmp_path):
    from stripweave.bench_scale import write_binary_stl
    v, t = _torus_soup()
    path = str(tmp_path / "torus.stl")
    write_binary_stl(path, v, t)
    raw_v, raw_t = sw.read_mesh(path)
    assert len(raw_v) == 3 * len(t)   # read as stored: three corners per triangle
    s_file = sw.load(path, target_triangles=0)
    s_arrays = sw.from_mesh(v.astype(np.float32).astype(np.float64), t, target_triangles=0)
    assert len(s_file.vertices) == len(v) and s_file.report()["genus"] == 1
    assert np.array_equal(s_file.triangles, s_arrays.triangles)
    assert np.array_equal(s_file.vertices, s_arrays.vertices)


def test_weld_merges_negative_and_positive_zero_only():
    """-0.0 == 0.0 (the std::map weld merged them); a corner moved by 1e-12 is its own vertex."""
    v, t = _torus_soup()
    corners = v[t].reshape(-1, 3).copy()
    first_half = np.arange(len(corners)) < len(corners) // 2
    corners[first_half & (corners[:, 2] == 0), 2] = -0.0
    assert np.signbit(corners[:, 2]).any()
    soup = np.arange(len(corners)).reshape(-1, 3)
    assert len(sw.from_mesh(corners, soup, target_triangles=0).vertices) == len(v)
    corners[5, 0] += 1e-12
    assert len(sw.from_mesh(corners, soup, target_triangles=0).vertices) == len(v) + 1


# --- the proxy (paper §8.1) ----------------------------------------------------------------

def box_grid(n, size=10.0, open_top=False):
    """The box [0, size]^3 as a welded grid of n x n quads per face (two triangles each),
    outward; without its top face if open_top."""
    s = np.linspace(0, size, n + 1)
    verts, tris, index = [], [], {}

    def vid(p):
        key = tuple(np.round(p, 9))
        if key not in index:
            index[key] = len(verts)
            verts.append(p)
        return index[key]

    for axis in range(3):
        for side in (0.0, size):
            if open_top and axis == 2 and side == size:
                continue
            for i in range(n):
                for j in range(n):
                    q = []
                    for a, b in ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)):
                        p = [0.0, 0.0, 0.0]
                        p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = side, s[a], s[b]
                        q.append(vid(np.array(p)))
                    if side == 0.0:
                        q = q[::-1]
                    tris += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    return np.array(verts), np.array(tris)


def test_proxy_keeps_genus_boundary_and_creases():
    """An open box of 16,000 triangles, proxied at 1,500 (simplified, then remeshed): the same
    genus, boundary loop and crease curves as the original kept as it is."""
    v, t = box_grid(40, open_top=True)
    original = sw.from_mesh(v, t, target_triangles=0)
    proxy = sw.from_mesh(v, t, target_triangles=1500)
    assert "simplify" in proxy.timings_ms and "simplify" not in original.timings_ms
    assert len(proxy.triangles) < len(t) / 5
    a, b = original.report(), proxy.report()
    assert (b["genus"], b["boundary_loops"], b["feature_curves"]) == (a["genus"], a["boundary_loops"],
                                                                      a["feature_curves"]) == (0, 1, 8)
    # The crease curves run where the original's do: every proxy crease point on a box edge.
    for curve in proxy.feature_curve_points():
        c = np.asarray(curve)
        on_faces = np.sum((np.abs(c) < 1e-9) | (np.abs(c - 10) < 1e-9), axis=1)
        assert np.all(on_faces >= 2)


def _bumpy_torus_distance(p, R=2.5):
    """Distance of points to bench_scale.torus_grid's smooth bumpy torus (the original's surface)."""
    p = np.asarray(p)
    q = np.hypot(p[:, 0], p[:, 1]) - R
    v = np.arctan2(p[:, 2], q)
    u = np.arctan2(p[:, 1], p[:, 0])
    return np.abs(np.hypot(q, p[:, 2]) - (1.0 + 0.06 * np.sin(5 * u) * np.sin(3 * v)))


def test_loop_found_on_the_proxy_lies_on_the_original():
    """A torus of 80,000 triangles proxied at 9,000: its vertices are projected onto the original,
    and best loops found on the proxy stay within 1e-3 of the diagonal from the original."""
    from stripweave.bench_scale import torus_grid
    from stripweave.loops import LoopSession
    v, t = torus_grid(80000)
    proxy = sw.from_mesh(v, t, target_triangles=9000)
    assert "project" in proxy.timings_ms
    diagonal = proxy.report()["bbox_diagonal"]
    # The original's own facets lie within its chord error of the smooth torus.
    corners = v[t]
    chord = max(_bumpy_torus_distance(corners.mean(axis=1)).max(),
                *(_bumpy_torus_distance(0.5 * (corners[:, i] + corners[:, (i + 1) % 3])).max() for i in range(3)))
    assert _bumpy_torus_distance(proxy.vertices).max() < chord + 1e-9 * diagonal
    session = LoopSession(proxy)
    for point in [(3.5, 0, 0), (0, 2.5, 1.0), (-1.5, 0, 0), (2.1213, 2.1213, 0.866)]:
        loop = session.best_loop(point)
        assert _bumpy_torus_distance(loop["points"]).max() + chord < 1e-3 * diagonal


def test_refit_deviation_sees_a_bump_only_the_original_has():
    """A closed box of 19,200 triangles with one vertex of its top raised by 0.1 (one grid cell
    wide: below the 2,000-triangle proxy's resolution): the fit is measured against the
    original, so its deviation shows the bump; without it the fit is exact."""
    from stripweave.design import Design
    from stripweave.strips import DesignSession
    from stripweave.surfacing import fit_report, refit_design
    belts = [[(5, 5, 10, 1, 0, 0)], [(5, 3, 0, 0, 1, 0)], [(3, 0, 5, 1, 0, 0)]]
    v, t = box_grid(40)

    def fit(vertices):
        proxy = sw.from_mesh(vertices, t, target_triangles=2000)
        assert "simplify" in proxy.timings_ms
        return proxy, fit_report(refit_design(DesignSession(proxy, Design(belts))))

    _, flat = fit(v)
    assert flat["max_deviation"] < 1e-6
    bumped = v.copy()
    top = np.argmin(np.linalg.norm(v - [5.25, 5.25, 10], axis=1))
    bumped[top, 2] += 0.1
    proxy, fit_bumped = fit(bumped)
    assert fit_bumped["max_deviation"] > max(0.02, fit_bumped["tolerance"])
    assert not fit_bumped["tolerance_met"]


def test_bench_scale_reports_every_figure_against_the_numpy_floor():
    """`bench --scale` on one small size, without the weave (figures, not timed assertions)."""
    from stripweave.bench_scale import run_scale
    result = run_scale(sizes=(20000,), weave=False)
    (entry,) = result["scale"]
    assert "load_error" not in entry, entry
    assert abs(entry["input_triangles"] - 20000) < 200 and entry["proxy_triangles"] > 0
    for key in ("floor_s", "load_s", "proxy_s", "graph_s"):
        assert entry[key] > 0
    assert entry["load_ratio"] == pytest.approx(entry["load_s"] / entry["floor_s"], rel=0.05, abs=0.01)
    assert 0 < entry["hover_ms"]["median"] <= entry["hover_ms"]["p95"] and entry["hover_ms"]["runs"] == 50
    assert entry["load_peak_mb"] > 0
