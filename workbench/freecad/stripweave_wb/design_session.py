"""The derived state of a Design object: a cached ``DesignSession`` and
immutable snapshots of it for drawing.

No document access and no Qt here, so every function may run on a worker
thread.  One :class:`SessionCache` lives on each Design proxy; it owns the
``stripweave.strips.DesignSession`` (loop engine, cross field,
parameterization, strips, compatibility mask) and a lock that serialises
every use of it: the GUI thread's recompute, the design tool's hover worker
and the background derivation after a document is reopened all go through
it.  Hover queries can be interrupted (a newer query wins, and an edit must
not wait for a stale preview); edits and updates never are, because a
cancelled update would leave the native state half-changed.

After every change of the derived state the cache takes a :class:`Derived`
snapshot (numpy arrays and plain values, in model units) that the view
provider draws and the Design object publishes, so drawing never touches the
native session.
"""

import json
import threading

import numpy as np

from . import import_stripweave
from .lift import NormalLift
from .loop_match import loop_gap, same_loop_tolerance

# Where on a proposed loop to take directional anchors (fractions of its
# points), after the one nearest the hovered point.  The design's loop search
# from one g' node of an alternative often finds the alternative again, but
# not always: an alternative (the k-th best loop through a point) need not be
# the best loop through any one of its nodes.  Two or three of its nodes
# together pin it (generated box and cylinder, 48 alternatives: one anchor
# reproduced 35, one to three all 48).
ANCHOR_SAMPLES = (0.25, 0.5, 0.75)
# How far (diagonals) a symmetry may map the surface off itself and be accepted: design.md's 1e-3.
SYMMETRY_TOLERANCE = 1e-3


def anchor_sets(anchors):
    """The anchor sets to try for a proposal with ``anchors`` (nearest the
    hovered point first, then at ANCHOR_SAMPLES): each alone, then the nearest
    with the opposite one, then the nearest with the two quarter points.
    Fewer anchors first: a one-anchor search is the fastest, and a strip with
    fewer anchors is easier to edit."""
    sets = [[a] for a in anchors]
    if len(anchors) == 4:
        sets += [[anchors[0], anchors[2]], [anchors[0], anchors[1], anchors[3]]]
    return sets


def _native():
    import_stripweave()
    from stripweave._native import native
    return native


def design_key(design, features):
    """What the derived state depends on besides the surface: the strips'
    anchors, the options, the Features flag and the accepted symmetries (a
    reflection changes the solver mesh, solver_surface; every one the images an
    added strip gets) (JSON text, comparable)."""
    maps = [{k: s.get(k) for k in ("kind", "point", "normal", "axis", "order")} for s in design.symmetry or []]
    return json.dumps([design.anchor_lists(), design.options, bool(features), maps], sort_keys=True)


def loop_options_key(design):
    """The options the loop engine (elastica graph) is built with: changing
    them needs a new LoopSession (a graph build), the rest only an update.
    The accepted symmetries the solver mesh is made exact under change it,
    hence the graph."""
    return json.dumps([design.loop_options(), mesh_maps(design)], sort_keys=True)


def mesh_maps(design):
    """The design's symmetries its solver mesh depends on (kind, point, normal
    or axis, order: stripweave.symmetry.mesh_symmetries)."""
    import_stripweave()
    from stripweave.symmetry import mesh_symmetries
    return [[s["kind"], s["point"], s.get("normal"), s.get("axis"), s.get("order")]
            for s in mesh_symmetries(design.symmetry)]


def solver_surface(surface, design):
    """The surface the design's strips are derived on: with symmetries accepted, made
    exactly symmetric under them (stripweave.symmetry.symmetric_surface: one half cut at a
    mirror plane and mirrored, or one sector turned about a rotation's axis), so that a
    strip's image is the image of its loop on the graph too (a tessellation symmetric only
    roughly put a mirrored loop 0.3 off on a 46 mm slab, past design.md's 1e-3 of the
    diagonal); the surface itself otherwise."""
    if not mesh_maps(design):
        return surface
    from stripweave.symmetry import symmetric_surface
    return symmetric_surface(surface, design.symmetry)


# The options the native DesignState is made with (its constructor and its
# compatibility settings, §6.2): an imported design that differs in them
# needs a new DesignState, or its strips are searched under the old mask
# rules (a woven design's band and 60-degree angle refused 6 of 10 strips).
STATE_OPTIONS = ("boundary", "compatibility_band", "compatibility_angle_deg")


def state_options_key(design):
    return json.dumps({k: design.options.get(k) for k in STATE_OPTIONS}, sort_keys=True)


