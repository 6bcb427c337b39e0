"""Automatic weaving (issue 6): complete a design strip by strip, as a user would.

    ds = DesignSession(surface, design)         # empty or partial: the user's strips are kept
    result = auto_weave(ds, WeaveOptions(max_strips=30))
    result.log            # per added strip: why (region, colour, seed point) and what it did
    result.assessment     # the final regions (weave_assessment)

The paper's tool (§4) is interactive: the user hovers, the system proposes the best
strip through the cursor (§5), the region colours (§4.2) say where strips are still
needed. Automatic weaving plays the user: it picks seed points in the order
    red regions (not discs: no valid layout yet), then orange (several singularities,
    i.e. curvature extrema, in one region), then yellow (valence and curvature disagree),
    then the largest area no strip covers,
asks for the best compatible loop there (several seed points per region: its centre,
then farthest-point samples; ranked alternatives when those fail), scores each proposal
by the assessment it would give, adds the best one, and rejects an addition that makes
the assessment worse. When nothing is coloured and the uncovered area is small, a refine
phase goes past the paper's colours: it splits the patch with the worst corner (a strip
across its longest side) while the real layout's mean corner deviation drops. It stops at
the deviation or patch target, the time limit (which never stops work on red regions), or
the strip limit. Loop queries that run too long are cancelled (then, and only then, the
result can depend on the machine's speed).

A strip is added as one directional anchor (a g' node of the proposed loop: point and
tangent), so that re-deriving the design (DesignState) finds the same loop quickly and
deterministically. The same design and options always give the same result. All geometry
(regions, centres, uncovered areas, anchors) is native (`weave_assessment`, `loop_anchor`);
this module only decides.
"""
import os
import sys
import threading
import time
from dataclasses import dataclass, field, replace

from ._native import native

COLOURS = ("red", "orange", "yellow")
# STRIPWEAVE_WEAVE_DEBUG=path: save each design before it is derived (to replay a crash).
_DEBUG_DESIGN = os.environ.get("STRIPWEAVE_WEAVE_DEBUG")


@dataclass
class WeaveOptions:
    """What automatic weaving aims at (see the module doc)."""
    max_strips: int = 40            # strips in the design at most (the user's included)
    patches: int = 0                # target patch count (0: as coarse as the colours allow)
    uncovered: float = 0.04         # stop seeding uncovered areas below this fraction of the surface
    seeds_per_region: int = 3       # seed points tried per region (centre first)
    alternatives: int = 3           # ranked alternatives tried when no seed point helps
    seed: int = 0                   # which seed point to try first (varies the result, deterministically)
    time_limit_s: float = 16.0      # after this, only red regions are still worked on
    refine: bool = True             # then split the patches with the worst corners (needs the layout)
    refine_deviation_deg: float = 12.0   # ... while the mean corner deviation is above this
    refine_patches: int = 160       # ... and the layout has fewer patches than this (0: no limit)
    query_timeout_s: float = 6.0    # a loop query running longer is cancelled (no proposal there)
    verbose: bool = False           # progress on stderr

    def check(self):
        if self.max_strips < 0:
            raise native.InputError(f"max strips must be 0 or more, got {self.max_strips}")
        if self.patches < 0:
            raise native.InputError(f"the patch target must be 0 (none) or more, got {self.patches}")
        if not 0 <= self.uncovered <= 1:
            raise native.InputError(f"the uncovered fraction must be within [0, 1], got {self.uncovered}")
        if self.seeds_per_region < 1 or self.alternatives < 1:
            raise native.InputError("seeds per region and alternatives must be at least 1")


@dataclass
class WeaveResult:
    log: list = field(default_factory=list)      # per added strip: reason and effect
    assessment: dict = None
    stopped: str = ""                            # why weaving stopped
    time_ms: float = 0.0


