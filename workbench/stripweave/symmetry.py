"""Symmetry (paper §5.8, issue 21): the reflections and rotations a layout should respect.

    syms = detect(surface)                        # [{"kind", "point", "normal"|"axis", "order",
                                                  #   "source": "detected", "rms_error", "max_error"}]
    syms = resolve(surface, "auto" | "none" | "reflect:0,0,0,1,0,0" | [dict, ...] | None,
                   design_symmetry=[...], tolerance=1e-3)
    parse("rotate:0,0,0,0,0,1,5")                 # a given symmetry as design.md's dict
    orbit(surface, syms, anchors, loop_points)    # a strip's images on the other parts
    axis_seeds(surface, syms)                     # anchors of loops beside a rotation's axis
    add_images(ds, index, syms, tolerance, own_tolerance)   # add strip index's images to a DesignSession
    layout_symmetry_error(layout, sym)            # how far the layout's vertex set is from mapping to itself

Symmetries are design.md's dicts, in model units; the maps and their detection are native
(symmetry/*.h). The tolerance is a fraction of the bounding-box diagonal: a symmetry is
accepted when no surface vertex is mapped farther than that from the surface.
"""
import math

import numpy as np

from ._native import native

SYNTAX = "auto, none, reflect:PX,PY,PZ,NX,NY,NZ or rotate:PX,PY,PZ,AX,AY,AZ,N"


def parse(text):
    """'auto', 'none', or a given symmetry (design.md's dict, source "given") from the
    command line's reflect:/rotate: syntax; InputError naming the syntax otherwise."""
    text = text.strip()
    if text in ("auto", "none"):
        return text
    kind, _, numbers = text.partition(":")
    try:
        values = [float(x) for x in numbers.split(",")]
    except ValueError:
        values = []
    if kind == "reflect" and len(values) == 6 and all(map(math.isfinite, values)):
        return {"kind": "reflection", "point": values[:3], "normal": values[3:], "source": "given"}
    if kind == "rotate" and len(values) == 7 and all(map(math.isfinite, values)) and values[6] == int(values[6]):
        return {"kind": "rotation", "point": values[:3], "axis": values[3:6], "order": int(values[6]), "source": "given"}
    raise native.InputError(f"--symmetry must be {SYNTAX}; got {text!r}")


def check(entry, where=""):
    """A symmetry dict from a design file, checked: InputError naming what is wrong."""
    def error(what):
        return native.InputError(f"design file{where}: {what}")
    if not isinstance(entry, dict):
        raise error("a symmetry must be an object")
    kind = entry.get("kind")
    keys = {"reflection": ("point", "normal"), "rotation": ("point", "axis")}.get(kind)
    if keys is None:
        raise error(f"a symmetry's kind must be 'reflection' or 'rotation', got {kind!r}")
    for key in keys:
        v = entry.get(key)
        if not isinstance(v, (list, tuple)) or len(v) != 3 or not all(
                isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v):
            raise error(f"a {kind}'s {key} must be three finite numbers, got {v!r}")
    if not any(entry[keys[1]]):
        raise error(f"a {kind}'s {keys[1]} must not be zero")
    if kind == "rotation":
        order = entry.get("order")
        if isinstance(order, bool) or not isinstance(order, int) or not 2 <= order <= 64:
            raise error(f"a rotation's order must be a whole number within 2..64, got {order!r}")
    return entry


def detect(surface, tolerance=1e-3):
    """The surface's symmetries within tolerance (diagonals), each with its errors (model units)."""
    return list(native.detect_symmetries(surface, float(tolerance)))


def measure(surface, entry):
    """The symmetry with its RMS and max error measured on the surface (model units)."""
    return {**dict(native.measure_symmetry(surface, entry)), "source": entry.get("source", "given")}


def resolve(surface, spec, design_symmetry=None, tolerance=1e-3):
    """The symmetries to weave with: none, detected ("auto"), or given (a dict or a list, as
    parse() gives); None takes the design's own ("symmetry" of design.json), re-measured on
    this surface. A given symmetry farther off than the tolerance is an InputError that says
    by how much (an approximate symmetry is accepted only when the tolerance allows it)."""
    if not tolerance > 0:
        raise native.InputError(f"the symmetry tolerance must be a positive fraction of the diagonal, got {tolerance}")
    if spec is None:
        spec = list(design_symmetry or [])
    if isinstance(spec, str):
        spec = parse(spec)
    if spec == "none":
        return []
    if spec == "auto":
        return dihedral(surface, detect(surface, tolerance))
    given = [spec] if isinstance(spec, dict) else list(spec)
    diagonal = surface.bbox_diagonal
    out = []
    for entry in given:
        m = measure(surface, entry)
        if m["max_error"] > tolerance * diagonal:
            raise native.InputError(
                f"the given {m['kind']} maps the surface up to {m['max_error']:.4g} off itself "
                f"({m['max_error'] / diagonal:.3g} of the diagonal), more than the tolerance "
                f"{tolerance:g} of the diagonal")
        out.append(m)
    return dihedral(surface, out)


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _cos_to_axis(mirror, rotation):
    """|cos| of the angle between a reflection's normal and a rotation's axis: 0 for a plane
    that holds the axis's direction, 1 for one across it."""
    return abs(float(_unit(mirror["normal"]) @ _unit(rotation["axis"])))


