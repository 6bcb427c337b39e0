"""preview.png: a layout drawn on the shaded model, rendered offscreen (issue 6).

    render_preview(path, vertices, triangles, normals, stripes=[...], tints=..., lines=[...])
    render_design(path, ds, layout=None, regions=None)  # what `stripweave weave` writes
    render_deviation(path, ds, fit, details=None)  # deviation.png of `weave --step`: patches by fit

People look at layouts; they do not read them. The picture shows the part shaded (Lambert,
two-sided), each strip as its stripe pattern (paper §4.2: quasi-parallel isocurves of the
strip map, so crossing strips form a grid), the region colours of the assessment as a tint
(red, orange, yellow), and patch edges (or, without a layout, the dual loops) as lines.

This is a small software renderer on purpose: no display, no FreeCAD GUI, no dependency
beyond numpy, zlib and the native library. Triangles are rasterized in an orthographic view by the native
library (render/rasterize.h: per pixel the nearest triangle and its barycentrics; the numpy
rasterizer before it took 1.5 to 2.7 s of a weave run, the native one 0.15 s, the same
pixels), and pixels are shaded from their triangle and barycentrics (render/shade.h: the
numpy shader's arithmetic, the same colours, 0.4 s instead of 1.3 to 3 s). Lines
are sampled at half-pixel steps and kept where they are not behind the surface (with a small
depth offset so lines on the surface win). It is the display of data the native side has
computed, not geometry of its own: the view is chosen among the eight isometric directions (and the
six axis directions, when they see clearly more) as the one that sees the most surface area.
"""
import struct
import zlib

import numpy as np

from ._native import native

BACKGROUND = np.array([255, 255, 255], float)
BASE = np.array([0.80, 0.82, 0.85])
TINTS = {"red": (0.95, 0.25, 0.2), "orange": (1.0, 0.6, 0.15), "yellow": (0.98, 0.9, 0.25)}
# Strip hues: distinct, darkish, so stripes read on the light base.
HUES = np.array([(0.12, 0.38, 0.75), (0.1, 0.55, 0.3), (0.6, 0.2, 0.6), (0.0, 0.5, 0.6), (0.45, 0.35, 0.1),
                 (0.75, 0.3, 0.1), (0.3, 0.3, 0.65), (0.2, 0.5, 0.1)])


# --- the view ------------------------------------------------------------------

def best_view(vertices, triangles):
    """The isometric direction (to the eye) that sees the most surface area: projected area of
    the triangles facing it. Ties go to views from above (+z), then to the first listed."""
    v = np.asarray(vertices, float)
    t = np.asarray(triangles)
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])  # 2 x area, outward
    # Isometric views read best as 3D; an axis view wins only when it sees clearly more
    # (the flat face of a plate-like part).
    views = [(np.array([sx, sy, sz], float) / np.sqrt(3), 1.0) for sz in (1, -1) for sx in (1, -1) for sy in (-1, 1)]
    views += [(np.array(a, float), 0.8) for a in ((0, 0, 1), (1, 0, 0), (0, -1, 0), (0, 0, -1), (-1, 0, 0), (0, 1, 0))]
    best, best_seen = None, -1.0
    for d, weight in views:
        if abs(d[2]) > 0.99:   # straight down: tilt a little so the camera has an up direction
            d = d + np.array([0.0, -0.35, 0.0])
            d /= np.linalg.norm(d)
        seen = weight * np.clip(n @ d, 0, None).sum()
        if seen > best_seen * (1 + 1e-3):
            best, best_seen = d, seen
    return best


def camera(view, vertices, width, height, margin=0.06):
    """Orthographic camera: (right, up, view) axes and the map model -> pixel (x, y, depth)."""
    view = np.asarray(view, float) / np.linalg.norm(view)
    up0 = np.array([0, 0, 1.0]) if abs(view[2]) < 0.95 else np.array([0, 1.0, 0])
    right = np.cross(up0, view)
    right /= np.linalg.norm(right)
    up = np.cross(view, right)
    v = np.asarray(vertices, float)
    x, y = v @ right, v @ up
    span = max((x.max() - x.min()) / width, (y.max() - y.min()) / height) / (1 - 2 * margin)
    cx, cy = (x.max() + x.min()) / 2, (y.max() + y.min()) / 2

    def project(p):
        p = np.asarray(p, float)
        return np.stack([(p @ right - cx) / span + width / 2, height / 2 - (p @ up - cy) / span, -(p @ view)], -1)
    return project, span


# --- rasterization --------------------------------------------------------------