class Derived:
    """A snapshot of everything a design implies, for drawing and reports.

    ``strips``: per strip a dict with ``points`` ((k,3) array, the loop),
    ``closed``, ``length``, ``width_left``, ``width_right``,
    ``area_fraction``, ``stop_left``, ``stop_right`` and ``across`` (per
    solver-mesh vertex the signed distance from the loop inside the strip,
    NaN outside).  ``lift``: moves points off the surface for drawing.  ``singularities``: list of ((x,y,z), index).  ``error``:
    the InputError text when a strip failed (``strips`` then holds the ones
    before it), else None.
    """

    def __init__(self, revision, key, vertices, normals, triangles, lift, strips, singularities,
                 fold_overs, error, requested):
        self.revision = revision
        self.lift = lift  # NormalLift of the solver mesh (lift.py)
        self.key = key
        self.vertices = vertices
        self.normals = normals
        self.triangles = triangles
        self.strips = strips
        self.singularities = singularities
        self.fold_overs = fold_overs
        self.error = error
        self.requested = requested  # number of strips in the design (>= len(strips))

    def singularity_counts(self):
        """{"+1/4": n, "-1/4": n, "other": n}."""
        counts = {"+1/4": 0, "-1/4": 0, "other": 0}
        for _pos, index in self.singularities:
            if abs(index - 0.25) < 1e-6:
                counts["+1/4"] += 1
            elif abs(index + 0.25) < 1e-6:
                counts["-1/4"] += 1
            else:
                counts["other"] += 1
        return counts

    def summary(self):
        """JSON-safe digest (what the Design object stores in ``Summary``)."""
        return {
            "strips": [{k: (bool(s[k]) if k == "closed" else s[k]) for k in (
                "closed", "length", "width_left", "width_right", "area_fraction", "stop_left", "stop_right")}
                for s in self.strips],
            "requested_strips": self.requested,
            "singularities": [{"position": list(p), "index": i} for p, i in self.singularities],
            "singularity_counts": self.singularity_counts(),
            "fold_overs": self.fold_overs,
            "error": self.error,
        }


def _strip_record(session, i, raw):
    across = session.stripe_coordinates(i)[:, 1]
    return {
        "points": np.asarray(raw["points"], dtype=float).reshape(-1, 3),
        "closed": bool(raw["closed"]),
        "length": float(raw["length"]),
        "width_left": float(raw["width_left"]),
        "width_right": float(raw["width_right"]),
        "area_fraction": float(raw["area_fraction"]),
        "stop_left": str(raw.get("stop_left", "")),
        "stop_right": str(raw.get("stop_right", "")),
        "across": np.asarray(across, dtype=float),
    }


