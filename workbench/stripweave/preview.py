"""preview.png and deviation.png: a layout drawn on the shaded model, rendered offscreen (issues 6, 16).

    render_design(path, ds, layout=None, regions=None)           # preview.png of `stripweave weave`
    render_deviation(path, ds, fit, details=None, uncovered=None) # deviation.png of `weave --step`
    render_preview(path, vertices, triangles, normals, stripes=[...], tints=..., lines=[...], ...)

People look at layouts; they do not read them. Each picture is 1024 x 768 pixels: two views of
the part side by side, each labelled, over a legend band that says what every colour and mark
means (text: raster_text.py).
  preview.png    the part shaded (Lambert, two-sided), the patch edges dark and wide (the most
                 visible thing: they are the layout), each strip's stripe pattern dimmed under
                 them (paper §4.2: isocurves of the strip map, so crossing strips form a grid),
                 the dual loops thin and light, the region colours of the assessment as a tint
                 (red: not a disc; orange: several singularities; yellow: valence and curvature
                 disagree; crease: the region keeps the layout off a crease), and defects
                 (layout.json's "defects" of patches and vertices, when it has them) in magenta:
                 a hatch over a defective patch, a ring around a defective vertex. The legend
                 counts the defects by kind.
  deviation.png  each patch coloured by its fit's deviation over the tolerance (green at 0,
                 yellow at the tolerance, red at twice it and beyond), with a colour bar in
                 model units; violet: a patch that was not fitted; blue: source triangles more
                 than half of whose area is within tolerance of no fitted patch (`uncovered`,
                 UNCOVERED_FRACTION; a patch that was not fitted keeps its violet).

Up (up_axis). A part should stand as it stands in use, never upside down. Up is the model's
+z (the CAD convention, FreeCAD's and STEP's: a part appears as its designer placed it) unless
+y or +x is clearly more of a base to stand on (conventions differ in which axis is up, but
nobody models a part upside down, so a negative axis is never up): base_share(up) is the area
of the convex outline of the part's lowest slab (2 % of the diagonal deep) over that of the
whole part, both seen along up; a foot, a pedestal, four legs or a flat underside score near 1,
a side that meets the ground along a curve or at a point near 0. +y or +x wins only with 1.5
times +z's share, so a box or a tall prism (every side as much a base) keeps +z and stands
upright, and a scan or graphics mesh modelled y-up (a cow on its four feet, a statue on its
pedestal) stands on its feet. Both views and both pictures use the same up.

The two views (view_pair). Front is the direction, among eight from above at the isometric
elevation (35.26 degrees over the horizon of up) and two horizontal ones (weighted 0.8: a 3D
view reads better unless an axis view sees clearly more), that sees the most surface area: the
projected area of all triangles, each seen from the side it faces, so a direction and its
opposite score alike and the pair sees the whole of a convex part between them. Back is its
opposite: the view from below and behind. Both views keep up as image up (they are mirror
images in outline), which is well defined since no candidate is within 54 degrees of up.

This is a small software renderer on purpose: no display, no FreeCAD GUI, no dependency beyond
numpy, zlib and the native library. Triangles are rasterized in an orthographic view by the
native library (render/rasterize.h: per pixel the nearest triangle and its barycentrics), and
pixels are shaded from their triangle and barycentrics (render/shade.h), at twice the
resolution and averaged down. Lines are sampled at half-pixel steps (whole-pixel for wide lines,
whose stamp covers the gaps) and kept where they are not
behind the surface (with a small depth offset so lines on the surface win). It is the display
of data the native side has computed, not geometry of its own.
"""
import struct
import zlib
from dataclasses import dataclass, field

import numpy as np

from ._native import native
from .raster_text import CELL_H, draw_text, text_size

WIDTH, HEIGHT = 1024, 768        # the whole picture
LEGEND_H = 112                   # the legend band under the two views
TEXT = 2                         # text scale: 12 x 20 pixel cells
BACKGROUND = np.array([255, 255, 255], float)
BASE = np.array([0.80, 0.82, 0.85])
INK = np.array((0.1, 0.1, 0.12))
EDGE = np.array((0.04, 0.04, 0.06))
MARK = np.array((0.92, 0.0, 0.78))     # defects: magenta, in no other role
TINTS = {"red": (0.95, 0.25, 0.2), "orange": (1.0, 0.6, 0.15), "yellow": (0.98, 0.9, 0.25),
         "crease": (0.2, 0.7, 0.85)}
