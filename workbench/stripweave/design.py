"""Designs and the design file (`design.json`, see ../shared/design.md; paper §4.1).

A design is an ordered list of strips. Each strip is its anchors (points the
loop passes, with or without a tangent direction), in model units; its loop is
derived by the loop search, never stored as truth. So a design survives
re-tessellation: loading it onto a model re-projects the anchors.

    d = Design.load("design.json")
    d.add_strip([(5, 5, 10, 1, 0, 0)])
    d.remove_strip(0)
    d.save("design.json")

The file format:
    {"format": "stripweave-design", "version": 1,
     "model": {"path": ..., "bbox_diagonal": ...},
     "options": {"k": 4, "max_turn_deg": 30, "alpha": 1.0, "beta": 0.25,
                 "boundary": "aligned", "feature_angle_deg": 30},
     "strips": [{"anchors": [{"point": [x, y, z], "direction": [dx, dy, dz] | null}],
                 "closed": true}],
     "symmetry": [{"kind": "reflection", "point": [x, y, z], "normal": [..], "source": "given",
                   "rms_error": e, "max_error": e},
                  {"kind": "rotation", "point": [..], "axis": [..], "order": n, ...}]}
Only format, version and strips are required; "symmetry" (symmetry.py, paper §5.8) is kept
as read (None when absent: a design without it loads and saves as before); missing options take the
defaults above. Keys this version does not know are kept on save, at every
level (a newer tool's additions survive an edit here).
"""
import copy
import json
import math
import os

from ._native import native

FORMAT = "stripweave-design"
VERSION = 1
DEFAULT_OPTIONS = {"k": 4, "max_turn_deg": 30, "alpha": 1.0, "beta": 0.25, "boundary": "aligned",
                   "feature_angle_deg": 30,
                   # How far from its loop (model units) a strip refuses parallel loops; None is the
                   # paper's whole strip (§6.2). A finite band allows denser layouts.
                   "compatibility_band": None,
                   # Within the band, loops whose direction is within this angle of the strip's
                   # are refused: 45 is the paper's (§6.2); more asks for crossings nearer to
                   # right angles (automatic refinement, weave.py).
                   "compatibility_angle_deg": 45}
# Ranges of the numeric options (a NaN or 1e308 must not reach the native side).
OPTION_RANGES = {"k": (1, 16, int), "max_turn_deg": (1, 179, float), "alpha": (0, 1e6, float),
                 "beta": (0, 1e6, float), "feature_angle_deg": (1e-6, 179.999, float)}


def _in_range(value, low, high, kind):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    if kind is int and not isinstance(value, int):
        return False
    return low <= value <= high  # False for NaN


# The options the loop search takes (the rest belong to the surface stage).
LOOP_OPTIONS = ("k", "max_turn_deg", "alpha", "beta", "boundary")


def _error(where, what):
    return native.InputError(f"design file{where}: {what}")


def _vector(value, where, what):
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise _error(where, f"{what} must be a list of three numbers, got {value!r}")
    try:
        v = [float(x) for x in value]
    except (TypeError, ValueError, OverflowError):
        raise _error(where, f"{what} must be a list of three numbers, got {value!r}") from None
    if not all(math.isfinite(x) for x in v):
        raise _error(where, f"{what} has a NaN or infinite coordinate")
    return v


class Anchor:
    """A point the loop passes, optionally with its tangent there (sign irrelevant)."""

    def __init__(self, point, direction=None, extra=None):
        self.point = [float(x) for x in point]
        self.direction = None if direction is None else [float(x) for x in direction]
        self.extra = dict(extra or {})

    @classmethod
    def of(cls, value):
        """An Anchor from an Anchor, (x,y,z) or (x,y,z,dx,dy,dz)."""
        if isinstance(value, Anchor):
            return value
        value = list(value)
        if len(value) == 3:
            return cls(value)
        if len(value) == 6:
            return cls(value[:3], value[3:])
        raise native.InputError(f"an anchor is (x, y, z) or (x, y, z, dx, dy, dz), got {value!r}")

    def to_list(self):
        return self.point + (self.direction or [])

    def to_dict(self):
        return {**self.extra, "point": list(self.point), "direction": None if self.direction is None else list(self.direction)}

    def __repr__(self):
        return f"Anchor({self.point}, {self.direction})"