def score(a):
    """How far an assessment is from a good layout, smaller is better (compared as tuples):
    first validity (red regions, weighted by how far from a disc they are), then the
    regions the paper flags for quality (orange: extra singularities, yellow: valence
    mismatch), then the coarseness (fewer regions)."""
    red = [r for r in a["regions"] if r["colour"] == "red"]
    # A handle is cut by a non-separating loop (genus - 1, two more boundaries: chi unchanged),
    # then holes are joined by cuts between them (chi + 1): both count as progress.
    genus = sum(r["genus"] for r in red)
    badness = sum(max(1, abs(1 - r["euler_characteristic"])) for r in red)
    orange = sum(max(0, r["singularities"] - 1) for r in a["regions"] if r["colour"] == "orange")
    yellow = sum(abs(r["valence"] - r["ideal_valence"]) for r in a["regions"] if r["colour"] == "yellow")
    return (genus, badness, orange + 0.5 * yellow)


def seeds_in_order(a, options, skip):
    """(reason, region id, colour, [points]) in the order the issue asks: red, orange, yellow
    regions (each colour largest first), then the largest uncovered area."""
    out = []
    for colour in COLOURS:
        regions = [(i, r) for i, r in enumerate(a["regions"]) if r["colour"] == colour]
        for i, r in sorted(regions, key=lambda x: (-x[1]["area"], x[0])):
            points = [p for p in r["seeds"] if _key(p) not in skip]
            if points:
                k = options.seed % len(points)
                points = points[k:] + points[:k]
            if colour == "red":
                # After the centre: across each loop that leaves the region on both sides (the
                # cut that completes a handle's meridian), then the other seed points.
                crossing = [c for c in r.get("crossing_anchors", []) if _key(c) not in skip]
                points = points[:1] + crossing + points[1:]
            if points:
                out.append((f"{colour} region", i, colour, points))
    u = a["uncovered"]
    # No crossing yet means no patch at all (a disc cut by nothing is "valid"): keep weaving.
    wanted = u["largest_area"] > options.uncovered * u["surface_area"] or a["crossings"] == 0
    if u["found"] and wanted and _key(u["point"]) not in skip:
        out.append(("uncovered area", -1, "uncovered", [u["point"]]))
    if a["crossings"] == 0 and a["colours"]["red"] == 0:
        # Valid but no patch yet (a sphere cut once, a disc): the largest regions' centres.
        for i, r in sorted(enumerate(a["regions"]), key=lambda x: (-x[1]["area"], x[0])):
            points = [p for p in r["seeds"] if _key(p) not in skip]
            if points:
                out.append(("no patch yet", i, "uncovered", points))
    return out


def _key(p):
    return tuple(round(float(x), 6) for x in p)


def _say(options, text):
    if options.verbose:
        print(f"stripweave weave: {text}", file=sys.stderr, flush=True)


class _Weaver:
    def __init__(self, ds, options):
        self.ds, self.options = ds, options
        self.session = ds.loop_session.native

    def assess(self, extra=(), seeds=True):
        return native.weave_assessment(self.ds.native, list(extra), self.options.seeds_per_region if seeds else 0)

    def proposals(self, point, alternatives):
        """Loops through the point, best first; when the all-directions query gives nothing in
        time, the best loops along the two principal directions there (one-direction queries
        are fast)."""
        found = self._proposals(point, alternatives)
        if not found and len(point) == 3:
            for anchor in native.principal_anchors(self.ds.surface, list(point)):
                found += self._proposals(anchor, 1)
            found.sort(key=lambda loop: loop.cost)
        return found

    def _proposals(self, point, alternatives):
        """Loops through the point compatible with every strip (§6.2), best first. A query
        that runs past the timeout is cancelled: some points (a cusp, a narrow neck under
        many strips) admit no good loop, and waiting for it would stall the whole weave."""
        self.ds.native.apply_mask()
        watchdog = threading.Timer(self.options.query_timeout_s, self.session.cancel)
        watchdog.start()
        try:
            if alternatives <= 1 and len(point) == 3:
                return [self.session.best_loop(list(point), True)]
            return list(self.session.loops([list(point)], alternatives, True))
        except (native.InputError, native.Cancelled):
            return []
        finally:
            watchdog.cancel()
            self.session.clear_disabled()

    def candidates(self, points, alternatives, current):
        """(score, cost, loop, point) of proposals at the points, best first. Points are tried
        in order and the search stops at the first point whose proposals improve on
        `current`: the region's centre usually does, and each further point costs a loop
        search and an arrangement."""
        out = []
        for point in points:
            for loop in self.proposals(point, alternatives):
                a = self.assess([loop], seeds=False)
                out.append((score(a), loop.cost, loop, point, a))
            if out and min(c[0] for c in out) < current:
                break
        out.sort(key=lambda c: (c[0], c[1]))
        return out

    def add(self, loop, point):
        """Add the loop as one directional anchor; None if the design rejects it."""
        anchor = native.loop_anchor(self.session, loop, list(point)[:3])
        if _DEBUG_DESIGN:   # the design about to be derived, for reproducing native failures
            d = self.ds.design.copy()
            d.add_strip([anchor])
            d.save(_DEBUG_DESIGN)
        try:
            index = self.ds.add_strip([anchor])
        except native.InputError:
            return None
        return index