REGION_MEANING = {"red": "not a disc", "orange": "2+ extrema of one sign", "yellow": "valence vs curvature",
                  "crease": "blocks a crease"}
# Strip hues: distinct, darkish, so stripes read on the light base.
HUES = np.array([(0.12, 0.38, 0.75), (0.1, 0.55, 0.3), (0.6, 0.2, 0.6), (0.0, 0.5, 0.6), (0.45, 0.35, 0.1),
                 (0.75, 0.3, 0.1), (0.3, 0.3, 0.65), (0.2, 0.5, 0.1)])
STRIPE_STRENGTH = 0.16           # dimmed: the stripes show the strips without hiding the edges
TINT_SHARE = 0.55                # a tint's share of the colour (render/shade.h)
UP = np.array([0.0, 0.0, 1.0])


# --- the views -----------------------------------------------------------------

# Up is one of the model's positive axes: conventions differ in which axis is up (CAD's z, many
# scans' and graphics meshes' y), but nobody models a part upside down.
AXES = (("+z", (0, 0, 1)), ("+y", (0, 1, 0)), ("+x", (1, 0, 0)))
BASE_DEPTH = 0.02      # a part's base: its lowest slab, this share of the bounding box diagonal deep
BASE_CLEARLY = 1.5     # another side is the base only when its share is this many times +z's


def _outline_area(points):
    """Area of the convex outline of 2D points, as the polygon of the points extreme in 64
    directions (within 0.5 % of the hull's area; no hull algorithm needed)."""
    a = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    q = points[np.unique(np.argmax(points @ np.stack([np.cos(a), np.sin(a)]), axis=0))]
    if len(q) < 3:
        return 0.0
    c = q - q.mean(0)
    q = q[np.argsort(np.arctan2(c[:, 1], c[:, 0]))]
    return 0.5 * abs(np.dot(q[:, 0], np.roll(q[:, 1], 1)) - np.dot(q[:, 1], np.roll(q[:, 0], 1)))


def _horizontal(up):
    """Two unit directions completing `up` to a right-handed frame: a model axis, then up x it."""
    up = np.asarray(up, float)
    e1 = np.eye(3)[int(np.argmin(np.abs(up)))]
    e1 = e1 - (e1 @ up) * up
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(up, e1)


def base_share(vertices, up):
    """How much of a base the part has under `up`: the area of the convex outline of its
    lowest slab (BASE_DEPTH deep) over that of the whole part, both seen along `up`. A part
    standing on a foot, a pedestal, four legs or a flat face scores high; a side that touches
    the ground along a curve or at a point scores near 0."""
    v = np.asarray(vertices, float)
    up = np.asarray(up, float)
    e1, e2 = _horizontal(up)
    h = v @ up
    low = v[h < h.min() + BASE_DEPTH * np.linalg.norm(np.ptp(v, axis=0))]
    whole = _outline_area(np.stack([v @ e1, v @ e2], 1))
    return _outline_area(np.stack([low @ e1, low @ e2], 1)) / whole if whole > 0 else 0.0


def up_axis(vertices):
    """(name, unit vector): the model's +z (CAD's up: a part appears as its designer placed it),
    unless +y or +x is clearly more of a base to stand on (base_share over BASE_CLEARLY times
    +z's): a scan or a graphics mesh modelled y-up stands on its feet then. Never a negative
    axis: a part whose top is flatter than its bottom still stands as modelled."""
    share = {name: base_share(vertices, d) for name, d in AXES}
    best = max(share, key=lambda name: share[name] * (1 + 1e-9 * (name == "+z")))
    name = best if share[best] > BASE_CLEARLY * share["+z"] else "+z"
    return name, np.array(dict(AXES)[name], float)


def view_candidates(up=UP):
    """(direction to the eye, weight): eight directions from above at the isometric elevation
    (the four octant diagonals first, as FreeCAD's isometric view, then the four between),
    then two horizontal axis directions (each stands for its pair, as every candidate does).
    Above and horizontal are with respect to `up`."""
    up = np.asarray(up, float)
    e1, e2 = _horizontal(up)
    e = np.arctan(1 / np.sqrt(2))       # the isometric elevation, 35.26 degrees
    azimuths = [-np.pi / 4, np.pi / 4, 3 * np.pi / 4, 5 * np.pi / 4, 0.0, np.pi / 2, np.pi, 1.5 * np.pi]
    iso = [(np.cos(e) * (np.cos(a) * e1 + np.sin(a) * e2) + np.sin(e) * up, 1.0) for a in azimuths]
    return iso + [(-e2, 0.8), (e1, 0.8)]


