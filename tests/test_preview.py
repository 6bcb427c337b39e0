"""The preview pictures' native rasterizer and shader (render/rasterize.h, render/shade.h):
which triangle each pixel shows, where in it and how deep, and its colour (Lambert, tints,
stripe lines), for scenes whose answer is known in closed form."""
import numpy as np
import pytest

from stripweave._native import native


def test_square_covers_its_pixels_and_the_nearer_square_wins():
    # Two axis-aligned squares of two triangles each: the far one from (2, 2) to (12, 12)
    # at depth 5, the near one from (6, 6) to (16, 16) at depth 1, in a 20 x 20 image.
    screen = np.array([[2, 2, 5], [12, 2, 5], [12, 12, 5], [2, 12, 5],
                       [6, 6, 1], [16, 6, 1], [16, 16, 1], [6, 16, 1]], float)
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    tri, bary, depth = native.rasterize(screen, tris, 20, 20)
    tri, depth = tri.reshape(20, 20), depth.reshape(20, 20)
    # Pixel centres (x + 0.5, y + 0.5) inside [2, 12]^2 or [6, 16]^2: 10 x 10 each,
    # overlapping in 6 x 6.
    assert (tri >= 0).sum() == 100 + 100 - 36
    assert np.all(tri[6:16, 6:16] >= 2)                      # the near square in front
    assert np.allclose(depth[6:16, 6:16], 1.0)
    assert np.all(tri[2:6, 2:12] <= 1) and np.allclose(depth[2:6, 2:12], 5.0)
    assert np.all(tri[:2] == -1) and np.all(np.isinf(depth[:2]))
    # Barycentrics reproduce the pixel centre.
    hit = np.nonzero(tri.ravel() >= 0)[0]
    t = tris[tri.ravel()[hit]]
    p = (bary[hit, :, None] * screen[t][:, :, :2]).sum(1)
    centre = np.stack([hit % 20 + 0.5, hit // 20 + 0.5], 1)
    assert np.abs(p - centre).max() < 1e-9
    assert np.allclose(bary[hit].sum(1), 1.0)


def test_the_raster_is_handed_to_numpy_and_shaded_where_it_lies():
    """A supersampled view's raster is tens of MB: rasterize hands its buffers to numpy (the
    arrays own them, no copy) and shade reads them in place (the triangle per pixel as
    int32, as rasterize gives it)."""
    screen = np.array([[0, 0, 1], [30, 0, 1], [0, 30, 1]], float)
    tri, bary, depth = native.rasterize(screen, np.array([[0, 1, 2]]), 32, 32)
    assert tri.dtype == np.int32 and tri.flags.c_contiguous and bary.shape == (32 * 32, 3)
    for a in (tri, bary, depth):
        assert a.base is not None and not a.flags.owndata   # a view of the native buffer
    normals = np.tile([0.0, 0.0, 1.0], (3, 1))
    args = (screen, normals, np.array([[0, 1, 2]]), [0.0, 0.0, 1.0], [0.5, 0.5, 0.5], [1.0, 1.0, 1.0])
    rgb = native.shade(tri, bary, *args)
    assert rgb.shape == (32 * 32, 3) and not rgb.flags.owndata
    assert np.allclose(rgb[tri >= 0], 0.5) and np.allclose(rgb[tri < 0], 1.0)
    del bary, depth
    assert np.array_equal(native.shade(tri.astype(np.int64), native.rasterize(screen, np.array([[0, 1, 2]]), 32, 32)[1],
                                       *args), rgb)


def test_disc_area_and_both_orientations():
    # A disc of radius 40 pixels as a fan, wound clockwise: its pixel count is its area.
    n = 256
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    screen = np.concatenate([[[50, 50, 0]], np.stack([50 + 40 * np.cos(a), 50 - 40 * np.sin(a), np.zeros(n)], 1)])
    tris = np.array([[0, 1 + (i + 1) % n, 1 + i] for i in range(n)])
    tri, _, _ = native.rasterize(screen, tris, 100, 100)
    assert abs((tri >= 0).sum() - np.pi * 40 ** 2) < 0.01 * np.pi * 40 ** 2


def test_bad_input_is_named():
    with pytest.raises(native.InputError, match="names vertex 7"):
        native.rasterize(np.zeros((3, 3)), np.array([[0, 1, 7]]), 4, 4)
    with pytest.raises(native.InputError, match=r"\(n, 3\)"):
        native.rasterize(np.zeros((3, 2)), np.array([[0, 1, 2]]), 4, 4)


def _flat_square(n=40):
    """A square in the plane z = 0 filling an n x n image, normals +z: screen = model."""
    screen = np.array([[0, 0, 0], [n, 0, 0], [n, n, 0], [0, n, 0]], float)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    normals = np.tile([0.0, 0.0, 1.0], (4, 1))
    return screen, tris, normals


def test_shading_is_lambert_on_the_base_and_tint():
    screen, tris, normals = _flat_square()
    tri, bary, _ = native.rasterize(screen, tris, 40, 40)
    base, background = [0.8, 0.82, 0.85], [1.0, 1.0, 1.0]
    light = np.array([0.0, 0.6, 0.8])             # |n . light| = 0.8
    rgb = native.shade(tri, bary, screen, normals, tris, light.tolist(), base, background)
    assert np.allclose(rgb, np.array(base) * (0.35 + 0.65 * 0.8))
    # A tint on the second triangle only: 45:55 with the base there.
    tints = np.array([[np.nan] * 3, [1.0, 0.0, 0.0]])
    rgb = native.shade(tri, bary, screen, normals, tris, light.tolist(), base, background, tints)
    second = tri == 1
    assert np.allclose(rgb[second], (0.45 * np.array(base) + 0.55 * np.array([1.0, 0, 0])) * 0.87)
    assert np.allclose(rgb[~second], np.array(base) * 0.87)
    # Pixels no triangle covers show the background.
    tri[:5] = -1
    assert np.allclose(native.shade(tri, bary, screen, normals, tris, light.tolist(), base, background)[:5], 1.0)


def test_stripes_are_lines_at_multiples_of_the_period():
    # A strip whose coordinate across is x: stripe lines at x = 0, 10, 20, ... (period 10),
    # each in the strip's hue at 0.6 where it is exactly on the line, none a quarter period off.
    screen, tris, normals = _flat_square()
    tri, bary, _ = native.rasterize(screen, tris, 40, 40)
    coords = np.stack([screen[tris][:, :, 1], screen[tris][:, :, 0]], 2)   # (along, across) = (y, x)
    base, hue = [0.8, 0.8, 0.8], [0.0, 0.0, 1.0]
    rgb = native.shade(tri, bary, screen, normals, tris, [0.0, 0.0, 1.0], base, [1.0, 1.0, 1.0],
                       stripes=[coords], hues=[hue], stripe_period=10.0).reshape(40, 40, 3)
    x = np.arange(40) + 0.5                        # pixel centres
    phase = np.abs((x / 10 + 0.5) % 1.0 - 0.5)
    line = np.clip(1.6 - 8 * phase, 0, 1) * 0.6
    expect = np.array(base) * (1 - line[:, None]) + np.array(hue) * line[:, None]
    assert np.allclose(rgb[17], expect)            # every row alike
    assert line[np.argmin(np.abs(x - 10.5))] > 0.3 and line[np.argmin(np.abs(x - 15.5))] == 0


def test_shading_bad_input_is_named():
    screen, tris, normals = _flat_square()
    tri, bary, _ = native.rasterize(screen, tris, 8, 8)
    with pytest.raises(native.InputError, match="one normal per vertex"):
        native.shade(tri, bary, screen, normals[:3], tris, [0, 0, 1.0], [1, 1, 1.0], [1, 1, 1.0])
    with pytest.raises(native.InputError, match="one hue per strip"):
        native.shade(tri, bary, screen, normals, tris, [0, 0, 1.0], [1, 1, 1.0], [1, 1, 1.0],
                     stripes=[np.zeros((2, 3, 2))])


def test_stripe_strength_scales_the_stripe_line():
    screen, tris, normals = _flat_square()
    tri, bary, _ = native.rasterize(screen, tris, 40, 40)
    coords = np.stack([screen[tris][:, :, 1], screen[tris][:, :, 0]], 2)
    args = (tri, bary, screen, normals, tris, [0.0, 0.0, 1.0], [0.8, 0.8, 0.8], [1.0, 1.0, 1.0])
    strong = native.shade(*args, stripes=[coords], hues=[[0.0, 0.0, 1.0]], stripe_period=10.0)
    weak = native.shade(*args, stripes=[coords], hues=[[0.0, 0.0, 1.0]], stripe_period=10.0, stripe_strength=0.2)
    # The red channel is 0.8 (1 - line): the line's share is a third of the default's.
    assert np.allclose(0.8 - weak[:, 0], (0.8 - strong[:, 0]) * 0.2 / 0.6)
    with pytest.raises(native.InputError, match="stripe strength"):
        native.shade(*args, stripe_strength=1.5)


# --- the pictures (preview.py, raster_text.py) ------------------------------------

from types import SimpleNamespace  # noqa: E402

from stripweave import preview  # noqa: E402
from stripweave.raster_text import CELL_H, CELL_W, GLYPHS, draw_text, text_mask, text_size  # noqa: E402

PANEL_H, PANEL_W = preview.HEIGHT - preview.LEGEND_H, preview.WIDTH // 2


def grid_square(n=10, size=10.0):
    """The square [0, size]^2 in z = 0 as n x n cells of two triangles, normals +z."""
    x, y = np.meshgrid(np.linspace(0, size, n + 1), np.linspace(0, size, n + 1))
    v = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], 1)
    i = np.arange(n * (n + 1)).reshape(n, n + 1)[:, :n].ravel()
    tris = np.concatenate([np.stack([i, i + 1, i + n + 2], 1), np.stack([i, i + n + 2, i + n + 1], 1)])
    return v, tris, np.tile([0.0, 0.0, 1.0], (len(v), 1))