def _layout(ds):
    from .layout import compute_layout
    return compute_layout(ds)


def _deviation(layout):
    return layout["summary"]["corner_deviation_deg"]["mean"] if layout["valid"] and layout["patches"] else 180.0


def _refine(w, ds, options, a, result, elapsed):
    """Past the paper's colours: a region can be fine by §4.2 and still give patches with
    corners far from 90 degrees (a cube-like layout wrapped on a cylinder). Split the worst
    patch by the best strip across its longest side (seeded at that side's middle), keep it
    if the mean corner deviation of the real layout drops, until the deviation or the patch
    count is reached or time runs out."""
    try:
        layout = _layout(ds)
    except ImportError:
        return a
    tried = set()
    while len(ds.design.strips) < options.max_strips and elapsed() < options.time_limit_s:
        deviation = _deviation(layout)
        patches = len(layout["patches"])
        if deviation <= options.refine_deviation_deg:
            result.stopped = "done"
            break
        limit = options.patches or options.refine_patches
        if limit and patches >= limit:
            result.stopped = "patch target"
            break
        # Patches by their worst corner, then the middle of each one's longest side.
        order = sorted(range(patches), key=lambda i: -max((abs(x - 90) for x in layout["patches"][i]["corner_angles_deg"]),
                                                          default=0.0))
        seed = None
        for i in order:
            sides = sorted(layout["patches"][i]["edges"], key=lambda e: (-layout["edges"][e]["length"], e))
            points = layout["edges"][sides[0]]["points"]
            p = points[len(points) // 2]
            if _key(p) not in tried:
                seed, worst = p, i
                break
        if seed is None:
            result.stopped = "no seed helps"
            break
        tried.add(_key(seed))
        _say(options, f"strip {len(ds.design.strips) + 1}: refine patch {worst} (corner deviation "
                      f"{deviation:.1f} deg, {patches} patches, {elapsed():.1f} s)")
        proposals = w.proposals(seed, 1)
        if not proposals:
            continue
        index = w.add(proposals[0], seed)
        if index is None:
            continue
        after_layout = _layout(ds)
        after = w.assess()
        if after["colours"]["red"] or score(after)[0] > score(a)[0] or _deviation(after_layout) >= deviation:
            ds.remove_strip(index)
            continue
        ds.design.strips[index].extra["added_by"] = {"reason": "corner deviation", "region": -1,
                                                     "colour": "none", "seed": [float(x) for x in seed]}
        result.log.append({"strip": index, "reason": "corner deviation", "region": -1, "colour": "none",
                           "seed": [float(x) for x in seed], "anchor": ds.design.strips[index].anchors[0].to_list(),
                           "cost": proposals[0].cost, "deviation_before": deviation,
                           "deviation_after": _deviation(after_layout), "time_s": round(elapsed(), 3)})
        a, layout = after, after_layout
    else:
        result.stopped = "max strips" if len(ds.design.strips) >= options.max_strips else "time limit"
    return a


def auto_weave(ds, options=None):
    """Complete the design of `ds` (a DesignSession) by adding strips; see the module doc.
    The design's existing strips are kept, first and unchanged."""
    options = options or WeaveOptions()
    options.check()
    w = _Weaver(ds, options)
    start = time.perf_counter()
    result = WeaveResult()
    a = w.assess()
    skip = set()          # seed points that gave nothing useful
    stalls = 0            # consecutive red-phase additions that did not lower the score
    escalated = False     # looked harder once already
    user_strips = len(ds.design.strips)

    def elapsed():
        return time.perf_counter() - start

    while True:
        if len(ds.design.strips) >= options.max_strips:
            result.stopped = "max strips"
            break
        current = score(a)
        valid = a["colours"]["red"] == 0
        if valid and (options.patches or options.refine_patches) and \
                a["crossings"] >= (options.patches or options.refine_patches):
            result.stopped = "patch target"
            break
        seeds = seeds_in_order(a, options, skip)
        if valid and elapsed() > options.time_limit_s:
            result.stopped = "time limit"
            break
        if not seeds and a["colours"]["red"] and not escalated:
            # Invalid and out of ideas: look harder once (more seed points per region, more
            # ranked alternatives), rather than end with no layout.
            escalated = True
            w.options = options = replace(options, seeds_per_region=3 * options.seeds_per_region,
                                          alternatives=2 * options.alternatives)
            skip.clear()
            stalls = 0
            a = w.assess()
            continue
        if not seeds:
            result.stopped = "done" if valid and not a["colours"]["orange"] + a["colours"]["yellow"] else "no seed helps"
            break
        reason, region, colour, points = seeds[0]
        _say(options, f"strip {len(ds.design.strips) + 1}: {reason} {region} "
                      f"(red {a['colours']['red']}, orange {a['colours']['orange']}, "
                      f"yellow {a['colours']['yellow']}, {elapsed():.1f} s)")
        added = None
        tried_real = False
        # Ranked alternatives (slow: a second search per rank) only where validity is at stake.
        for alternatives in ((1, options.alternatives) if colour == "red" else (1,)):
            tried = points if alternatives == 1 else points[:1]
            for s, cost, loop, point, predicted in w.candidates(tried, alternatives, current):
                improves = s < current
                if colour == "red" and not improves and s[:2] <= current[:2] and stalls < 3:
                    improves = True   # a handle can take two loops to cut (a torus: meridian, then equator)
                if colour == "uncovered":
                    improves = s <= current   # coverage, without spoiling the colours
                    if not improves and a["crossings"] == 0 and s[:2] <= current[:2]:
                        improves = True       # no patch yet: any valid strip is progress
                if not improves and colour in ("orange", "yellow") and s[:2] <= current[:2] and not tried_real:
                    # The prediction keeps the old singularities, which the new strip moves:
                    # give the best proposal one real try.
                    improves = tried_real = True
                if not improves and colour != "red" and a["crossings"] == 0 and s[:2] <= current[:2]:
                    improves = True   # no patch yet: a valid strip that crosses is progress
                if not improves:
                    break             # candidates are sorted: none after this one is better
                index = w.add(loop, point)
                if index is None:
                    continue
                after = w.assess()
                # While there is no patch, only validity counts (the colours come with patches).
                worse = score(after) > current and not (a["crossings"] == 0 and score(after)[:2] <= current[:2])
                no_gain = colour == "uncovered" and after["uncovered"]["area"] >= a["uncovered"]["area"] \
                    and after["crossings"] <= a["crossings"]
                if worse or no_gain:
                    ds.remove_strip(index)   # the re-derived design is worse than predicted: reject
                    continue
                stalls = stalls + 1 if score(after)[:2] >= current[:2] and colour == "red" else 0
                added = {"strip": index, "reason": reason, "region": region, "colour": colour,
                         "seed": [float(x) for x in point[:3]], "anchor": list(ds.design.strips[index].anchors[0].to_list()),
                         "cost": cost, "score_before": list(current), "score_after": list(score(after)),
                         "time_s": round(elapsed(), 3)}
                a = after
                break
            if added:
                break
        if added:
            ds.design.strips[added["strip"]].extra["added_by"] = {
                k: added[k] for k in ("reason", "region", "colour", "seed")}
            result.log.append(added)
            continue
        for p in points:      # nothing helped from this region's seeds: do not ask again
            skip.add(_key(p))

    if result.stopped == "done" and options.refine:
        a = _refine(w, ds, options, a, result, elapsed)
    result.assessment = a
    result.time_ms = elapsed() * 1000.0
    _say(options, f"{result.stopped}: {len(ds.design.strips)} strips ({user_strips} given, "
                  f"{len(result.log)} added), red {a['colours']['red']}, orange {a['colours']['orange']}, "
                  f"yellow {a['colours']['yellow']}, {elapsed():.1f} s")
    return result
