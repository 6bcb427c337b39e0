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
