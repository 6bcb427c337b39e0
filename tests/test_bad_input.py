"""Bad input: every case gets a clear error naming the problem, or a documented
repair with a warning that counts what was repaired. Nothing crashes."""
import numpy as np
import pytest

import stripweave as sw
from models import box

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TET_T = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)


def closed_box_mesh():
    s = sw.from_shape(box(10), target_triangles=0)
    return s.vertices.copy(), s.triangles.copy()


# --- files ---------------------------------------------------------------------

@pytest.mark.parametrize("name", ["missing.step", "missing.stl", "missing.obj"])
def test_missing_file(tmp_path, name):
    with pytest.raises(sw.InputError, match="does not exist"):
        sw.load(str(tmp_path / name))


@pytest.mark.parametrize("name", ["empty.step", "empty.stl", "empty.off", "empty.ply", "empty.obj"])
def test_empty_file(tmp_path, name):
    (tmp_path / name).write_bytes(b"")
    with pytest.raises(sw.InputError, match="empty"):
        sw.load(str(tmp_path / name))


@pytest.mark.parametrize("name,expected", [("broken.step", "STEP"), ("broken.igs", "IGES"), ("broken.brep", "BREP"),
                                           ("broken.off", "OFF"), ("broken.ply", "PLY")])
def test_garbage_file(tmp_path, name, expected):
    (tmp_path / name).write_text("this is not a model\n" * 20)
    with pytest.raises(sw.InputError, match=expected):
        sw.load(str(tmp_path / name))


def test_unknown_format(tmp_path):
    (tmp_path / "model.xyz").write_text("1 2 3\n")
    with pytest.raises(sw.InputError, match="unknown"):
        sw.load(str(tmp_path / "model.xyz"))


def test_step_round_trip_of_a_generated_part(tmp_path):
    path = str(tmp_path / "box.step")
    box(10).exportStep(path)
    r = sw.load(path, target_triangles=2000).report()
    assert (r["brep_faces"], r["feature_curves"], r["genus"]) == (6, 12, 0)


# --- shapes ----------------------------------------------------------------------

def test_shape_without_faces():
    import Part
    from FreeCAD import Vector
    wire = Part.makePolygon([Vector(0, 0, 0), Vector(1, 0, 0), Vector(1, 1, 0)])
    with pytest.raises(sw.InputError, match="no faces"):
        sw.from_shape(wire)


def test_broken_brep_text():
    with pytest.raises(sw.InputError, match="BREP"):
        sw.from_shape("DBRep_DrawableShape\nCASCADE Topology V1, (c) Matra-Datavision\nLocations 3\ngarbage")


def test_non_manifold_shape():
    """Two boxes fused with their shared face kept: its edges have four faces."""
    import Part
    from FreeCAD import Vector
    a = Part.makeBox(10, 10, 10)
    b = Part.makeBox(10, 10, 10, Vector(10, 0, 0))
    shared = a.generalFuse([b])[0]
    with pytest.raises(sw.InputError, match="non-manifold"):
        sw.from_shape(shared)


def test_several_components_are_kept_and_reported():
    import Part
    from FreeCAD import Vector
    two = Part.makeCompound([Part.makeBox(10, 10, 10), Part.makeBox(10, 10, 10, Vector(30, 0, 0))])
    r = sw.from_shape(two, target_triangles=4000).report()
    assert r["components"] == 2
    assert r["feature_curves"] == 24
    assert r["genus"] == 0


# --- meshes ----------------------------------------------------------------------

def test_nan_coordinates():
    v = TET_V.copy()
    v[2, 1] = np.nan
    with pytest.raises(sw.InputError, match="NaN"):
        sw.from_mesh(v, TET_T, target_triangles=0)


def test_index_out_of_range():
    t = TET_T.copy()
    t[1, 2] = 7
    with pytest.raises(sw.InputError, match="refers to vertex 7"):
        sw.from_mesh(TET_V, t, target_triangles=0)


def test_no_triangles():
    with pytest.raises(sw.InputError, match="no triangles"):
        sw.from_mesh(TET_V, np.zeros((0, 3), dtype=np.int32), target_triangles=0)


def test_wrong_array_shapes():
    with pytest.raises(sw.InputError, match=r"\(N, 3\)"):
        sw.from_mesh(TET_V[:, :2], TET_T)