def box_mesh(lo, hi):
    """An axis-aligned box, 4 vertices per face (outward normals), 12 triangles."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    verts, tris, normals = [], [], []
    for axis in range(3):
        for side in (0, 1):
            a, b = [k for k in range(3) if k != axis]
            n = np.zeros(3)
            n[axis] = 1 if side else -1
            quad = []
            for u, w in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = lo.copy()
                p[axis] = hi[axis] if side else lo[axis]
                p[a] = hi[a] if u else lo[a]
                p[b] = hi[b] if w else lo[b]
                quad.append(p)
            k = len(verts)
            verts += quad
            normals += [n] * 4
            t = [[k, k + 1, k + 2], [k, k + 2, k + 3]]
            if np.cross(quad[1] - quad[0], quad[2] - quad[0]) @ n < 0:
                t = [[k, k + 2, k + 1], [k, k + 3, k + 2]]
            tris += t
    return np.array(verts), np.array(tris), np.array(normals)


def frustum(r0, r1, h, axis=2, n=64):
    """A closed cone frustum, radius r0 at 0 and r1 at h along `axis` (0, 1 or 2)."""
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = lambda r, z: np.stack([r * np.cos(a), r * np.sin(a), np.full(n, z)], 1)  # noqa: E731
    v = np.concatenate([ring(r0, 0), ring(r1, h), [[0, 0, 0], [0, 0, h]]])
    i, j = np.arange(n), (np.arange(n) + 1) % n
    tris = np.concatenate([np.stack([i, j, n + j], 1), np.stack([i, n + j, n + i], 1),
                           np.stack([np.full(n, 2 * n), j, i], 1), np.stack([np.full(n, 2 * n + 1), n + i, n + j], 1)])
    v = v[:, {2: [0, 1, 2], 1: [1, 2, 0], 0: [2, 0, 1]}[axis]]   # z -> axis, a cyclic (orientation-keeping) swap
    normals = v - v.mean(0)
    return v, tris, normals / np.linalg.norm(normals, axis=1, keepdims=True)


def find_text(image, text, colour, scale=preview.TEXT):
    """Top-left corners (x, y) where the text's ink is drawn in `colour` (uint8 image), its
    paper pixels not in that colour: the text exactly, wherever it is."""
    ink = np.all(np.abs(image.astype(int) - np.round(np.asarray(colour) * 255)) <= 1, axis=2)
    mask = text_mask(text, scale)
    ys, xs = np.nonzero(mask)
    fy, fx = ys[0], xs[0]          # the first ink pixel of the text
    found = []
    for y, x in zip(*np.nonzero(ink)):
        y0, x0 = y - fy, x - fx
        if y0 < 0 or x0 < 0 or y0 + mask.shape[0] > ink.shape[0] or x0 + mask.shape[1] > ink.shape[1]:
            continue
        if np.array_equal(ink[y0:y0 + mask.shape[0], x0:x0 + mask.shape[1]], mask):
            found.append((x0, y0))
    return found


def panels(image):
    """The two views' pixels (front, back), without their label rows and the line between them;
    column c of the front and PANEL_W - 3 - c of the back are mirror images."""
    return image[40:PANEL_H, :PANEL_W - 2], image[40:PANEL_H, PANEL_W + 2:2 * PANEL_W]


def drawn(panel):
    """The part's pixels: not background, not the axis triad."""
    triad = [np.all(np.abs(panel.astype(int) - np.array(c) * 255) <= 2, axis=2) for c in preview.AXIS_COLOURS]
    return np.any(panel < 250, axis=2) & ~np.any(triad, axis=0)