def _axial(mirror, rotation, surface):
    """Whether a reflection's plane holds the rotation's axis (to a thousandth of the
    diagonal over the part, a thousandth of a radian)."""
    off = abs(float(_unit(mirror["normal"]) @ (np.asarray(rotation["point"], float) - np.asarray(mirror["point"], float))))
    return _cos_to_axis(mirror, rotation) < 1e-3 and off < 1e-3 * surface.bbox_diagonal


def _turned(v, axis, angle):
    return v * math.cos(angle) + np.cross(axis, v) * math.sin(angle) + axis * float(axis @ v) * (1 - math.cos(angle))


def dihedral(surface, symmetries):
    """The symmetries with a dihedral group made consistent: with one rotation of order n,
    each reflection whose plane holds its axis (within tolerance: _axial) is made to hold it
    exactly (its point on the axis, its normal across it), at an exact multiple of pi / n
    from the first such (the group's mirrors are n planes that far apart), and measured
    again. Detected or given one by one, the planes miss the axis and each other's angles
    by up to the tolerance, and a solver mesh exact under the rotation and one mirror
    (symmetric_surface) was then only 2e-5 off under the others, and a strip's images under
    the group did not close on themselves. Other lists are returned as they are."""
    rotations = [s for s in symmetries if s["kind"] == "rotation"]
    if len(rotations) != 1 or rotations[0]["order"] < 3:
        return symmetries
    rot = rotations[0]
    a = _unit(rot["axis"])
    first, out = None, []
    for sym in symmetries:
        if sym["kind"] == "reflection" and _axial(sym, rot, surface):
            n = np.asarray(sym["normal"], float)
            n = _unit(n - a * float(a @ n))
            if first is None:
                first = n
            else:
                step = math.pi / rot["order"]
                angle = math.atan2(float(np.cross(first, n) @ a), float(first @ n))
                n = _turned(first, a, step * round(angle / step))
            sym = measure(surface, {**sym, "point": list(rot["point"]), "normal": n.tolist()})
        out.append(sym)
    return out


def mesh_symmetries(symmetries):
    """The symmetries the solver mesh is made exact under (symmetric_surface), in the order
    it is made so: every reflection; a rotation if it is the only symmetry. A rotation's mesh
    is n turned copies of one sector, and beside another rotation one sector cannot serve
    both. A dihedral group (one rotation of order 3 or more, reflections whose planes hold
    its axis: dihedral()) is made exact under its first such mirror, then under the rotation
    with the sector from -pi/n to pi/n about that mirror ("sector_start": the sector is then
    its own mirror image, and the n copies are exact under every mirror of the group, which
    need no step of their own); reflections across the axis come first. Under order 2
    perpendicular mirrors, one after the other, already make the half-turn exact."""
    symmetries = list(symmetries or ())
    mirrors = [s for s in symmetries if s["kind"] == "reflection"]
    rotations = [s for s in symmetries if s["kind"] == "rotation"]
    if len(rotations) == 1 and rotations[0]["order"] >= 3 and mirrors:
        rot = rotations[0]
        # dihedral() made the planes through the axis hold it exactly.
        axial = [m for m in mirrors if _cos_to_axis(m, rot) < 1e-6]
        across = [m for m in mirrors if _cos_to_axis(m, rot) > 1 - 1e-6]
        if axial and len(axial) + len(across) == len(mirrors):
            a = _unit(rot["axis"])
            start = _turned(_unit(np.cross(a, axial[0]["normal"])), a, -math.pi / rot["order"])
            return across + [axial[0], {**rot, "sector_start": start.tolist()}]
    if mirrors:
        return mirrors
    return symmetries if len(symmetries) == 1 else []