class Strip:
    """A strip as its anchors; `closed` is what the loop search decided (None until then)."""

    def __init__(self, anchors, closed=None, extra=None):
        self.anchors = [Anchor.of(a) for a in anchors]
        if not self.anchors:
            raise native.InputError("a strip needs at least one anchor")
        self.closed = closed
        self.extra = dict(extra or {})

    def to_dict(self):
        d = {**self.extra, "anchors": [a.to_dict() for a in self.anchors]}
        if self.closed is not None:
            d["closed"] = bool(self.closed)
        return d


class Design:
    """An ordered list of strips, with the loop options and the model it was made on, and the
    points where the user put primal vertices (`pins`, model units: paper §7, a vertex dragged
    within its region; the layout moves each pinned region's vertex there), and the primal
    edges the user routed by hand (`edge_routes`, model units: paper §7, where in its corridor
    a patch boundary lies; each {"through": point, "across": point} takes the edge whose arc
    passes nearest "across" through "through")."""

    def __init__(self, strips=(), options=None, model=None, extra=None, symmetry=None, pins=None,
                 edge_routes=None):
        self.strips = [s if isinstance(s, Strip) else Strip(s) for s in strips]
        self.pins = [[float(x) for x in p] for p in (pins or ())]
        self.edge_routes = [{k: [float(x) for x in r[k]] for k in ("through", "across")}
                            for r in (edge_routes or ())]
        self.symmetry = None if symmetry is None else [dict(x) for x in symmetry]
        self.options = {**DEFAULT_OPTIONS, **(options or {})}
        self.model = dict(model or {})
        self.extra = dict(extra or {})

    # --- editing -----------------------------------------------------------
    def add_strip(self, anchors):
        self.strips.append(Strip(anchors))
        return len(self.strips) - 1

    def remove_strip(self, index):
        self.remove_strips(index, 1)

    def remove_strips(self, first, count):
        """Remove strips first .. first + count - 1. A strip that was the image of a removed
        one (its "image_of") is an image no longer; later images name their originals anew."""
        del self.strips[first:first + count]
        for s in self.strips:
            original = s.extra.get("image_of")
            if original is None or original < first:
                continue
            if original < first + count:
                del s.extra["image_of"]
            else:
                s.extra["image_of"] = original - count

    def edit_strip(self, index, anchors):
        self.strips[index] = Strip(anchors, extra=self.strips[index].extra)

    def anchor_lists(self):
        """Per strip, its anchors as (x,y,z[,dx,dy,dz]) lists: what the native design takes."""
        return [[a.to_list() for a in s.anchors] for s in self.strips]

    def loop_options(self):
        return {k: self.options[k] for k in LOOP_OPTIONS}

    def copy(self):
        return copy.deepcopy(self)

    # --- the file ------------------------------------------------------------
    @classmethod
    def from_dict(cls, data):
        if not isinstance(data, dict):
            raise _error("", "the top level must be a JSON object")
        if data.get("format") != FORMAT:
            raise _error("", f"'format' must be '{FORMAT}', got {data.get('format')!r}")
        if not isinstance(data.get("version"), int) or data["version"] < 1:
            raise _error("", f"'version' must be a positive integer, got {data.get('version')!r}")
        if data["version"] > VERSION:
            raise _error("", f"version {data['version']} is newer than this StripWeave reads ({VERSION})")
        if not isinstance(data.get("strips"), list):
            raise _error("", "'strips' must be a list")
        options = data.get("options", {}) or {}
        if not isinstance(options, dict):
            raise _error("", "'options' must be an object")
        boundary = options.get("boundary", DEFAULT_OPTIONS["boundary"])
        if boundary not in ("aligned", "trimmed"):
            raise _error("", f"options.boundary must be 'aligned' or 'trimmed', got {boundary!r}")
        band = options.get("compatibility_band")
        if band is not None and (isinstance(band, bool) or not isinstance(band, (int, float)) or band <= 0):
            raise _error("", f"options.compatibility_band must be a positive length or null, got {band!r}")
        angle = options.get("compatibility_angle_deg", DEFAULT_OPTIONS["compatibility_angle_deg"])
        if isinstance(angle, bool) or not isinstance(angle, (int, float)) or not 0 < angle < 90:
            raise _error("", f"options.compatibility_angle_deg must be within (0, 90) degrees, got {angle!r}")
        for key, (low, high, kind) in OPTION_RANGES.items():
            if key in options and not _in_range(options[key], low, high, kind):
                raise _error("", f"options.{key} must be {'a whole number' if kind is int else 'a number'} "
                                 f"within [{low:g}, {high:g}], got {options[key]!r}")
        if not isinstance(data.get("model", {}) or {}, dict):
            raise _error("", "'model' must be an object")
        symmetry = data.get("symmetry")
        if symmetry is not None:
            from .symmetry import check
            if not isinstance(symmetry, list):
                raise _error("", "'symmetry' must be a list")
            for i, entry in enumerate(symmetry):
                check(entry, f", symmetry {i + 1}")
        pins = data.get("pins", [])
        if not isinstance(pins, list):
            raise _error("", "'pins' must be a list of points")
        pins = [_vector(p, f", pin {i + 1}", "a pin") for i, p in enumerate(pins)]
        routes = data.get("edge_routes", [])
        if not isinstance(routes, list):
            raise _error("", "'edge_routes' must be a list of {\"through\": point, \"across\": point}")
        for i, r in enumerate(routes):
            if not isinstance(r, dict) or set(r) != {"through", "across"}:
                raise _error(f", edge route {i + 1}", "an edge route needs exactly 'through' and 'across' points")
        routes = [{k: _vector(r[k], f", edge route {i + 1}", k) for k in ("through", "across")}
                  for i, r in enumerate(routes)]
        strips = []
        for i, s in enumerate(data["strips"]):
            where = f", strip {i + 1}"
            if not isinstance(s, dict) or not isinstance(s.get("anchors"), list) or not s["anchors"]:
                raise _error(where, "a strip needs a non-empty 'anchors' list")
            anchors = []
            for j, a in enumerate(s["anchors"]):
                at = f"{where}, anchor {j + 1}"
                if not isinstance(a, dict) or "point" not in a:
                    raise _error(at, "an anchor needs a 'point'")
                point = _vector(a["point"], at, "point")
                direction = a.get("direction")
                if direction is not None:
                    direction = _vector(direction, at, "direction")
                    if not any(direction):
                        raise _error(at, "direction must not be zero (use null for a positional anchor)")
                anchors.append(Anchor(point, direction, {k: v for k, v in a.items() if k not in ("point", "direction")}))
            closed = s.get("closed")
            strips.append(Strip(anchors, closed if isinstance(closed, bool) else None,
                                {k: v for k, v in s.items() if k not in ("anchors", "closed")}))
        return cls(strips, options, data.get("model"),
                   {k: v for k, v in data.items()
                    if k not in ("format", "version", "model", "options", "strips", "symmetry", "pins",
                                 "edge_routes")}, symmetry, pins, routes)

    def to_dict(self):
        d = {**self.extra, "format": FORMAT, "version": VERSION, "model": dict(self.model),
             "options": dict(self.options), "strips": [s.to_dict() for s in self.strips]}
        if self.symmetry is not None:
            d["symmetry"] = [dict(x) for x in self.symmetry]
        if self.pins:
            d["pins"] = [list(p) for p in self.pins]
        if self.edge_routes:
            d["edge_routes"] = [{k: list(r[k]) for k in ("through", "across")} for r in self.edge_routes]
        return d

    @classmethod
    def load(cls, path):
        """Read a design file; every way it can be unusable is a one-line InputError."""
        path = os.fspath(path)
        if not os.path.exists(path):
            raise native.InputError(f"design file {path} does not exist")
        if not os.path.isfile(path):  # a FIFO or a device is read forever
            raise native.InputError(f"design file {path} is not a regular file")
        try:
            with open(path, encoding="utf-8") as f:
                data = json.load(f)
        except json.JSONDecodeError as exc:
            raise native.InputError(f"design file {path} is not valid JSON: {exc}") from None
        except UnicodeDecodeError as exc:
            raise native.InputError(f"design file {path} is not UTF-8 text (byte {exc.start}: "
                                    f"{exc.object[exc.start:exc.start + 1]!r})") from None
        except RecursionError:
            raise native.InputError(f"design file {path} nests its JSON too deeply") from None
        except OSError as exc:
            raise native.InputError(f"cannot read design file {path}: {exc.strerror or exc}") from None
        return cls.from_dict(data)

    def save(self, path):
        """Write design.json atomically (files.write_atomic): a failed or concurrent save never
        destroys or mixes the user's design; a symlink and the file's mode are kept."""
        from .files import write_atomic
        write_atomic(path, json.dumps(self.to_dict(), indent=2) + "\n")