def hue_share(panel, colour, cos=0.999):
    """Per pixel whether its colour points the way the tint as drawn does (any shading)."""
    c = preview.tint_as_drawn(colour)
    px = panel.astype(float)
    norm = np.linalg.norm(px, axis=2)
    return (px @ (c / np.linalg.norm(c))) > cos * np.maximum(norm, 1e-9)


def test_font_draws_glyphs_and_clips():
    assert text_mask("A", 1).shape == (CELL_H, CELL_W) and text_size("abc", 3) == (3 * CELL_W * 3, CELL_H * 3)
    m = text_mask("Hi", 2)
    assert np.array_equal(m[2:2 + 14:2, 0:10:2], GLYPHS["H"][:7])      # row 0 of the cell is space
    assert np.array_equal(text_mask("\u00e9", 1), text_mask("?", 1))     # no glyph: '?'
    assert len({GLYPHS[c].tobytes() for c in GLYPHS}) == len(GLYPHS)    # every glyph distinct
    img = np.zeros((10, 10, 3))
    draw_text(img, "WWWW", -3, -4, (1, 1, 1), 2)                        # clipped, no error
    assert img.sum() > 0


def test_legend_and_view_labels_are_drawn():
    v, t, n = box_mesh((0, 0, 0), (4, 3, 2))
    items = [("line", preview.EDGE, "patch edge"), ("hatch", preview.MARK, "defective patch: 1")]
    img, (front, back) = preview.picture(preview.Scene(v, t, n), items)
    assert img.shape == (preview.HEIGHT, preview.WIDTH, 3)
    ink = preview.INK
    (x, y), = find_text(img, "patch edge", ink)
    assert y >= PANEL_H                                                 # in the legend band
    (hx, hy), = find_text(img, "defective patch: 1", ink)
    swatch = img[hy:hy + 20, hx - 34:hx - 4]                            # its icon: the hatch
    assert np.any(np.all(np.abs(swatch.astype(int) - preview.MARK * 255) < 2, axis=2))
    (lx, ly), = find_text(img, "front: from", ink)
    (rx, ry), = find_text(img, "back: from", ink)
    assert ly < 40 and ry < 40 and lx < PANEL_W <= rx