def view_pair(vertices, triangles, up=UP):
    """(front, back): unit directions to the eye (module doc). The pair that sees the most
    area wins (ties: the first listed); front is the one from above, or for a horizontal pair
    the one facing more outward normals."""
    v = np.asarray(vertices, float)
    t = np.asarray(triangles)
    n = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])  # 2 x area, outward
    best, best_seen = None, -1.0
    for d, weight in view_candidates(up):
        seen = weight * np.abs(n @ d).sum()
        if seen > best_seen * (1 + 1e-3):
            best, best_seen = d, seen
    if abs(best @ up) < 1e-9 and np.clip(n @ -best, 0, None).sum() > np.clip(n @ best, 0, None).sum() * (1 + 1e-3):
        best = -best
    return best, -best


def best_view(vertices, triangles):
    """The front view of view_pair, under up_axis's up."""
    return view_pair(vertices, triangles, up_axis(vertices)[1])[0]


def _fallback_up(view):
    """(name, vector): the up of a view along the chosen up: model +y, or +z along y."""
    return ("+y", np.array([0, 1.0, 0])) if abs(view[1]) < 0.95 else ("+z", np.array([0, 0, 1.0]))


def image_axes(view, up=UP):
    """(right, up, view): the image's axes in model space, unit. Image up is `up` projected onto
    the image plane (_fallback_up when the view is along it)."""
    view = np.asarray(view, float) / np.linalg.norm(view)
    up0 = np.asarray(up, float) if abs(np.dot(up, view)) < 0.95 else _fallback_up(view)[1]
    right = np.cross(up0, view)
    right /= np.linalg.norm(right)
    return right, np.cross(view, right), view


def camera(view, vertices, width, height, margin=0.06, up=UP):
    """Orthographic camera (image_axes): the map model -> pixel (x, y, depth) and model units
    per pixel."""
    right, up, view = image_axes(view, up)
    v = np.asarray(vertices, float)
    x, y = v @ right, v @ up
    span = max((x.max() - x.min()) / width, (y.max() - y.min()) / height, 1e-30) / (1 - 2 * margin)
    cx, cy = (x.max() + x.min()) / 2, (y.max() + y.min()) / 2

    def project(p):
        p = np.asarray(p, float)
        return np.stack([(p @ right - cx) / span + width / 2, height / 2 - (p @ up - cy) / span, -(p @ view)], -1)
    return project, span


# --- rasterization and marks -----------------------------------------------------

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
    # Samples at half-pixel steps for thin lines; a wide stamp covers the gaps of whole-pixel steps.
    n = np.maximum(1, np.ceil(length / (0.5 if width_px < 3 else 1.0)).astype(int))
    seg = np.repeat(np.arange(len(s)), n + 1)
    u = (np.arange(len(seg)) - np.repeat(np.cumsum(n + 1) - (n + 1), n + 1)) / np.repeat(n, n + 1)
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


def draw_hatch(image, tri_img, marked, colour, period, width, row0=0):
    """Diagonal screen-space lines over the pixels of marked triangles: a pattern that follows
    no surface direction, so it cannot be taken for a strip's stripes. `row0`: the image's
    first row in the whole view (a band, render_view), where the pattern is anchored."""
    H, W = image.shape[:2]
    # Only the marked triangles' pixels are looked at (full-image index grids would be tens
    # of MB on a supersampled view).
    t = tri_img.reshape(-1)
    pixel = np.flatnonzero(t >= 0)
    pixel = pixel[marked[t[pixel]]]
    y, x = np.divmod(pixel, W)
    on = (x + y + row0) % period < width
    image[y[on], x[on]] = colour


def draw_rings(image, depth, project, points, colour, radius, width, offset):
    """A ring in screen space around each point that is not behind the surface."""
    H, W = image.shape[:2]
    d = depth.reshape(H, W)
    r = int(np.ceil(radius))
    dy, dx = np.mgrid[-r:r + 1, -r:r + 1]
    ring = np.abs(np.hypot(dx, dy) - (radius - width / 2)) <= width / 2
    dx, dy = dx[ring], dy[ring]
    for q in project(np.asarray(points, float).reshape(-1, 3)):
        cx, cy = int(np.floor(q[0])), int(np.floor(q[1]))
        if not (0 <= cx < W and 0 <= cy < H) or q[2] > d[cy, cx] + offset:
            continue
        x, y = cx + dx, cy + dy
        ok = (x >= 0) & (y >= 0) & (x < W) & (y < H)
        image[y[ok], x[ok]] = colour