def symmetric_surface(surface, symmetries):
    """The surface with its solver mesh made exactly symmetric under mesh_symmetries(): each
    reflection in turn (native symmetric_surface: one half cut at the plane and mirrored), or
    the rotation (one sector cut between two half-planes through the axis and turned n times,
    rotation_surface.h), so that a strip's image is the image of its loop on the graph too. A
    part not rotation-symmetric enough for one sector to stand for the others (the welded
    mesh's genus or boundaries would differ) keeps its mesh."""
    for sym in mesh_symmetries(symmetries):
        try:
            surface = native.symmetric_surface(surface, sym, sym.get("sector_start", []))
        except native.InputError:
            if sym["kind"] == "reflection":
                raise
    return surface


def _images(sym):
    return 1 if sym["kind"] == "reflection" else sym["order"] - 1


def hausdorff(a, b):
    """Two-sided distance of two polylines (model units)."""
    identity = {"kind": "reflection", "point": [0, 0, 0], "normal": [1, 0, 0]}
    return max(native.image_distance(identity, 0, a, b), native.image_distance(identity, 0, b, a))


def orbit(surface, symmetries, anchors, loop_points, tolerance, existing=()):
    """The images of a strip (its anchors and its loop's points) under the group the
    symmetries generate (each applied in turn to every image so far: for a rotation with a
    mirror through its axis, the whole dihedral orbit), without the strip itself: images
    whose loop lies within `tolerance` of the strip's loop, of an earlier image, or of a loop
    in `existing` are left out (a loop that is its own mirror image needs no copy).
    Every anchor is mapped: a loop through two anchors, searched again through the first's
    image alone, closes wherever is cheapest (a loop beside both ends of a hub's axis, whose
    images then passed its bottom anywhere).
    Returns ([(anchors, expected loop points)], the largest distance of an image left out as
    the strip's own loop from that loop: 0 for a loop exactly its own image)."""
    elements = [([list(a) for a in anchors], np.asarray(loop_points, dtype=float))]
    for sym in symmetries:
        for group, points in list(elements):
            mapped = [native.anchor_images(surface, sym, a) for a in group]   # per anchor, per k
            for k in range(1, _images(sym) + 1):
                elements.append(([list(m[k - 1]) for m in mapped], native.map_points(sym, points, k)))
    kept = [elements[0]]
    own = 0.0     # how far the images that coincide with the strip's own loop are from it
    for group, points in elements[1:]:
        d = hausdorff(points, elements[0][1])
        if d <= tolerance:
            own = max(own, d)
            continue
        if any(hausdorff(points, p) <= tolerance for _, p in kept[1:]) or \
                any(hausdorff(points, p) <= tolerance for p in existing):
            continue
        kept.append((group, points))
    return kept[1:], own


def axis_seeds(surface, symmetries, fractions=(0.5, 0.35, 0.65)):
    """Per rotation among the symmetries and per clearance fraction, the anchors of one loop
    beside every point where the rotation's axis meets the surface (native axis_seeds,
    axis_seeds.h): a loop through such a point has its n - 1 images through it too, so the
    symmetric layout puts a valence-n vertex there, in the n-gon the loop and its images make
    when it passes beside it. The fractions are of the largest clearance that keeps the
    n-gon's corners on the smooth cap around the point: the middle first, then nearer and
    farther (where the images of a chord's ends run down a hub's side too close together,
    another clearance parts them). Anchor lists in model units; none where the axis misses
    the surface (a flange's bore, a ring).

    Odd orders only. A rotation of even order holds the half-turn, which maps a chord beside
    the axis onto the parallel chord across it: the two would be one strip's two sides, and the
    compatibility mask refuses the image (a screw's half-turn: every such seed refused, 130
    work units spent). There a loop through the point is what the group keeps: its own image
    under a half-turn, and crossing its quarter-turn image at right angles."""
    out = []
    for sym in symmetries:
        if sym["kind"] == "rotation" and sym["order"] % 2 == 1:
            out += [[list(a) for a in seed] for seed in native.axis_seeds(surface, sym, list(fractions)) if seed]
    return out


def image_tolerance(surface):
    """How close an image must come to a loop to be that loop (model units): loops are chains
    of graph nodes, so an image closer than two solver edges is that loop on this graph (a loop
    that crosses the mirror orthogonally is its own image)."""
    return 2.0 * mean_edge_length(surface)