def test_front_and_back_are_opposite_views_from_above_and_below():
    # An L: a block with a tower on its +x end, asymmetric in every mirror but the plane y = 1.5.
    a, b = box_mesh((0, 0, 0), (6, 3, 2)), box_mesh((4, 0, 2), (6, 3, 5))
    v = np.concatenate([a[0], b[0]])
    t = np.concatenate([a[1], b[1] + len(a[0])])
    n = np.concatenate([a[2], b[2]])
    normal_z = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])[:, 2]
    tints = np.full((len(t), 3), np.nan)
    tints[normal_z > 0] = preview.TINTS["red"]        # faces looking up
    tints[normal_z < 0] = (0.1, 0.2, 0.9)             # faces looking down
    img, (front, back) = preview.picture(preview.Scene(v, t, n, tints=tints), [])
    assert np.allclose(front, -back) and front[2] > 0.5
    f, k = panels(img)
    # Orthographic views from opposite sides with one up: mirror images of one silhouette.
    mf, mk = drawn(f), drawn(k)
    iou = lambda p, q: (p & q).sum() / (p | q).sum()  # noqa: E731
    assert iou(mk, mf[:, ::-1]) > 0.97 and iou(mf, mf[:, ::-1]) < 0.9
    up_f, up_k = hue_share(f, preview.TINTS["red"]), hue_share(k, preview.TINTS["red"])
    down_f, down_k = hue_share(f, (0.1, 0.2, 0.9)), hue_share(k, (0.1, 0.2, 0.9))
    assert up_f.sum() > 5000 and down_f.sum() == 0      # the front sees the tops only
    assert down_k.sum() > 5000 and up_k.sum() == 0      # the back the bottoms only