# --- shading and one view --------------------------------------------------------

def shade(tri_img, bary, vertices, triangles, normals, light, stripes, tints, stripe_period,
          stripe_strength=STRIPE_STRENGTH):
    """RGB per pixel (float 0..1): Lambert on the base colour, region tint, stripe lines
    (native: render/shade.h; each strip in its hue)."""
    stripes = [np.asarray(c, float) for c in stripes]
    return native.shade(tri_img, bary, np.asarray(vertices, float), np.asarray(normals, float),
                        np.asarray(triangles, np.int64), np.asarray(light, float).tolist(), BASE.tolist(),
                        (BACKGROUND / 255.0).tolist(), None if tints is None else np.asarray(tints, float), stripes,
                        [HUES[i % len(HUES)].tolist() for i in range(len(stripes))], float(stripe_period),
                        float(stripe_strength))


@dataclass
class Scene:
    """What a view draws, in model units: the mesh (per vertex normals), per strip its stripe
    coordinates (shade.h: (triangles, 3, 2), or the coordinate across alone, (triangles, 3)),
    per triangle a tint (NaN rows: none) and a defect hatch (bool),
    lines (patch edges, dark and wide), thin lines (loops, light, in their strip's hue) and
    points ringed as defective vertices."""
    vertices: np.ndarray
    triangles: np.ndarray
    normals: np.ndarray
    stripes: list = field(default_factory=list)
    tints: np.ndarray = None
    lines: list = field(default_factory=list)
    thin_lines: list = field(default_factory=list)
    hatch: np.ndarray = None
    rings: np.ndarray = None
    stripe_period: float = None


# A view is rasterized, shaded and marked in horizontal bands, one at a time: a whole
# supersampled view's raster and shaded pixels were some 80 MB at once (issue 22). Each band is
# drawn with BAND_MARGIN extra rows above and below (supersampled pixels), more than any mark
# reaches (a ring's radius, a wide line's stamp), so every pixel of the band comes out as in
# the whole view: the raster and the shading are per pixel, and a mark that reaches into the
# band is drawn in it, its depth test made at the same pixel.
BANDS = 2
BAND_MARGIN = 24