class SessionCache:
    """A DesignSession, its lock, and the latest :class:`Derived` snapshot."""

    def __init__(self):
        self.lock = threading.RLock()
        self._flag_lock = threading.Lock()
        self._querying = False
        self.session = None
        self.surface = None
        self._loop_key = None
        self._state_key = None
        self._features = None
        self.applied_key = None      # design_key of what the session reflects
        self._mask_key = None        # (session, revision) whose mask the loop engine holds
        self.derived = None
        self.revision = 0
        self._mesh = None

    # -- hover queries ------------------------------------------------------------
    def interrupt(self):
        """Stop a running hover query (it raises Cancelled), so that the
        caller gets the lock soon.  Never touches an update or an edit."""
        with self._flag_lock:
            if self._querying and self.session is not None:
                self.session.loop_session.native.cancel()

    def query(self, fn, masked=True):
        """Run ``fn(loop_session)`` as an interruptible query on the loop
        engine under the design's compatibility mask (§6.2), or under none
        (``masked`` False: the mask of every strip would refuse a grabbed
        strip's own moved loop, which re-routing searches under the mask of
        the strips before it only); the caller holds no lock.  Returns
        (value, revision)."""
        with self.lock:
            if self.session is None:
                raise RuntimeError("the design is not derived yet")
            if masked:
                self._apply_mask()
            else:
                self.session.loop_session.native.clear_disabled()
                self._mask_key = None
            with self._flag_lock:
                self._querying = True
            try:
                return fn(self.session.loop_session), self.revision
            finally:
                with self._flag_lock:
                    self._querying = False

    def proposals(self, point, alternatives=1, masked=True):
        """What the design tool shows through ``point`` (or through the
        directional anchor ``point`` = (x, y, z, dx, dy, dz) of a drag, or
        through a list of anchors: Shift+click's, each proposal then
        "exact": adding it adds those anchors): with alternatives
        1 the hover query (the best loop over all directions), else up to
        that many ranked alternatives.  Each is a dict as
        ``LoopSession.describe`` plus ``anchors``: directional anchors on the
        loop (native ``loop_anchor``, the one nearest ``point`` first) from
        which :meth:`add_shown` tries to derive it again.  Interruptible.
        ``masked`` False: under no compatibility mask (a grabbed strip's
        moved loop, whose own strip must not refuse it; see :meth:`query`)."""
        native = _native()
        several = len(point) > 0 and isinstance(point[0], (list, tuple))
        anchors = [[float(c) for c in a][:6] for a in (point if several else [point])]
        point = anchors[0][:3]   # a directional anchor (x, y, z, dx, dy, dz): a drag (§4.1)

        def run(ls):
            if alternatives <= 1 and len(anchors) == 1 and len(anchors[0]) == 3:
                loops = [ls.native.best_loop(point, True)]
            else:
                loops = ls.native.loops(anchors, int(alternatives), True)
            out = []
            for loop in loops:
                d = ls.describe(loop)
                if several:   # Shift+click's strip: the design searches these anchors again
                    d["anchors"], d["exact"] = anchors, True
                    out.append(d)
                    continue
                pts = d["points"]
                samples = [point] + [pts[int(f * len(pts))] for f in ANCHOR_SAMPLES if pts]
                d["anchors"] = [list(native.loop_anchor(ls.native, loop, list(p))) for p in samples]
                out.append(d)
            return out
        return self.query(run, masked)

    def reproducing_anchors(self, anchors, shown):
        """The first of ``anchor_sets(anchors)`` from which the design's own
        loop search (what adding a strip derives: one loop through the
        anchors, under the current compatibility mask) finds the polyline
        ``shown`` again, with its gap; (None, smallest gap) if none does.
        Not interruptible: it decides an edit."""
        sw = import_stripweave()
        with self.lock:
            self._require()
            self._apply_mask()
            tolerance = same_loop_tolerance(self.session.surface.vertices)
            best_gap = float("inf")
            for candidate in anchor_sets([list(a) for a in anchors]):
                try:
                    found = self.session.loop_session.loops(candidate, 1)
                except sw.InputError:
                    continue
                gap = loop_gap(found[0]["points"], shown) if found else float("inf")
                if gap <= tolerance:
                    return candidate, gap
                best_gap = min(best_gap, gap)
            return None, best_gap

    def add_shown(self, anchors, shown):
        """Add the strip whose loop is the polyline ``shown`` (a proposal with
        these ``anchors``), from the first anchor set that derives it again;
        InputError (nothing added) if none does.  Returns (design dict,
        snapshot)."""
        sw = import_stripweave()
        with self.lock:
            candidate, gap = self.reproducing_anchors(anchors, shown)
            if candidate is None:
                raise sw.InputError(
                    "no anchors on the loop shown make the design derive it (the nearest derived loop is "
                    "{:.3g} away): choose another alternative or another point".format(gap))
            return self.add_strip(candidate)

    def _apply_mask(self):
        # DesignSession.best_loop/loops recompute the mask for every query
        # and clear it after; computing it costs as much as a hover query
        # (~65 ms at 30K triangles), so apply it once per derived state and
        # keep it between queries.  Updates clear it (set_strips ends with an
        # empty mask): they reset _mask_key, and so does handing the session out.
        key = (id(self.session), self.revision)
        if self._mask_key != key:
            self.session.native.apply_mask()
            self._mask_key = key

    def session_for_caller(self):
        """The DesignSession for direct use (its own queries clear the mask)."""
        with self.lock:
            self._mask_key = None
            return self.session

    # -- updates ----------------------------------------------------------------
    def is_current(self, surface, design, features):
        return (self.session is not None and self.surface is surface
                and self.applied_key == design_key(design, features))

    def sync(self, surface, design, features):
        """Make the session reflect ``design`` on ``surface`` and return the
        snapshot.  A strip that fails is recorded in ``Derived.error`` (the
        design itself is never changed here)."""
        sw = import_stripweave()
        from stripweave.design import Design
        from stripweave.strips import DesignSession

        self.interrupt()
        with self.lock:
            key = design_key(design, features)
            loop_key = loop_options_key(design)
            state_key = state_options_key(design)
            if (self.session is None or self.surface is not surface or self._loop_key != loop_key
                    or self._features != bool(features) or self._state_key != state_key):
                reuse = None
                if self.session is not None and self.surface is surface and self._loop_key == loop_key:
                    reuse = self.session.loop_session  # Features or compatibility changed: keep the graph
                # Built empty, then updated: a failing strip must not lose the session.
                self.session = DesignSession(solver_surface(surface, design), Design(options=design.options),
                                             loop_session=reuse,
                                             features=bool(features))
                self.surface = surface
                self._loop_key = loop_key
                self._features = bool(features)
                self._state_key = state_key
                self._mesh = None
                self.applied_key = None
            if key == self.applied_key and self.derived is not None:
                self.session.design = design  # same strips: only unknown keys, pins or symmetries may differ
                self.session.apply_layout_inputs()   # the layout's alone: nothing to derive
                return self.derived
            self.session.design = design
            self._mask_key = None
            error = None
            try:
                self.session.update()
            except sw.InputError as exc:
                error = str(exc)
            except BaseException:
                self.applied_key = None  # unknown state: redo next time
                raise
            self.applied_key = key
            return self._snapshot(error)

    def add_strip(self, anchors):
        """Append a strip (reverted on InputError, which propagates).
        Returns (design dict, snapshot)."""
        with self.lock:
            self._require()
            self._mask_key = None
            self.session.add_strip(anchors)
            try:
                self._add_images(len(self.session.design.strips) - 1)
            finally:   # added with its images, or neither: the session reflects its design
                self.applied_key = design_key(self.session.design, self._features)
            return self.session.design.to_dict(), self._snapshot(None)

    def _add_images(self, index):
        """The design's accepted symmetries (design.json's "symmetry", paper §5.8): strip
        ``index`` gets its images too (stripweave.symmetry.add_images, as the weave does);
        a refused image removes the strip again and raises InputError saying why."""
        symmetries = self.session.design.symmetry
        if not symmetries:
            return 0
        from stripweave.symmetry import add_images, image_tolerance
        surface = self.session.surface
        own = SYMMETRY_TOLERANCE * surface.bbox_diagonal
        # The graph's resolution: a loop its own image within it needs no copy (the GUI's
        # solver mesh is not made symmetric, so the weave's tighter test would refuse it).
        return add_images(self.session, index, symmetries, image_tolerance(surface), max(own, image_tolerance(surface)))

    def edit_strip(self, index, anchors):
        """Replace strip ``index``'s anchors and re-derive from it (strip
        ``index``'s loop under the mask of the strips before it, §6.2; the
        later ones again under theirs).  Reverted on InputError, which
        propagates.  Returns (design dict, snapshot)."""
        with self.lock:
            self._require()
            if not 0 <= index < len(self.session.design.strips):
                raise IndexError("the design has no strip {}".format(index + 1))
            self._mask_key = None
            self.session.edit_strip(index, anchors)
            self.applied_key = design_key(self.session.design, self._features)
            return self.session.design.to_dict(), self._snapshot(None)

    def run(self, fn):
        """``fn(design_session)`` under the lock (no hover query or edit in
        between), for work that reads the derived state: the layout, the fit."""
        self.interrupt()   # a hover query gives way
        with self.lock:
            self._require()
            self._mask_key = None
            return fn(self.session)

    def weave(self, options, on_session=None):
        """Complete the design by automatic weaving (stripweave.weave) with
        ``options`` (a WeaveOptions; its ``cancel`` event stops it) and adopt
        the result.  The weave runs on a second DesignSession over the same
        loop engine, so a cancelled or failed weave leaves this cache as it
        was.  Without ``options.symmetry`` the design's accepted symmetries are used.  ``on_session(ds)`` gets the weave's DesignSession (to watch its
        strips).  Returns (WeaveResult, design dict, snapshot)."""
        from stripweave.strips import DesignSession
        from stripweave.weave import auto_weave
        self.interrupt()   # a hover query gives way
        with self.lock:
            self._require()
            ds = DesignSession(self.session.surface, self.session.design.copy(), loop_session=self.session.loop_session,
                               features=self._features)
            if not options.symmetry and ds.design.symmetry:
                # The accepted symmetries (the design tool's Symmetry tab): every strip the weave
                # adds comes with its images, as a click's strip does.
                import dataclasses
                options = dataclasses.replace(options, symmetry=tuple(ds.design.symmetry))
            self._mask_key = None
            if on_session is not None:
                on_session(ds)
            result = auto_weave(ds, options)
            self.session = ds
            self._state_key = state_options_key(ds.design)
            self.applied_key = design_key(ds.design, self._features)
            return result, ds.design.to_dict(), self._snapshot(None)

    def _require(self):
        if self.session is None:
            raise RuntimeError("the design is not derived yet")

    def _snapshot(self, error):
        s = self.session
        if self._mesh is None:
            surf = s.surface
            vertices, normals = np.asarray(surf.vertices, dtype=float), np.asarray(surf.normals, dtype=float)
            self._mesh = (vertices, normals, np.asarray(surf.triangles, dtype=np.int64),
                          NormalLift(vertices, normals))
        strips = []
        try:
            for i, raw in enumerate(s.strips()):
                strips.append(_strip_record(s, i, raw))
        except Exception as exc:  # what could be derived, plus why not more
            error = error or "strips: {}".format(exc)
        try:
            singularities = [(tuple(float(c) for c in x["position"]), float(x["index"]))
                             for x in s.singularities()]
        except Exception:
            singularities = []
        try:
            fold_overs = int(s.native.fold_overs)
        except Exception:
            fold_overs = 0
        self.revision += 1
        self.derived = Derived(self.revision, self.applied_key, *self._mesh, strips, singularities, fold_overs,
                               error, len(s.design.strips))
        return self.derived