@pytest.mark.parametrize("axis", [2, 1])
def test_a_tall_part_stands_upright_in_both_views(axis):
    # A frustum 12 tall, radius 3 at its base and 1 at its top, along z and along y (a mesh
    # modelled y-up: its base is its clear foot, up_axis takes +y).
    v, t, n = frustum(3.0, 1.0, 12.0, axis=axis)
    assert preview.up_axis(v)[0] == ("+z" if axis == 2 else "+y")
    img, _ = preview.picture(preview.Scene(v, t, n), [])
    for p in panels(img):
        rows, cols = np.nonzero(drawn(p))
        assert rows.ptp() > 2.0 * cols.ptp()                          # its long axis vertical
        r0, r1 = rows.min(), rows.max()
        width = lambda r: np.ptp(cols[rows == r])  # noqa: E731
        q = (r1 - r0) // 5
        assert width(r1 - q) > 1.8 * width(r0 + q)                    # the wide base at the bottom


def test_up_is_z_unless_another_side_is_clearly_the_base():
    v, _, _ = box_mesh((0, 0, 0), (2, 3, 10))          # a tall box: every side as much a base
    assert preview.up_axis(v)[0] == "+z"
    v, _, _ = frustum(1.0, 3.0, 12.0)                  # wide at its top: still as modelled
    assert preview.base_share(v, (0, 0, -1)) > 0.9 > 0.3 > preview.base_share(v, (0, 0, 1))
    assert preview.up_axis(v)[0] == "+z"
    v, _, _ = frustum(3.0, 1.0, 12.0, axis=0)
    assert preview.up_axis(v)[0] == "+x"
    assert preview.base_share(v, (1, 0, 0)) > 0.9 > 0.3 > preview.base_share(v, (0, 0, 1))


def test_patch_edges_are_drawn_dark_over_dim_stripes():
    v, t, n = grid_square()
    across = v[t][:, :, 0]                              # stripes across x, every 0.5
    stripes = [np.stack([v[t][:, :, 1], across], 2)]
    scene = preview.Scene(v, t, n, stripes=stripes, lines=[[(0, 5, 0), (10, 5, 0)]], stripe_period=0.5)
    img = preview.render_view(scene, np.array([0, 0, 1.0]), 200, 200)   # up +y: model y = 5 is row 100
    row = img[100, 20:180]
    assert row.max() < 0.15                              # the edge: dark all along, stripes or not
    off = img[120, 20:180]
    assert off.max() - off.min() > 0.05                  # stripes are drawn there ...
    assert off.min() > 0.45                              # ... at low contrast


def test_a_view_drawn_in_bands_is_the_view_drawn_whole(monkeypatch):
    """render_view draws a view band by band (memory): with a margin past every mark's reach,
    each pixel comes out as when the whole view is drawn at once, marks across the band
    boundaries (a ring centred on one, the hatch, lines and stripes over them) included."""
    v, t, n = grid_square()
    v = v.copy()
    v[:, 2] = 0.3 * np.sin(v[:, 0]) * np.cos(v[:, 1])    # not flat: depths and shading vary
    stripes = [np.stack([v[t][:, :, 1], v[t][:, :, 0]], 2)]
    hatch = np.zeros(len(t), bool)
    hatch[::3] = True
    scene = preview.Scene(v, t, n, stripes=stripes, lines=[[(0, 5, 0.5), (10, 5.1, 0.5)], [(5, 0, 0.5), (5, 10, 0.5)]],
                          thin_lines=[[(0, 2, 0.5), (10, 8, 0.5)]], hatch=hatch,
                          rings=np.array([[5.0, 5.0, 0.0], [2.0, 6.7, 0.0]]), stripe_period=0.5)
    view = np.array([0.3, -0.4, 1.0])
    monkeypatch.setattr(preview, "BANDS", 1)
    whole = preview.render_view(scene, view, 160, 150)
    for bands in (2, 3, 7):
        monkeypatch.setattr(preview, "BANDS", bands)
        assert np.array_equal(preview.render_view(scene, view, 160, 150), whole), bands