def render_view(scene, view, width, height, supersample=2, up=UP):
    """One view of the scene as a float RGB image (height, width, 3), `up` up."""
    vertices = np.asarray(scene.vertices, float)
    W, H, ss = width * supersample, height * supersample, supersample
    project, span = camera(view, vertices, W, H, up=up)
    # Light from the upper left of the viewer, so faces of a box get distinct tones.
    right, image_up, eye = image_axes(view, up)
    light = eye - 0.45 * right + 0.7 * image_up
    light /= np.linalg.norm(light)
    diag = np.linalg.norm(vertices.max(0) - vertices.min(0))
    period = scene.stripe_period or diag / 55.0   # sparser than the solver could draw: a texture, not a grid
    offset = 2.5 * span * ss + 1e-3 * diag   # lines on the surface win against it
    step = -(-H // (BANDS * ss)) * ss          # whole ss x ss blocks per band
    out = []
    for y0 in range(0, H, step):
        y1 = min(H, y0 + step)
        top, bottom = max(0, y0 - BAND_MARGIN), min(H, y1 + BAND_MARGIN)
        img = _render_rows(scene, project, top, bottom, W, light, period, offset, ss)[y0 - top:y1 - top]
        if ss > 1:   # the mean of each ss x ss block, as slices (a reshaped mean is several times slower)
            img = sum(img[i::ss, j::ss] for i in range(ss) for j in range(ss)) / (ss * ss)
        out.append(img)
    return np.concatenate(out)


def _render_rows(scene, project, top, bottom, W, light, period, offset, ss):
    """Rows top..bottom-1 of a view (supersampled pixels): shaded, with the hatch, the lines
    and the rings."""
    shift = np.array([0.0, float(top), 0.0])   # whole pixels: the shifted positions are exact

    def rows_project(p):
        return project(p) - shift
    vertices = np.asarray(scene.vertices, float)
    tri_img, bary, depth = rasterize(rows_project(vertices), scene.triangles, W, bottom - top)
    img = shade(tri_img, bary, vertices, scene.triangles, scene.normals, light, scene.stripes, scene.tints, period)
    del bary   # 24 bytes a pixel, not needed for the marks
    img = img.reshape(bottom - top, W, 3)
    if scene.hatch is not None and np.any(scene.hatch):
        draw_hatch(img, tri_img, np.asarray(scene.hatch, bool), MARK, period=9 * ss, width=2 * ss, row0=top)
    # Loops in their strip's hue, light, under the patch edges, which are drawn last and widest.
    for i, line in enumerate(scene.thin_lines):
        hue = 0.5 * HUES[i % len(HUES)] + 0.5 * BASE
        draw_lines(img, depth, rows_project, [line], hue, width_px=1.0 * ss, offset=offset)
    draw_lines(img, depth, rows_project, scene.lines, EDGE, width_px=3.2 * ss, offset=offset)
    if scene.rings is not None and len(scene.rings):
        draw_rings(img, depth, rows_project, scene.rings, MARK, radius=7.5 * ss, width=2.5 * ss, offset=offset)
    return img


# --- the legend ------------------------------------------------------------------

def _icon(canvas, kind, colour, x, y, w=28, h=14):
    """A legend item's sample at (x, y): a tinted swatch, a line, a hatch or a ring."""
    box = canvas[y:y + h, x:x + w]
    if kind == "swatch":
        box[:] = colour
        box[[0, -1]] = INK
        box[:, [0, -1]] = INK
    elif kind == "line":
        box[h // 2 - 2:h // 2 + 2] = colour
    elif kind == "hatch":
        box[:] = BASE
        yy, xx = np.mgrid[0:h, 0:w]
        box[(xx + yy) % 9 < 2] = colour
    elif kind == "text":
        return 0
    elif kind == "ring":
        yy, xx = np.mgrid[0:h, 0:w]
        box[np.abs(np.hypot(xx - w / 2 + 0.5, yy - h / 2 + 0.5) - 6) <= 1.3] = colour


def tint_as_drawn(colour):
    """A tint as the shader shows it on a surface lit at |n . light| = 0.8 (render/shade.h)."""
    return ((1 - TINT_SHARE) * BASE + TINT_SHARE * np.asarray(colour, float)) * (0.35 + 0.65 * 0.8)


def draw_legend(canvas, items, x0, y0, x1):
    """Items (kind, colour, text) flowed left to right from (x0, y0), wrapping before x1."""
    x, y = x0, y0
    row = CELL_H * TEXT + 4
    for kind, colour, text in items:
        icon = 0 if kind == "text" else 34    # "text": a heading, no sample
        w = icon + text_size(text, TEXT)[0] + 18
        if x > x0 and x + w > x1:
            x, y = x0, y + row
        _icon(canvas, kind, colour, x, y + 3)
        draw_text(canvas, text, x + icon, y, INK, TEXT)
        x += w
    return y + row


def _number(value):
    """A tick label: three significant digits, no exponent for everyday sizes."""
    return f"{value:.3g}" if value == 0 or 1e-3 <= abs(value) < 1e5 else f"{value:.2e}"


def draw_colour_bar(canvas, tolerance, x0, y0, length=400, h=16):
    """The deviation scale from 0 to 2 x tolerance in model units (colours as drawn), ticks
    at quarters of it labelled in model units, the tolerance marked by a long tick. Returns
    the y under it."""
    draw_text(canvas, "deviation, model units:", x0, y0, INK, TEXT)
    y = y0 + CELL_H * TEXT + 2
    top = DEVIATION_SCALE[-1][0]
    for i in range(length):
        canvas[y:y + h, x0 + i] = tint_as_drawn(deviation_colour(top * (i + 0.5) / length))
    canvas[[y, y + h - 1], x0:x0 + length] = INK
    canvas[y:y + h, [x0, x0 + length - 1]] = INK
    for k in range(5):
        r = top * k / 4
        x = x0 + int(round(r / top * (length - 1)))
        tol = abs(r - 1.0) < 1e-9
        canvas[y - (6 if tol else 0):y + h + (8 if tol else 4), max(x - 1, 0):x + 1] = INK
        label = _number(r * tolerance)
        draw_text(canvas, label, max(x - text_size(label, TEXT)[0] // 2, 0), y + h + 8, INK, TEXT)
        if tol:
            draw_text(canvas, "tolerance", x - text_size("tolerance", TEXT)[0] // 2, y + h + 8 + CELL_H * TEXT,
                      INK, TEXT)
    return y + h + 8 + 2 * CELL_H * TEXT


AXIS_COLOURS = ((0.8, 0.1, 0.1), (0.1, 0.55, 0.1), (0.1, 0.2, 0.85))   # x, y, z


def draw_triad(image, view, up, x0=56, length=34):
    """The model axes as seen in a view, from a corner (x0 from the left and bottom): x red,
    y green, z blue, each named at its tip; an axis along the view is a short stub. (x0, the
    origin, is in panel pixels.)"""
    right, upv, _ = image_axes(view, up)
    ox, oy = x0, image.shape[0] - x0
    background = np.all(image == BACKGROUND / 255.0, axis=2)   # the triad never hides the part
    out = image.copy()
    for k, name in enumerate("XYZ"):
        e = np.eye(3)[k]
        dx, dy = length * (e @ right), -length * (e @ upv)
        t = np.linspace(0, 1, 4 * length)
        for w in (-1, 0, 1):          # three pixels wide
            xs = np.round(ox + t * dx + w * (abs(dy) > abs(dx))).astype(int)
            ys = np.round(oy + t * dy + w * (abs(dy) <= abs(dx))).astype(int)
            out[ys, xs] = AXIS_COLOURS[k]
        draw_text(out, name, ox + dx + 9 * np.sign(dx) - 5, oy + dy + 11 * np.sign(dy) - 9, AXIS_COLOURS[k], TEXT)
    image[background] = out[background]


def _direction(d):
    x, y, z = (0.0 if abs(c) < 5e-3 else c for c in d)    # no "-0.00"
    return f"{x:.2f}, {y:.2f}, {z:.2f}"


def compose(views, legend_items, colour_bar=None):
    """The picture (HEIGHT, WIDTH, 3 uint8): the two views (label, image) side by side, over the
    legend band (the colour bar on its left when given, then the items)."""
    canvas = np.empty((HEIGHT, WIDTH, 3))
    canvas[:] = BACKGROUND / 255.0
    ph, pw = HEIGHT - LEGEND_H, WIDTH // 2
    for i, (label, img) in enumerate(views):
        canvas[:ph, i * pw:(i + 1) * pw] = img
        draw_text(canvas, label, i * pw + 8, 6, INK, TEXT)
    canvas[8:ph - 8, pw - 1:pw + 1] = 0.75
    canvas[ph:ph + 2, 8:WIDTH - 8] = 0.75
    y, x = ph + 8, 12
    if colour_bar is not None:
        draw_colour_bar(canvas, colour_bar, x, y)
        x = 480
    draw_legend(canvas, legend_items, x, y, WIDTH - 8)
    canvas *= 255    # in place: the canvas is 19 MB of doubles
    canvas += 0.5
    return np.clip(canvas, 0, 255, out=canvas).astype(np.uint8)


def write_png(path, image):
    """An 8-bit RGB PNG (image: H x W x 3 uint8)."""
    h, w, _ = image.shape
    raw = b"".join(b"\x00" + image[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def picture(scene, legend_items, view=None, colour_bar=None, supersample=2):
    """The picture of a scene (HEIGHT, WIDTH, 3 uint8) and its views (front, back): view_pair's,
    or `view` and its opposite."""
    up_name, up = up_axis(scene.vertices)
    if view is None:
        front, back = view_pair(scene.vertices, scene.triangles, up)
    else:
        front = np.asarray(view, float) / np.linalg.norm(view)
        back = -front
    ph, pw = HEIGHT - LEGEND_H, WIDTH // 2
    if abs(front @ up) >= 0.95:     # looking along up: the camera's fallback is up
        up_name = _fallback_up(front)[0]
    views = []
    for name, d in (("front", front), ("back", back)):
        img = render_view(scene, d, pw, ph, supersample, up)
        draw_triad(img, d, up)
        views.append((f"{name}: from ({_direction(d)}), {up_name} up", img))
    return compose(views, legend_items, colour_bar), (front, back)


def render_scene(path, scene, legend_items, **kw):
    """Write the picture of a scene (picture's arguments); returns its views (front, back)."""
    image, views = picture(scene, legend_items, **kw)
    write_png(path, image)
    return views


def render_preview(path, vertices, triangles, normals, stripes=(), tints=None, lines=(), thin_lines=(),
                   view=None, stripe_period=None, supersample=2, hatch=None, rings=None, legend=None):
    """Render and write a picture of a mesh (the Scene's fields; `legend`: items (kind, colour,
    text), kind one of swatch, line, hatch, ring; default: the patch edge). Returns the views
    (front, back)."""
    scene = Scene(np.asarray(vertices, float), np.asarray(triangles), np.asarray(normals, float), list(stripes),
                  tints, list(lines), list(thin_lines), hatch, rings, stripe_period)
    return render_scene(path, scene, legend if legend is not None else [("line", EDGE, "patch edge")],
                        view=view, supersample=supersample)


# --- preview.png: the design -------------------------------------------------------

def _counts(items):
    """{kind: count} over items' "defects" lists, or None when no item has the key."""
    if not any("defects" in x for x in items):
        return None
    counts = {}
    for x in items:
        for kind in x.get("defects", []):
            counts[kind] = counts.get(kind, 0) + 1
    return counts


def defect_marks(layout, details, triangle_count):
    """(hatch, rings): per surface triangle whether it lies (partly) in a patch whose
    layout.json entry lists defects (None when nothing is marked or `details`, the native
    layout(details=True) whose patch order layout.json's is, has no patch_of_triangle), and
    the positions of the vertices that list defects ((k, 3), possibly empty)."""
    patches = (layout or {}).get("patches", [])
    vertices = (layout or {}).get("vertices", [])
    bad = np.array([bool(p.get("defects")) for p in patches] + [False], bool)
    hatch = None
    if bad.any() and details is not None and "patch_of_triangle" in details:
        patch = np.asarray(details["patch_of_triangle"])
        parent = np.asarray(details["parent_triangle"])
        if len(patches) != len(details.get("patches", patches)):
            raise ValueError(f"layout.json has {len(patches)} patches, the layout details "
                             f"{len(details['patches'])}")
        hatch = np.zeros(triangle_count, bool)
        hatch[parent[bad[np.where(patch < 0, len(patches), patch)]]] = True
    rings = np.array([v["position"] for v in vertices if v.get("defects")], float).reshape(-1, 3)
    return hatch, rings


def _kinds(counts):
    return ", ".join(f"{k.replace('_', ' ')} {n}" for k, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))


def design_legend(layout):
    """The preview's legend: patch edges, strips, the region colours, and the defect marks
    with their counts by kind when layout.json lists defects."""
    items = [("line", EDGE, "patch edge"), ("line", 0.5 * HUES[0] + 0.5 * BASE, "strip (loop, stripes)")]
    items += [("text", INK, "regions:")] + [("swatch", tint_as_drawn(TINTS[c]), REGION_MEANING[c]) for c in TINTS]
    patches = _counts((layout or {}).get("patches", []))
    vertices = _counts((layout or {}).get("vertices", []))
    if patches is not None:
        n = sum(1 for p in layout["patches"] if p.get("defects"))
        items.append(("hatch", MARK, f"defective patch: {n}" + (f" ({_kinds(patches)})" if n else "")))
    if vertices is not None:
        n = sum(1 for v in layout["vertices"] if v.get("defects"))
        items.append(("ring", MARK, f"defective vertex: {n}" + (f" ({_kinds(vertices)})" if n else "")))
    return items


def _across(coordinates, triangle_count):
    """A strip's coordinate across per triangle corner (triangles, 3), NaN outside it."""
    if len(coordinates) != triangle_count:
        return np.full((triangle_count, 3), np.nan)
    return np.ascontiguousarray(coordinates[:, :, 1])


def render_design(path, ds, layout=None, regions=None, **kw):
    """The preview of a DesignSession: its strips' stripes, the region colours (from `regions`,
    native.regions(..., details=True) or the layout's details, or computed here), the layout's
    patch edges (or the loops when there is no layout) and its defects (defect_marks: from
    layout.json's "defects", placed by `regions`' patch_of_triangle when it has one)."""
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
    # A strip the extraction found empty has no coordinates: it shows as its loop only. The
    # shader reads the coordinate across alone (half the memory of both, per strip).
    stripes = [_across(ds.native.strip_coordinates(i), len(s.triangles)) for i in range(ds.native.strip_count)]
    loops = [st["points"] for st in ds.strips()]
    edges = [e["points"] for e in (layout or {}).get("edges", [])]
    hatch, rings = defect_marks(layout, regions, len(s.triangles))
    scene = Scene(s.vertices, s.triangles, s.normals, stripes, tints, edges or loops, loops if edges else [],
                  hatch, rings, kw.pop("stripe_period", None))
    return render_scene(path, scene, design_legend(layout), **kw)


# --- deviation.png: the fit's deviation per patch (weave --step) ---------------------

DEVIATION_SCALE = ((0.0, (0.15, 0.65, 0.3)), (1.0, (0.98, 0.85, 0.2)), (2.0, (0.9, 0.15, 0.1)))
NOT_FITTED = (0.6, 0.35, 0.75)
UNCOVERED = (0.1, 0.3, 0.95)
UNCOVERED_FRACTION = 0.5   # a triangle more than half uncovered shows as uncovered


def deviation_colour(ratio):
    """The colour of a patch whose deviation is `ratio` times the tolerance: green at 0,
    yellow at the tolerance, red at twice it and beyond (linear in between)."""
    r = min(max(float(ratio), 0.0), DEVIATION_SCALE[-1][0])
    for (r0, c0), (r1, c1) in zip(DEVIATION_SCALE, DEVIATION_SCALE[1:]):
        if r <= r1:
            w = (r - r0) / (r1 - r0)
            return tuple((1 - w) * a + w * b for a, b in zip(c0, c1))
    return DEVIATION_SCALE[-1][1]


def patch_deviation_tints(details, fit, triangle_count, uncovered=None):
    """Per surface triangle the colour of its patch's fit (deviation_colour of the larger of
    the patch's and its edge curves' deviation over the tolerance; NOT_FITTED for a layout
    patch that is no clean quad, NaN outside every patch). `details`: the design's
    layout(details=True), whose quad patches are the fitted network's patches in order.
    `uncovered`: per surface triangle the fraction of its area within tolerance of no fitted
    patch; a triangle more than UNCOVERED_FRACTION uncovered is UNCOVERED, unless its patch
    was not fitted (that patch's own colour says more)."""
    quads = [i for i, p in enumerate(details["patches"]) if p["quad"]]
    # A layout patch the fit split (its "layout_patch" pieces) shows its worst piece.
    tol = float(fit["tolerance"])
    ratio = {}
    for k, p in enumerate(fit["per_patch"]):
        j = p.get("layout_patch", k)
        ratio[j] = max(ratio.get(j, 0.0), max(p["max_deviation"], p.get("side_deviation", 0.0)) / tol)
    if len(ratio) != len(quads):
        raise ValueError(f"the fit has {len(ratio)} layout patches, the layout {len(quads)} clean quads")
    colour = np.array([NOT_FITTED] * len(details["patches"]) + [(np.nan,) * 3], float)
    for i, k in zip(quads, sorted(ratio)):
        colour[i] = deviation_colour(ratio[k])
    patch = np.asarray(details["patch_of_triangle"])
    parent = np.asarray(details["parent_triangle"])
    tints = np.full((triangle_count, 3), np.nan)
    tints[parent] = colour[np.where(patch < 0, len(details["patches"]), patch)]
    if uncovered is not None:
        u = np.asarray(uncovered, float)
        if u.shape != (triangle_count,):
            raise native.InputError(f"deviation picture: uncovered must give one fraction per surface triangle "
                                    f"({triangle_count}), got shape {u.shape}")
        not_fitted = np.zeros(triangle_count, bool)
        quad = np.array([p["quad"] for p in details["patches"]] + [True], bool)
        not_fitted[parent] = ~quad[np.where(patch < 0, len(details["patches"]), patch)]
        tints[(u > UNCOVERED_FRACTION) & ~not_fitted] = UNCOVERED
    return tints


def deviation_legend(fit):
    """The deviation picture's legend: what its colours mean, and the fit's own figures (its
    largest deviation, two-sided where the fit measures both ways, and its coverage, where
    the fit reports them)."""
    items = [("line", EDGE, "patch edge"), ("swatch", tint_as_drawn(NOT_FITTED), "not fitted"),
             ("swatch", tint_as_drawn(UNCOVERED), "uncovered (>50%)"), ("swatch", BASE * 0.87, "in no patch")]
    if "max_deviation" in fit:
        items.append(("text", INK, f"max deviation {_number(float(fit['max_deviation']))}"))
    if "coverage" in fit:
        items.append(("text", INK, f"coverage {100 * float(fit['coverage']):.2f}%"))
    return items


def render_deviation(path, ds, fit, details=None, uncovered=None, **kw):
    """deviation.png: the layout's patches coloured by how far their fit is from the source
    (patch_deviation_tints), with the patch edges, in the preview's two views, over a colour
    bar in model units. `details`: the design's layout(details=True), if the caller has it;
    `uncovered`: per surface triangle the fraction of its area within tolerance of no fitted
    patch (the native refit's "triangle_uncovered"), if known."""
    s = ds.surface
    details = details if details is not None else ds.native.layout(True)
    tints = patch_deviation_tints(details, fit, len(s.triangles), uncovered)
    edges = [e["points"] for e in details.get("edges", [])]
    scene = Scene(s.vertices, s.triangles, s.normals, [], tints, edges)
    return render_scene(path, scene, deviation_legend(fit), colour_bar=float(fit["tolerance"]), **kw)
