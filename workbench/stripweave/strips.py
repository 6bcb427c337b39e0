"""Stage 3, dual strips (paper §4.1, §6): a design on a surface, with everything it implies.

    ds = DesignSession(surface, Design.load("design.json"))
    ds.strips()            # per strip: points, widths, area fraction, closed, ...
    ds.singularities()     # cross-field singularities: position, index (multiples of 1/4)
    ds.add_strip([(x, y, z)])           # the best compatible loop through the point
    ds.loops([(x, y, z)], alternatives=5)   # proposals that cross every strip transversally
    ds.strips_json()       # the content of strips.json (design.md)

Every edit recomputes the derived state (loops, cross field, parameterization,
strips, compatibility mask) from the first strip that changed. Strip i's loop
is searched under the compatibility mask of strips 0..i-1 (§6.2).
"""
import numpy as np

from ._native import native
from .design import Design
from .loops import LoopSession


class DesignSession:
    """A surface, its loop engine and a design, kept consistent."""

    def __init__(self, surface, design=None, loop_session=None, features=True, threads=2):
        self.surface = surface
        self.design = design if design is not None else Design()
        self.loop_session = loop_session or LoopSession(surface, threads=threads, **self.design.loop_options())
        self.native = native.DesignState(self.loop_session.native, features,
                                         self.design.options["boundary"] == "aligned")
        self.native.compatibility_band = self.design.options.get("compatibility_band")
        self.native.compatibility_angle = float(self.design.options.get("compatibility_angle_deg", 45))
        self.update()

    # --- editing -----------------------------------------------------------
    def update(self):
        """Recompute what changed since the last update (after editing self.design)."""
        self.apply_layout_inputs()
        try:
            self.native.set_strips(self.design.anchor_lists())
        finally:
            # The strips computed so far (all of them, or those before a failing one).
            for i, strip in enumerate(self.design.strips[:self.native.strip_count]):
                strip.closed = bool(self.native.strip(i)["closed"])

    def apply_layout_inputs(self):
        """Hand the design's pins, edge routes and symmetries to the layout: the layout's alone
        (nothing to derive), so the regions' vertices and edges follow them without recomputing
        the strips."""
        self.apply_hand_placed()
        self.native.layout_symmetries = list(self.design.symmetry or [])

    def apply_hand_placed(self):
        """Hand the design's pins and edge routes (paper §7, manual) to the layout."""
        self.native.vertex_pins = self.design.pins
        self.native.edge_routes = [(r["through"], r["across"]) for r in self.design.edge_routes]

    def add_strip(self, anchors):
        """Append a strip; on failure (an InputError, or a loop search cancelled or past
        the session's query cap) the design is left as it was."""
        self.design.add_strip(anchors)
        try:
            self.update()
        except (native.InputError, native.Cancelled):
            self.design.remove_strip(len(self.design.strips) - 1)
            self.update()
            raise
        return len(self.design.strips) - 1

    def add_strips(self, anchor_lists, extras=None):
        """Append several strips with one update (a strip's symmetric images, symmetry.py);
        on failure none of them is kept. Returns the index of the first."""
        first = len(self.design.strips)
        for i, anchors in enumerate(anchor_lists):
            self.design.add_strip(anchors)
            if extras is not None:
                self.design.strips[-1].extra.update(extras[i])
        try:
            self.update()
        except (native.InputError, native.Cancelled):
            del self.design.strips[first:]
            self.update()
            raise
        return first

    def remove_strip(self, index):
        self.design.remove_strip(index)
        self.update()

    def remove_strips(self, first, count):
        """Remove strips first .. first + count - 1 with one update."""
        self.design.remove_strips(first, count)
        self.update()

    def edit_strip(self, index, anchors):
        old = self.design.strips[index]
        self.design.edit_strip(index, anchors)
        try:
            self.update()
        except native.InputError:
            self.design.strips[index] = old
            self.update()
            raise

    # --- proposals -----------------------------------------------------------
    def loops(self, anchors, alternatives=1):
        """Loops through the anchors that are compatible with every strip (dicts, as LoopSession.loops)."""
        self.native.apply_mask()
        try:
            return self.loop_session.loops(anchors, alternatives)
        finally:
            self.loop_session.native.clear_disabled()

    def best_loop(self, point):
        self.native.apply_mask()
        try:
            return self.loop_session.best_loop(point)
        finally:
            self.loop_session.native.clear_disabled()

    # --- results -------------------------------------------------------------
    def strip(self, index):
        return self.native.strip(index)

    def strips(self):
        return [self.native.strip(i) for i in range(self.native.strip_count)]

    def singularities(self):
        return self.native.singularities()

    def stripe_coordinates(self, index):
        """Per vertex (along, across) of strip `index` in model units, NaN outside it: a stripe
        pattern of uniform density is a periodic function of `across`."""
        corner = self.native.strip_coordinates(index)
        out = np.full((len(self.surface.vertices), 2), np.nan)
        tris = self.surface.triangles
        inside = ~np.isnan(corner[:, 0, 0])
        # Where the conquest met itself (a closed strip's seam) a vertex has two values; keep the first.
        for c in range(3):
            v = tris[inside, c]
            fresh = np.isnan(out[v, 0])
            out[v[fresh]] = corner[inside, c][fresh]
        return out

    def timings_ms(self):
        return dict(self.native.timings_ms)

    def strips_json(self):
        """The content of strips.json (design.md), plus diagnostics."""
        strips = []
        for s in self.strips():
            strips.append({
                "points": s["points"].tolist(),
                "closed": bool(s["closed"]),
                "length": s["length"],
                "width_left": s["width_left"],
                "width_right": s["width_right"],
                "stop_left": s["stop_left"],
                "stop_right": s["stop_right"],
                "area_fraction": s["area_fraction"],
            })
        singularities = [{"position": x["position"], "index": x["index"]} for x in self.singularities()]
        v, f = len(self.surface.vertices), len(self.surface.triangles)
        e = len({tuple(sorted(p)) for t in self.surface.triangles.tolist() for p in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))})
        return {
            "strips": strips,
            "singularities": singularities,
            "index_sum": sum(x["index"] for x in singularities),
            "euler_characteristic": v - e + f,
            "fold_overs": self.native.fold_overs,
            "timings_ms": self.timings_ms(),
        }