def rasterize(screen, triangles, width, height):
    """Per pixel the nearest triangle (or -1) and its barycentrics; depth buffer (native:
    render/rasterize.h)."""
    return native.rasterize(np.asarray(screen, float), np.asarray(triangles, np.int64), int(width), int(height))


def draw_lines(image, depth, project, polylines, colour, width_px=1.5, offset=0.0):
    """Polylines (model units) with a depth test against the surface (offset toward the eye)."""
    H, W = image.shape[:2]
    segs = []
    for line in polylines:
        q = project(np.asarray(line, float))
        if len(q) >= 2:
            segs.append(np.stack([q[:-1], q[1:]], 1))
    if not segs:
        return
    s = np.concatenate(segs)
    length = np.linalg.norm(s[:, 1, :2] - s[:, 0, :2], axis=1)
    n = np.maximum(1, np.ceil(length / 0.5).astype(int))
    seg = np.repeat(np.arange(len(s)), n + 1)
    u = np.concatenate([np.linspace(0, 1, k + 1) for k in n]) if len(n) < 2000 else \
        (np.arange(len(seg)) - np.repeat(np.cumsum(n + 1) - (n + 1), n + 1)) / np.repeat(n, n + 1)
    pts = s[seg, 0] + (s[seg, 1] - s[seg, 0]) * u[:, None]
    r = width_px / 2
    stamps = [(dx, dy) for dx in np.arange(-np.ceil(r), np.ceil(r) + 1) for dy in np.arange(-np.ceil(r), np.ceil(r) + 1)
              if dx * dx + dy * dy <= r * r + 0.25]
    for dx, dy in stamps:
        x = np.floor(pts[:, 0] + dx).astype(int)
        y = np.floor(pts[:, 1] + dy).astype(int)
        ok = (x >= 0) & (y >= 0) & (x < W) & (y < H)
        x, y, z = x[ok], y[ok], pts[ok, 2]
        visible = z <= depth.reshape(H, W)[y, x] + offset
        image[y[visible], x[visible]] = colour


# --- shading ---------------------------------------------------------------------

def shade(tri_img, bary, vertices, triangles, normals, light, stripes, tints, stripe_period):
    """RGB per pixel (float 0..1): Lambert on the base colour, region tint, stripe lines
    (native: render/shade.h; each strip in its hue)."""
    stripes = [np.asarray(c, float) for c in stripes]
    return native.shade(tri_img, bary, np.asarray(vertices, float), np.asarray(normals, float),
                        np.asarray(triangles, np.int64), np.asarray(light, float).tolist(), BASE.tolist(),
                        (BACKGROUND / 255.0).tolist(), None if tints is None else np.asarray(tints, float), stripes,
                        [HUES[i % len(HUES)].tolist() for i in range(len(stripes))], float(stripe_period))