def _fake_session(v, t, n):
    """What render_design and render_deviation read of a DesignSession: the surface, no strips."""
    s = SimpleNamespace(vertices=v, triangles=t, normals=n)
    return SimpleNamespace(surface=s, native=SimpleNamespace(strip_count=0), strips=lambda: [])


def _halves(v, t):
    """Layout details of the grid square as two patches, x < 5 and x > 5, one edge between."""
    centre = v[t].mean(1)
    return {"regions": [{"colour": "none"}], "triangle_region": np.zeros(len(t), int),
            "parent_triangle": np.arange(len(t)), "patch_of_triangle": (centre[:, 0] > 5).astype(int),
            "patches": [{"quad": True}, {"quad": True}],
            "edges": [{"points": np.array([(5.0, 0, 0), (5.0, 10, 0)])}]}


def _capture(monkeypatch):
    images = []
    monkeypatch.setattr(preview, "write_png", lambda path, image: images.append(image))
    return images


def is_mark(panel):
    return np.all(np.abs(panel.astype(int) - preview.MARK * 255) <= 2, axis=2)


def test_defective_patches_and_vertices_are_marked(monkeypatch):
    v, t, n = grid_square()
    details = _halves(v, t)
    layout = {"edges": [{"points": [(5.0, 0, 0), (5.0, 10, 0)]}],
              "patches": [{"defects": ["non_quad", "creased"]}, {"defects": []}],
              "vertices": [{"position": [7.5, 5.0, 0.0], "defects": ["valence2"]},
                           {"position": [5.0, 0.0, 0.0], "defects": []}]}
    hatch, rings = preview.defect_marks(layout, details, len(t))
    assert np.array_equal(hatch, v[t].mean(1)[:, 0] < 5) and np.allclose(rings, [[7.5, 5.0, 0.0]])
    images = _capture(monkeypatch)
    preview.render_design("unused.png", _fake_session(v, t, n), layout, regions=details, view=(0, 0, 1))
    img = images[-1]
    front = img[:PANEL_H, :PANEL_W]
    project, _ = preview.camera((0, 0, 1), v, PANEL_W, PANEL_H)
    ys, xs = np.nonzero(is_mark(front))
    centre = project(np.array([[5.0, 5.0, 0.0], [7.5, 5.0, 0.0]]))[:, :2]
    hatched = xs < centre[0, 0] - 2
    assert hatched.sum() > 500                            # the hatch over the defective half ...
    ring = np.hypot(xs - centre[1, 0], ys - centre[1, 1])
    assert np.all(ring[~hatched] < 8.5) and (~hatched).sum() > 30   # ... and a ring, nothing else
    assert find_text(img, "defective patch: 1 (creased 1, non quad 1)", preview.INK)
    assert find_text(img, "defective vertex: 1 (valence2 1)", preview.INK)
    # A layout that lists no defects (no "defects" keys): no marks, no such legend.
    for x in layout["patches"] + layout["vertices"]:
        del x["defects"]
    assert preview.defect_marks(layout, details, len(t))[0] is None
    preview.render_design("unused.png", _fake_session(v, t, n), layout, regions=details, view=(0, 0, 1))
    assert not is_mark(images[-1]).any() and not find_text(images[-1], "defective", preview.INK)


def test_colour_bar_is_in_model_units(monkeypatch):
    v, t, n = grid_square()
    details = _halves(v, t)
    fit = {"tolerance": 0.25, "per_patch": [{"max_deviation": 0.1}, {"max_deviation": 0.6}],
           "max_deviation": 0.6, "coverage": 0.98765}
    images = _capture(monkeypatch)
    preview.render_deviation("unused.png", _fake_session(v, t, n), fit, details=details)
    img = images[-1]
    xs = []
    for label in ("0", "0.125", "0.25", "0.375", "0.5"):      # 0 .. 2 x tolerance, model units
        hits = [(x, y) for x, y in find_text(img, label, preview.INK) if y > PANEL_H + 30]
        assert hits, label
        xs.append(min(hits)[0] + text_size(label)[0] / 2)
    assert np.all(np.diff(xs) > 50)                             # in order along the bar
    assert np.ptp(np.diff(xs)) < 3                              # evenly spaced: a linear scale
    (tx, ty), = find_text(img, "tolerance", preview.INK)
    assert abs(tx + text_size("tolerance")[0] / 2 - xs[2]) < 3   # under the tolerance's tick
    assert find_text(img, "uncovered (>50%)", preview.INK)
    assert find_text(img, "max deviation 0.6", preview.INK) and find_text(img, "coverage 98.77%", preview.INK)


