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