def test_non_manifold_edge():
    """A fin: a third triangle on an edge of the tetrahedron."""
    v = np.vstack([TET_V, [[0.5, -1, 0]]])
    t = np.vstack([TET_T, [[0, 1, 4]]]).astype(np.int32)
    with pytest.raises(sw.InputError, match="non-manifold mesh: 1 edge is shared by more than two triangles"):
        sw.from_mesh(v, t, target_triangles=0)


def test_non_manifold_vertex_is_split_with_a_warning():
    """Two tetrahedra touching at one vertex: the vertex is split, two closed components remain."""
    v = np.vstack([TET_V, TET_V[1:] * -1.0])
    second = TET_T.copy()
    second[second > 0] += 3
    second = second[:, ::-1]  # mirrored: keep it outward
    t = np.vstack([TET_T, second]).astype(np.int32)
    r = sw.from_mesh(v, t, target_triangles=0).report()
    assert any("1 non-manifold (pinched) vertex" in w for w in r["warnings"])
    assert r["components"] == 2
    assert r["vertices"] == 8
    assert r["boundary_loops"] == 0


def test_degenerate_triangles_are_removed_with_a_warning():
    v, t = closed_box_mesh()
    t = np.vstack([t, [[0, 0, 5]], [[3, 7, 3]]]).astype(np.int32)
    r = sw.from_mesh(v, t, target_triangles=0).report()
    assert any("removed 2 degenerate triangles" in w for w in r["warnings"])
    assert r["boundary_loops"] == 0 and r["genus"] == 0


def test_zero_area_triangle_is_repaired_without_opening_a_hole():
    """A cap: vertex 4 on the middle of edge (0,1) of a closed tetrahedron-like mesh."""
    # Square pyramid whose base edge (0,1) carries a point 4 on it.
    v = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [1, 0, 0], [1, 1, 2]], dtype=float)
    t = np.array([[0, 4, 5], [4, 1, 5], [1, 2, 5], [2, 3, 5], [3, 0, 5],  # sides, (0,1) split at 4
                  [0, 1, 4],  # the cap: zero area
                  [0, 2, 1], [0, 3, 2]], dtype=np.int32)  # base
    r = sw.from_mesh(v, t, target_triangles=0).report()
    assert any("zero-area" in w for w in r["warnings"])
    assert r["boundary_loops"] == 0
    assert r["triangles"] == 8


def test_duplicate_triangles_are_removed_with_a_warning():
    v, t = closed_box_mesh()
    t = np.vstack([t, t[:3], t[5:6, ::-1]]).astype(np.int32)
    r = sw.from_mesh(v, t, target_triangles=0).report()
    assert any("removed 4 duplicate triangles" in w for w in r["warnings"])
    assert r["boundary_loops"] == 0


def test_inconsistent_orientation_is_fixed():
    v, t = closed_box_mesh()
    t[::3] = t[::3, ::-1]
    s = sw.from_mesh(v, t, target_triangles=0)
    r = s.report()
    assert any("flipped" in w for w in r["warnings"])
    tv = s.vertices[s.triangles]
    n = np.cross(tv[:, 1] - tv[:, 0], tv[:, 2] - tv[:, 0])
    assert np.all(np.sum(n * (tv.mean(axis=1) - 5.0), axis=1) > 0)  # all outward


def test_non_orientable_surface():
    """A Moebius strip."""
    n = 24
    u = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = lambda w: np.stack([(3 + w * np.cos(u / 2)) * np.cos(u), (3 + w * np.cos(u / 2)) * np.sin(u),
                               w * np.sin(u / 2)], axis=1)
    v = np.vstack([ring(-1), ring(1)])
    t = []
    for i in range(n):
        j = (i + 1) % n
        a, b, c, d = i, j, n + j, n + i
        if j == 0:  # the half twist glues the last column to the first one upside down
            b, c = n + 0, 0
        t += [[a, b, c], [a, c, d]]
    with pytest.raises(sw.InputError, match="not orientable"):
        sw.from_mesh(v, np.array(t, dtype=np.int32), target_triangles=0)


def test_tiny_debris_is_dropped_with_a_warning():
    v, t = closed_box_mesh()
    debris_v = TET_V * 0.01 + 20
    v2 = np.vstack([v, debris_v])
    t2 = np.vstack([t, TET_T + len(v)]).astype(np.int32)
    r = sw.from_mesh(v2, t2, target_triangles=0).report()
    assert any("tiny disconnected piece" in w for w in r["warnings"])
    assert r["components"] == 1


def test_cancel_stops_a_build():
    p = sw.Progress()
    p.cancel()
    with pytest.raises(sw.Cancelled):
        sw.from_shape(box(10), progress=p)