def test_uncovered_colour_is_exactly_where_uncovered_says(monkeypatch):
    v, t, n = grid_square()
    details = _halves(v, t)
    details["patches"][1]["quad"] = False                       # the right half was not fitted
    fit = {"tolerance": 1.0, "per_patch": [{"max_deviation": 0.0}]}
    c = v[t].mean(1)
    uncovered = np.where(c[:, 1] < 3, 0.9, np.where(c[:, 1] < 4, 0.5, 0.0))   # 0.5 is not over half
    tints = preview.patch_deviation_tints(details, fit, len(t), uncovered)
    blue = np.all(tints == preview.UNCOVERED, axis=1)
    assert np.array_equal(blue, (c[:, 1] < 3) & (c[:, 0] < 5))
    assert np.all(tints[c[:, 0] > 5] == preview.NOT_FITTED)     # not fitted keeps its colour
    with pytest.raises(native.InputError, match="one fraction per surface triangle"):
        preview.patch_deviation_tints(details, fit, len(t), uncovered[:-1])
    images = _capture(monkeypatch)
    preview.render_deviation("unused.png", _fake_session(v, t, n), fit, details=details, uncovered=uncovered,
                             view=(0, 0, 1))
    front = images[-1][:PANEL_H, :PANEL_W]
    project, _ = preview.camera((0, 0, 1), v, PANEL_W, PANEL_H)
    (x0, y1), (x1, y0) = project(np.array([[0.0, 0, 0], [5.0, 3, 0]]))[:, :2]
    hit = hue_share(front, preview.UNCOVERED)
    ys, xs = np.mgrid[0:PANEL_H, 0:PANEL_W]
    inside = (xs > x0 + 3) & (xs < x1 - 3) & (ys > y0 + 3) & (ys < y1 - 3)
    outside = ~((xs > x0 - 3) & (xs < x1 + 3) & (ys > y0 - 3) & (ys < y1 + 3))
    assert hit[inside].mean() > 0.95 and hit[outside].sum() == 0


def test_each_view_shows_the_model_axes():
    # Seen from above with +z up, the z axis of the triad points straight up the image, and
    # from the front's opposite the x axis points the other way.
    v, t, n = box_mesh((0, 0, 0), (4, 3, 2))
    img, (front, back) = preview.picture(preview.Scene(v, t, n), [])
    colour = lambda k: np.all(np.abs(img.astype(int) - np.array(preview.AXIS_COLOURS[k]) * 255) <= 2, axis=2)  # noqa: E731
    oy = PANEL_H - 56
    for ox in (56, PANEL_W + 56):
        assert colour(2)[oy - 25:oy - 2, ox].all()                 # z: up from the origin
        assert not colour(2)[oy + 2:oy + 30, ox].any()
    right = lambda d: preview.image_axes(d)[0]  # noqa: E731
    for ox, d in ((56, front), (PANEL_W + 56, back)):
        side = np.sign(right(d)[0])                                 # x's screen direction
        xs = np.nonzero(colour(0)[oy - 40:oy + 40, ox - 40:ox + 40].any(0))[0] - 40
        assert np.all(np.sign(xs[np.abs(xs) > 3]) == side)


def test_a_split_layout_patch_shows_its_worst_piece():
    """After splits the fit has more patches than the layout: each names its layout patch,
    and the layout patch takes the colour of its worst piece."""
    v, t, n = grid_square()
    details = _halves(v, t)
    fit = {"tolerance": 1.0, "per_patch": [{"max_deviation": 0.0, "layout_patch": 0},
                                           {"max_deviation": 0.0, "layout_patch": 1},
                                           {"max_deviation": 2.0, "layout_patch": 0}]}
    tints = preview.patch_deviation_tints(details, fit, len(t))
    c = v[t].mean(1)
    assert np.allclose(tints[c[:, 0] < 5], preview.deviation_colour(2.0))
    assert np.allclose(tints[c[:, 0] > 5], preview.deviation_colour(0.0))
    with pytest.raises(ValueError, match="layout patches"):
        preview.patch_deviation_tints(details, dict(fit, per_patch=fit["per_patch"][:1]), len(t))