def add_images(ds, index, symmetries, tolerance, own_tolerance):
    """Add the images of strip `index` of the DesignSession `ds` (orbit(): its anchors
    mapped and re-projected, its loop searched again there, all in one derivation); images
    that coincide with the strip or a strip before it are left out. Used by the weave and by
    the workbench's design tool, so a strip gets one set of images whoever adds it.
    Returns the number of images added. On a refusal nothing of them is kept and strip
    `index` is removed too (a design stays symmetric or does not take the strip): InputError
    saying why, its reason one line; Cancelled (a loop search cut short) propagates after the
    same clean-up. Refused: a loop its own image only to more than `own_tolerance` (a loop
    through a g-edge beside the mirror), an image the design refuses, and an image whose loop,
    searched afresh, strays more than `tolerance` from the image of the strip's loop (the
    compatibility mask of the strips before it, an asymmetric solver mesh)."""
    strip = ds.strip(index)
    existing = [ds.strip(j)["points"] for j in range(index)]
    anchors = [a.to_list() for a in ds.design.strips[index].anchors]
    images, own = orbit(ds.surface, symmetries, anchors, strip["points"], tolerance, existing)
    if own > own_tolerance and len(symmetries) == 1 and symmetries[0]["kind"] == "rotation" and len(anchors) == 1:
        images, own = _turned_onto_itself(ds, index, symmetries, anchors[0], tolerance, existing, (images, own))
    if own > own_tolerance:
        ds.remove_strip(index)
        raise native.InputError(f"the loop is its own symmetric image only to {own:.3g}")
    if not images:
        return 0
    try:
        ds.add_strips([group for group, _ in images], [{"image_of": index} for _ in images])
    except native.InputError as e:
        ds.remove_strip(index)
        raise native.InputError(f"a symmetric image is refused by the design ({e})") from None
    except native.Cancelled:
        ds.remove_strip(index)
        raise
    for j, (_, expected) in enumerate(images):
        if hausdorff(ds.strip(index + 1 + j)["points"], expected) > tolerance:
            ds.remove_strips(index, 1 + len(images))
            raise native.InputError("a symmetric image's loop is not the image of the strip's loop")
    return len(images)


def _turned_onto_itself(ds, index, symmetries, anchor, tolerance, existing, before):
    """A loop that the rotation maps onto itself only to within `tolerance` (around the axis):
    on a rotation-symmetric solver mesh the search returns one of n equal-cost turned copies
    of the loop, each within an edge of the others, and such a strip was refused (the
    order-5 hub: 0.15 to 0.5 mm, against 1e-3 of the diagonal, 0.044 mm). Anchored at its
    anchor and the anchor's n - 1 images in turn, its loop is n turned copies of one
    cheapest leg (each leg ends where the next begins, in the same direction: a rotation
    keeps a loop's sense), so it is exactly its own image. Both senses of turning are tried
    (the anchor's direction decides which the loop runs), the cheaper kept. Returns
    (images, own) of orbit(): those of `before` if neither sense gives a loop; the strip then
    keeps its one anchor."""
    rotation = symmetries[0]
    turned = [list(a) for a in native.anchor_images(ds.surface, rotation, anchor)]
    best = current = None     # the cheaper sense, and the one the strip has now
    for order in (turned, turned[::-1]):
        try:
            ds.edit_strip(index, [anchor] + order)   # a refusal restores the strip as it was
        except native.InputError:
            continue
        current = order
        if best is None or ds.strip(index)["cost"] < best[0]:
            best = (ds.strip(index)["cost"], order)
    if best is None:
        return before
    if best[1] is not current:
        ds.edit_strip(index, [anchor] + best[1])
    anchors = [a.to_list() for a in ds.design.strips[index].anchors]
    return orbit(ds.surface, symmetries, anchors, ds.strip(index)["points"], tolerance, existing)


def mean_edge_length(surface):
    """The solver mesh's mean edge length, model units: loops are chains of graph nodes, so
    two loops closer than this are one loop on this graph."""
    v, t = surface.vertices, surface.triangles
    e = np.concatenate([v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 1]], v[t[:, 0]] - v[t[:, 2]]])
    return float(np.linalg.norm(e, axis=1).mean()) if len(e) else 0.0


def layout_symmetry_error(layout, sym):
    """The largest distance from a mapped layout vertex to the nearest layout vertex (model
    units): 0 when the vertex set maps to itself; None without vertices."""
    p = np.array([v["position"] for v in layout.get("vertices", [])], dtype=float).reshape(-1, 3)
    if not len(p):
        return None
    worst = 0.0
    for k in range(1, _images(sym) + 1):
        q = native.map_points(sym, p, k)
        d = np.sqrt(((q[:, None, :] - p[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
        worst = max(worst, float(d.max()))
    return worst


def loops_symmetry_error(loops, sym):
    """The largest two-sided distance, over the loops (point arrays, model units) and the
    symmetry's maps, from a loop's image to the nearest loop: 0 when every loop's image is a
    loop of the design."""
    worst = 0.0
    for a in loops:
        for k in range(1, _images(sym) + 1):
            image = native.map_points(sym, a, k)
            worst = max(worst, min(hausdorff(image, b) for b in loops))
    return worst