def write_png(path, image):
    """An 8-bit RGB PNG (image: H x W x 3 uint8)."""
    h, w, _ = image.shape
    raw = b"".join(b"\x00" + image[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def render_preview(path, vertices, triangles, normals, stripes=(), tints=None, lines=(), thin_lines=(),
                   view=None, width=1024, height=768, stripe_period=None, supersample=2):
    """Render and write the picture; returns the view direction used."""
    vertices = np.asarray(vertices, float)
    view = best_view(vertices, triangles) if view is None else np.asarray(view, float)
    W, H = width * supersample, height * supersample
    project, span = camera(view, vertices, W, H)
    screen = project(vertices)
    # Light from the upper left of the viewer, so faces of a box get distinct tones.
    o = project(np.zeros((1, 3)))[0]
    right = project(np.eye(3))[:, 0] - o[0]
    up = -(project(np.eye(3))[:, 1] - o[1])
    light = view / np.linalg.norm(view) - 0.45 * right / np.linalg.norm(right) + 0.7 * up / np.linalg.norm(up)
    light /= np.linalg.norm(light)
    tri_img, bary, depth = rasterize(screen, triangles, W, H)
    diag = np.linalg.norm(vertices.max(0) - vertices.min(0))
    period = stripe_period or diag / 70.0
    img = shade(tri_img, bary, vertices, triangles, normals, light, stripes, tints, period)
    img = img.reshape(H, W, 3)
    offset = 2.5 * span * supersample + 1e-3 * diag   # lines on the surface win against it
    # Loops (spines) in their strip's hue, under the patch edges, which are drawn last and widest.
    for i, line in enumerate(thin_lines):
        draw_lines(img, depth, project, [line], 0.7 * HUES[i % len(HUES)], width_px=1.6 * supersample, offset=offset)
    draw_lines(img, depth, project, lines, np.array((0.05, 0.05, 0.07)), width_px=3.0 * supersample, offset=offset)
    if supersample > 1:
        img = img.reshape(height, supersample, width, supersample, 3).mean(axis=(1, 3))
    write_png(path, np.clip(img * 255 + 0.5, 0, 255).astype(np.uint8))
    return view


def render_design(path, ds, layout=None, regions=None, **kw):
    """The preview of a DesignSession: its strips' stripes, the region colours (from `regions`,
    native.regions(..., details=True), or computed here) and the layout's patch edges (or the
    loops when there is no layout)."""
    from ._native import native
    s = ds.surface
    if regions is None:
        loops = native.design_loops(ds.native)
        sing = ds.singularities()
        regions = native.regions(ds.loop_session.native, loops, [x["vertex"] for x in sing],
                                 [round(4 * x["index"]) for x in sing], True)
    tints = np.full((len(s.triangles), 3), np.nan)
    if "triangle_region" in regions:
        colour = [r["colour"] for r in regions["regions"]]
        parent = np.asarray(regions["parent_triangle"])
        reg = np.asarray(regions["triangle_region"])
        for name, rgb in TINTS.items():
            hit = np.array([c == name for c in colour] + [False])[np.where(reg < 0, len(colour), reg)]
            tints[parent[hit]] = rgb
    stripes = [ds.native.strip_coordinates(i) for i in range(ds.native.strip_count)]
    # A strip the extraction found empty has no coordinates: it shows as its loop only.
    stripes = [c if len(c) == len(s.triangles) else np.full((len(s.triangles), 3, 2), np.nan) for c in stripes]
    loops = [st["points"] for st in ds.strips()]
    edges = [e["points"] for e in (layout or {}).get("edges", [])]
    if edges:
        return render_preview(path, s.vertices, s.triangles, s.normals, stripes, tints, lines=edges,
                              thin_lines=loops, **kw)
    return render_preview(path, s.vertices, s.triangles, s.normals, stripes, tints, lines=loops, **kw)


# --- the fit's deviation per patch (weave --step) --------------------------------

DEVIATION_SCALE = ((0.0, (0.15, 0.65, 0.3)), (1.0, (0.98, 0.85, 0.2)), (2.0, (0.9, 0.15, 0.1)))
NOT_FITTED = (0.6, 0.35, 0.75)


def deviation_colour(ratio):
    """The colour of a patch whose deviation is `ratio` times the tolerance: green at 0,
    yellow at the tolerance, red at twice it and beyond (linear in between)."""
    r = min(max(float(ratio), 0.0), DEVIATION_SCALE[-1][0])
    for (r0, c0), (r1, c1) in zip(DEVIATION_SCALE, DEVIATION_SCALE[1:]):
        if r <= r1:
            w = (r - r0) / (r1 - r0)
            return tuple((1 - w) * a + w * b for a, b in zip(c0, c1))
    return DEVIATION_SCALE[-1][1]


def patch_deviation_tints(details, fit, triangle_count):
    """Per surface triangle the colour of its patch's fit (deviation_colour of the larger of
    the patch's and its edge curves' deviation over the tolerance; NOT_FITTED for a layout
    patch that is no clean quad, NaN outside every patch). `details`: the design's
    layout(details=True), whose quad patches are the fitted network's patches in order."""
    quads = [i for i, p in enumerate(details["patches"]) if p["quad"]]
    if len(quads) != len(fit["per_patch"]):
        raise ValueError(f"the fit has {len(fit['per_patch'])} patches, the layout {len(quads)} clean quads")
    colour = np.array([NOT_FITTED] * len(details["patches"]) + [(np.nan,) * 3], float)
    tol = float(fit["tolerance"])
    for k, i in enumerate(quads):
        p = fit["per_patch"][k]
        colour[i] = deviation_colour(max(p["max_deviation"], p.get("side_deviation", 0.0)) / tol)
    patch = np.asarray(details["patch_of_triangle"])
    parent = np.asarray(details["parent_triangle"])
    tints = np.full((triangle_count, 3), np.nan)
    tints[parent] = colour[np.where(patch < 0, len(details["patches"]), patch)]
    return tints


def render_deviation(path, ds, fit, details=None, **kw):
    """deviation.png: the layout's patches coloured by how far their fit is from the source
    (patch_deviation_tints: green well within the tolerance, yellow at it, red at twice it
    and beyond; violet: not fitted), with the patch edges, seen as preview.png sees the
    part. `details`: the design's layout(details=True), if the caller has it."""
    s = ds.surface
    details = details if details is not None else ds.native.layout(True)
    tints = patch_deviation_tints(details, fit, len(s.triangles))
    edges = [e["points"] for e in details.get("edges", [])]
    return render_preview(path, s.vertices, s.triangles, s.normals, (), tints, lines=edges, **kw)
