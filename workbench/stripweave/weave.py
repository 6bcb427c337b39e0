"""Automatic weaving (issue 6): complete a design strip by strip, as a user would.

    ds = DesignSession(surface, design)         # empty or partial: the user's strips are kept
    result = auto_weave(ds, WeaveOptions(max_strips=30))
    result.log            # per added strip: why (region, colour, seed point) and what it did
    result.assessment     # the final regions (weave_assessment)

The paper's tool (§4) is interactive: the user hovers, the system proposes the best
strip through the cursor (§5), the region colours (§4.2) say where strips are still
needed. Automatic weaving plays the user: it picks seed points in the order
    red regions (not discs: no valid layout yet), then closed discs no loop crossing bounds
    (valence 0: none of their surface lies in a patch, patchless; a cylinder of an assembly
    cut once while the other parts have patches), then crease regions (they keep the layout
    from following the part's creases, issue 17), then discs that touch the open boundary
    in two or more stretches (one vertex closes one; the rest would lie in no patch:
    open_stretches), across the bridge between two of them, then orange (several curvature extrema
    of one kind in one region: extra_extrema), then yellow (valence and curvature
    disagree), orange and yellow only where the region's vertex would have valence 2 or
    6 and more (extreme_only), then the largest area no strip covers,
asks for the best compatible loop there (several seed points per region: its centre,
then farthest-point samples; ranked alternatives when those fail), scores each proposal
by the assessment it would give, adds the best one, and rejects an addition that makes
the assessment worse. Red regions take the best-scored, cheapest proposal over all their
seed points (a cube's first seed point is a corner, and a belt through a corner leaves a
180-degree patch corner); the round's other proposals that cut are tried next, each kept
only if the design derived with it lowers the red regions' genus or badness again, before
a new round asks every seed point again (_more_cuts: a part with many handles took a round
of queries per cut). Once every crease region was asked for one loop, if the part's rims
(closed creases with no junction) lack crossings, the score counts that lack before the crease
excess and the crease seeds are asked once more (rim_lack, crease_rims.h: a loop across a rim
raises the excess until others part its pieces, so the excess alone never crosses one). With
crease_pairs, those no single loop parts are then asked for two that cross each other
(_crease_pair: a rim needs a loop across it and one round the feature's wall, and neither
helps alone).
Where most of the part is an area no strip covers and every loop proposed there leaves
a red region (a key whose strips lie on its ring: a loop around the shaft cuts off its
end), that loop is added with the red phase's loop that crosses the
region it leaves, both or neither (_coverage_pair); while most of the part lies in no patch
the refit takes (a quad), a strip or pair there may raise the crease excess if it brings more
of the part into such patches (_FitRescue: a loop along a shaft crosses every crease ringing
it, and a key's first two loops left one patch, no quad, over the whole part). Why orange
and yellow only at valence 2 or 6+: on scans every strip brings new field singularities, and chasing every coloured
region left the rocker-arm with 4 valence-2 and 3 valence-6 vertices (27 degrees mean
corner deviation; 19.9 without), while a cube needs its third belt to split the valence-2
lenses around pairs of corners. When no seed helps any more (or colour_share of the budget
is spent), a refine phase adds strips between the existing ones. Per step it takes the
patches with the most area times corner deviation (_split_need), and for each the loops
that would shorten its long sides: through the middle of a short side, along it (_splits: the middle of the
corridor between the loop that crosses the long sides and its next parallel), last the
old anchor across the patch. Each candidate's layout is predicted under the design's
current singularities (`predict`: loops, arrangement and primal layout, no field or
parameterization solve; the corners came out as after the solve in all but a few of the
rocker-arm's candidates; a loop that several seeds propose is predicted once per design
state), the best of refine_candidates is derived, and kept only if the
real layout improves: its mean corner deviation (patches that do not read as quads
counted 90 degrees off) plus region_penalty_deg per flaw of the assessment it adds (flaws:
extra extrema, valence mismatch, vertices of valence 2 or 6 and more the curvature does
not ask for). Flaws it removes do not pay for worse corners: on scans the flaws are dozens
of noise extrema (the rocker-arm: 110), whose count moves by a few with any strip and
outweighed the corners (kept strips made the corners worse). For it an empty design gets a
compatibility band (`band`), so that loops beside existing ones are allowed, and a
compatibility angle of refine_angle_deg (the paper's 45 lets a loop cross a strip at 45
degrees, and such crossings are patch corners 45 degrees off; 60 measured: rocker-arm 16.6
against 21.0 degrees, ec_soapbox-A 16.1 against 16.6, spot 27.9 either way, bumpy-cube 16.5
against 15.3, where it stopped at fewer patches). The switch is kept only if the design
is no further from valid and clean under it, and where crease regions remain the crease
phase then runs once more under the band: the loops that part creases running side by
side run beside the strips along them (_crease_phase_under_the_band). It stops at
the deviation or patch target (no candidate that would pass refine_patches is taken), the
work budget (past which only red regions are worked on, up to red_reserve budgets in all
plus one red strip's work per cut the part's handles and holes ask for, cuts_to_discs;
the budget counts from the first valid design, so the work validity takes leaves the
crease, colour and refining phases their whole budget; the strips that part stretches of
open boundary or cross patchless discs have one budget of their own, _Weaver.quality_work), or the strip limit. Refinement
never takes a strip that leaves a red region, more crease excess, more crease inside
patches, or more defective patches and vertices, whatever the corners gain.

Last, weaving takes back what it added and the layout is cleaner without (_take_back):
a strip judged good where it was added can come to bound slivers once later strips run
beside it or cross near its crossings, and only its removal merges them away (a cow's 24
degenerate patches went to 1, and its 96 patches to 58). One budget of its own.

Validity comes first to the end. While a region is red, the other colours leave room under
the strip cap for the cuts the red regions still need (cuts_to_discs), and when they are
done (or out of that room) with a region still red, the red seed points are asked once
more, in the design their strips made: each strip moves the regions and the field, so a
point that gave nothing may cut now. Once, at the end: asked after every strip, they cost
the crease phase its work.

The work budget counts what weaving does, not how long it takes, so the same input gives
the same design on any machine: a loop query is half a unit plus its own work count
(WORK_PER_POLL per poll, one per 4096 settled g' nodes; queries run on one thread, where
the count is exact, and stop at query_polls, refine_query_polls in the refine phase: a
refining loop that needs more search is a long detour, never kept in our measurements),
scoring a candidate half a unit, predicting its layout one and a half, deriving the design
with a strip added (field and parameterization, the dearest step) four, a primal layout
one. Removing the strip just added costs nothing: DesignState keeps the state from before
the last edit and swaps it back (a rejected strip used to cost a second derivation). A
unit is about 0.08 s on our 2-core machines when they are not
shared. Two wall-clock safety nets stay, generous enough never to act on the shared
models on an idle machine: time_limit_s for the whole weave and query_timeout_s per loop
query. Only they can make the result depend on the machine's speed, and the result says
when they acted (`stopped` "time limit (safety net)", `cancelled_queries`).

A strip is added as one directional anchor (a g' node of the proposed loop: point and
tangent), so that re-deriving the design (DesignState) finds the same loop quickly and
deterministically. The same design and options always give the same result. All geometry
(regions, centres, uncovered areas, anchors, layouts) is native (`weave_assessment`,
`loop_anchor`, `compute_layout`); this module only decides.
"""
import copy
import math
import os
import sys
import threading
import time
from dataclasses import dataclass, field, replace
from typing import Optional

from ._native import native

COLOURS = ("red", "crease", "orange", "yellow")
# Seeds whose strips cover surface no patch would (patchless, open_stretches): validity-like,
# so they get ranked alternatives and both families of loops, and a budget of their own.
COVERAGE = ("patchless", "open")
# STRIPWEAVE_WEAVE_DEBUG=path: save each design before it is derived (to replay a crash).
_DEBUG_DESIGN = os.environ.get("STRIPWEAVE_WEAVE_DEBUG")


@dataclass
class WeaveOptions:
    """What automatic weaving aims at (see the module doc)."""
    max_strips: Optional[int] = None  # strips in the design at most (the user's included); None: the cuts
                                    # the topology asks for plus STRIPS_BEYOND_CUTS (_Weaver.max_strips)
    patches: int = 0                # target patch count (0: as coarse as the colours allow)
    uncovered: float = 0.04         # stop seeding uncovered areas below this fraction of the surface
    seeds_per_region: int = 3       # seed points tried per region (centre first)
    alternatives: int = 3           # ranked alternatives tried when no seed point helps
    seed: int = 0                   # which seed point to try first (varies the result, deterministically)
    budget: float = 200.0           # work units (module doc), counted from the first valid design; past it,
                                    # only red regions are worked on
    time_limit_s: float = 90.0      # wall-clock safety net, same effect (inf: none)
    red_reserve: float = 4.0        # red regions may spend this many budgets (and time limits) in all, plus
                                    # the work of a red strip per cut of the topology (red_allowance), then
                                    # weaving stops with them left: a run never loops forever (a model on
                                    # which no loop ever makes a region a disc looped until killed)
    band: float = 0.03              # refinement's compatibility_band (empty designs), in bbox diagonals (0: the paper's)
    refine_angle_deg: float = 60.0  # ... and its compatibility angle (empty designs; 45: the paper's)
    colours: tuple = COLOURS        # the region colours that get strips (red always does)
    extreme_only: bool = True       # ... orange and yellow ones only where their vertex has valence 2 or 6+
    colour_share: float = 0.5       # ... spending at most this share of the budget before refining
    refine: bool = True             # then split the patches with the worst corners (needs the layout)
    region_penalty_deg: float = 5.0 # ... kept if the corners improve, each flaw of the assessment counted as this
    refine_deviation_deg: float = 12.0   # ... while the mean corner deviation is above this
    max_area_ratio: float = 20.0    # ... or a patch is larger than this many median patches (0: no bound)
    refine_patches: int = 160       # ... and the layout has fewer patches than this (0: no limit)
    refine_query_polls: int = 100   # ... its loop queries stopped past this work (0: query_polls)
    refine_candidates: int = 2      # ... predicting this many candidate strips per added one, the best derived
    take_back: bool = True          # last, take back added strips the layout is cleaner without (_take_back)
    take_back_share: float = 1.0    # ... spending at most this share of the budget on it
    crease_pairs: bool = False      # crease regions no single loop parts get pairs of crossing loops once
                                    # every one was asked for one, after the rims (rim_lack):
                                    # _crease_pair, a pocket's rim; off by default, as on the shared
                                    # models the pairs' work came out of the colour phases (README,
                                    # "pairs of loops")
    query_polls: int = 400          # a loop query doing more work is stopped (no proposal there; 0: no cap)
    seed_directions: str = "adaptive"   # at a seed point: "all" (the best loop over all directions, the
                                    # principal directions where it gives none), "principal" (the loops
                                    # along its two principal directions first), or "adaptive" ("all"
                                    # until an all-directions query runs past query_polls, then
                                    # "principal"); see proposals()
    query_timeout_s: float = 20.0   # a loop query running longer is cancelled (wall-clock safety net)
    symmetry_tolerance: float = 1e-3  # ... a loop that is its own image must be so within this (diagonals)
    symmetry: tuple = ()            # symmetries (symmetry.py dicts, model units): every added strip comes
                                    # with its images on the other parts (paper §5.8)
    verbose: bool = False           # progress on stderr
    cancel: object = None           # a threading.Event: once set, weaving raises Cancelled at its next step
                                    # (a GUI's Cancel; with the loop session's cancel() it stops within a step)

    def check(self):
        if self.max_strips is not None and self.max_strips < 0:
            raise native.InputError(f"max strips must be 0 or more, got {self.max_strips}")
        if self.patches < 0:
            raise native.InputError(f"the patch target must be 0 (none) or more, got {self.patches}")
        if not 0 <= self.uncovered <= 1:
            raise native.InputError(f"the uncovered fraction must be within [0, 1], got {self.uncovered}")
        if self.seeds_per_region < 1 or self.alternatives < 1:
            raise native.InputError("seeds per region and alternatives must be at least 1")
        if not self.budget >= 0:
            raise native.InputError(f"the work budget must be 0 or more, got {self.budget}")
        if not self.time_limit_s > 0:
            raise native.InputError(f"the time limit must be positive (inf: none), got {self.time_limit_s}")
        if not self.red_reserve >= 1 or not math.isfinite(self.red_reserve):
            raise native.InputError(f"the red reserve must be a finite number of budgets, 1 or more, "
                                    f"got {self.red_reserve}")
        if self.seed_directions not in ("adaptive", "principal", "all"):
            raise native.InputError(f"seed directions must be 'adaptive', 'principal' or 'all', "
                                    f"got {self.seed_directions!r}")
        if not self.band >= 0 or not 0 <= self.colour_share <= 1 or self.query_polls < 0:
            raise native.InputError("band and query polls must be 0 or more, the colour share within [0, 1]")
        unknown = set(self.colours) - set(COLOURS)
        if unknown:
            raise native.InputError(f"unknown region colours {sorted(unknown)}: use {', '.join(COLOURS)}")


@dataclass
class WeaveResult:
    log: list = field(default_factory=list)      # per added strip: reason and effect
    assessment: dict = None
    stopped: str = ""                            # why weaving stopped
    time_ms: float = 0.0
    work: float = 0.0                            # work units spent (module doc)
    cancelled_queries: int = 0                   # loop queries cut by the timeout (machine-dependent)
    capped_queries: int = 0                      # loop queries stopped by query_polls (no proposal there)
    max_strips: int = 0                          # the strip cap weaving had (_Weaver.max_strips)
    taken_back: list = field(default_factory=list)   # per strip taken back at the end (_take_back)


def extra_extrema(region):
    """How many more curvature extrema of one kind an orange region holds than one vertex can
    take (the native assessment's excess_extrema, assessment.h: a lens around two cube
    corners: 1; a +1/4, -1/4 pair: 0)."""
    return int(region["excess_extrema"])


def flaws(a):
    """The assessment's quality flaws (§4.2) in one number: curvature extrema of one kind
    beyond the first in orange regions (extra_extrema), half the valence mismatch of yellow
    regions, and each region whose vertex will have valence 2 or 6 and more where the
    curvature does not ask for it (|valence - ideal| > 1/2): a valence-2 vertex is two 180
    degree corners on a flat part, a valence-6 one six 60 degree corners, and a valence-1
    one (a lobe one arc bounds: a loop that curls across itself) the tip of a dangling edge,
    around which the patch at the crossing folds."""
    extreme = sum(1 for r in a["regions"] if r["disc"] and (1 <= r["valence"] <= 2 or r["valence"] >= 6)
                  and abs(r["valence"] - r["ideal_valence"]) > 0.5)
    return colour_flaws(a) + extreme


def shows(region, colour):
    """Whether a region has the flaw of an assessment colour (§4.2), whatever colour it is
    shown in: a region shows one colour (red, then crease, then orange, then yellow), and
    a crease region may also hold extrema to split or a valence mismatch."""
    if colour in ("red", "crease"):
        return region["colour"] == colour
    if not region["disc"]:
        return False
    orange = extra_extrema(region) > 0
    if colour == "orange":
        return orange
    return not orange and abs(region["valence"] - region["ideal_valence"]) > 1 + 1e-9


def colour_flaws(a):
    """Orange and yellow flaws in one number (§4.2): curvature extrema of one kind beyond
    the first (extra_extrema), plus half of each yellow region's valence mismatch."""
    orange = sum(extra_extrema(r) for r in a["regions"] if shows(r, "orange"))
    yellow = sum(abs(r["valence"] - r["ideal_valence"]) for r in a["regions"] if shows(r, "yellow"))
    return orange + 0.5 * yellow


def score(a):
    """How far an assessment is from a good layout, smaller is better (compared as tuples):
    first validity (red regions, weighted by how far from a disc they are), then the crease
    regions (patchless discs come before them, next to validity), then the stretches of open
    boundary no vertex closes (open_stretches), then the regions the paper flags for quality (orange: extra singularities, yellow: valence
    mismatch)."""
    red = [r for r in a["regions"] if r["colour"] == "red"]
    # A handle is cut by a non-separating loop (genus - 1, two more boundaries: chi unchanged),
    # then holes are joined by cuts between them (chi + 1): both count as progress.
    genus = sum(r["genus"] for r in red)
    badness = sum(max(1, abs(1 - r["euler_characteristic"])) for r in red)
    # Then the crease regions (issue 17), by how far each is from carrying its creases
    # (crease_excess: nodes, pieces and exits beyond one...), which every loop that
    # separates two crease junctions lowers, where the count of crease regions may not.
    # Once the crease phase has stalled, the crossings the rims lack count before the
    # excess (rim_lack; 0 until then).
    crease = (rim_lack(a), sum(r["crease_excess"] for r in a["regions"]))
    return (genus, badness, patchless(a), crease, open_stretches(a), colour_flaws(a))


def rim_lack(a):
    """The loop crossings the part's rims (closed creases with no junction: around a bore, a
    boss) lack to carry primal vertices and edges, 2 each (crease_rims.h), counted once the
    crease phase stalled (_Weaver.rims_counted; 0 before). A loop across a rim raises the crease
    excess (the rim's pieces count until further loops part them), yet every conforming layout
    has such loops: counted by the excess alone, a boss on a plate kept a crease region around
    both its rims. Counted from the start, the lack also outranked the excess where the excess
    was finding a way of its own (a plate with a bore: clean with 11 strips, with 18 not)."""
    return sum(r.get("crease_rim_lack", 0) for r in a["regions"]) if a.get("rims_counted") else 0


def patchless(a):
    """The closed discs whose boundary holds no loop crossing (valence 0): a cap cut off by one
    loop that crosses nothing. Their vertex has no primal edge, so none of their surface lies
    in a patch (uncovered, layout_defects.h), and any loop across one crosses its boundary
    twice and gives it patches. While the whole design has no crossing the weave treats that
    as "no patch yet"; on a part of several components (an assembly) the others' crossings
    hid it, and a cylinder's two caps, each holding its rim as a closed crease, were left in
    no patch while its crease seeds were refused for raising the crease excess. So they count
    right after validity, before the creases. A disc on the open boundary is none (regions.h,
    on_open_boundary): a sheet no curve has reached yet is a disc of valence 0 with no side
    along the open boundary too, and it is left to open_stretches and the uncovered areas,
    its first curve crossing nothing either (four ribbons seeded as caps: 12,600 triangles in
    no patch against 1,850)."""
    return len(_patchless_regions(a))


def _patchless_regions(a):
    """(index, region) of the patchless discs (patchless)."""
    return [(i, r) for i, r in enumerate(a["regions"])
            if r["disc"] and r["valence"] == 0 and not r.get("on_open_boundary", False)]


def open_stretches(a):
    """The stretches of open boundary that no primal vertex will close: per disc, those beyond
    its first (regions.h, open_sides). The layout is aligned to the boundary, and a region's
    one vertex closes one stretch; the band beside a curve that crosses nothing, or a tube cut
    from end to end, leaves the other in no patch (uncovered, layout_defects.h). Such a
    region is a disc, valid in the paper's sense, so this counts after validity and the
    crease regions (whose strips, across creases that run to the boundary, may leave such a
    band on the way), and before the paper's quality colours."""
    return sum(max(0, r.get("open_sides", 0) - 1) for r in a["regions"] if r["disc"])


def cuts_to_discs(a):
    """How many cuts the red regions of an assessment need before every region is a disc:
    two per handle (a loop across it and the loop along it that completes the cut; a loop
    lowers the genus by one at most) and one per boundary beyond the first (a cut joining
    two boundaries makes them one)."""
    return sum(2 * r["genus"] + max(0, r["boundaries"] - 1) for r in a["regions"] if r["colour"] == "red")


def work_per_red_strip(options):
    """An estimate of the work one red strip takes with these options: a capped loop query
    and a predicted layout at each of a region's seed points, then deriving the design with
    the strip and assessing it (the module doc's units; 58.5 with the defaults). A strip
    found only at a crossing or bridge anchor, or among ranked alternatives, costs more
    (60 to 130 units on a genus-15 NIST part whose queries run to their cap)."""
    # query_polls 0 leaves queries uncapped: the default cap stands for what one costs.
    polls = options.query_polls or WeaveOptions.query_polls
    query = WORK_QUERY + WORK_PER_POLL * polls
    return options.seeds_per_region * (query + WORK_PREDICT) + WORK_DERIVE + WORK_ASSESS


def seeds_in_order(a, options, skip):
    """(reason, region id, colour, [points]) in the order the issue asks: red, crease, orange,
    yellow regions (each colour largest first), with the patchless discs after the red ones
    (_patchless_seeds), the discs whose stretches of open
    boundary no vertex closes after the crease ones (_open_seeds), then the largest uncovered
    area."""
    out = []
    for colour in (c for c in COLOURS if c == "red" or c in options.colours):
        regions = [(i, r) for i, r in enumerate(a["regions"])
                   if shows(r, colour)
                   and (colour in ("red", "crease") or not options.extreme_only or r["valence"] <= 2
                        or r["valence"] >= 6)]
        for i, r in sorted(regions, key=lambda x: (-x[1]["area"], x[0])):
            points = [p for p in r["seeds"] if _key(p) not in skip]
            if points:
                k = options.seed % len(points)
                points = points[k:] + points[:k]
            if colour == "crease" and "crease_seed" in r and _key(_crease_seed(r)) not in skip:
                # First the point whose loop would cross the crease between its two nodes (or
                # exits), separating them (crease_structure.h), leaving across the crease: the
                # loop that separates them crosses it orthogonally (§5.6), and a query in one
                # direction costs a fraction of the all-directions one (whose best loop may
                # even run along the crease there, which separates nothing).
                points = [_crease_seed(r)] + points
            if colour == "red":
                # After the centre: across each loop that leaves the region on both sides (the
                # cut that completes a handle's meridian), along the shortest bridge between
                # two of its boundaries (the cut an annulus needs), then the other seed points.
                cuts = r.get("crossing_anchors", []) + r.get("bridge_anchors", [])
                points = points[:1] + [c for c in cuts if _key(c) not in skip] + points[1:]
            if points:
                out.append((f"{colour} region", i, colour, points))
        if colour == "red":
            out += _patchless_seeds(a, skip)
        if colour == ("crease" if "crease" in options.colours else "red"):
            out += _open_seeds(a, skip)    # after the crease regions, before the paper's colours
    u = a["uncovered"]
    # No crossing yet means no patch at all (a disc cut by nothing is "valid"): keep weaving.
    wanted = u["largest_area"] > options.uncovered * u["surface_area"] or a["crossings"] == 0
    if u["found"] and wanted and _coverage_key(u["point"]) not in skip:
        out.append(("uncovered area", -1, "uncovered", [u["point"]]))
    if a["crossings"] == 0 and a["colours"]["red"] == 0:
        # Valid but no patch yet (a sphere cut once, a disc): the largest regions' centres.
        for i, r in sorted(enumerate(a["regions"]), key=lambda x: (-x[1]["area"], x[0])):
            points = [p for p in r["seeds"] if _coverage_key(p) not in skip]
            if points:
                out.append(("no patch yet", i, "uncovered", points))
    return out


def _coverage_key(p):
    """The skip key of a point asked as an uncovered area's seed. A point that gave nothing as
    a region's seed may still give something here, as the question differs: a colour seed's
    strip must lower the score, an uncovered area's may leave it as it was if it brings
    surface into patches, and where its loop would leave a red region it is tried with the
    loop that makes that region valid again (_coverage_pair). The farthest point from every
    loop is both the largest region's seed and the uncovered area's: on a part whose two
    strips lie on one handle (a key's bow), the crease phase asked it first, and the pair
    that would have covered the shaft was never tried (one patch over the whole part)."""
    return ("uncovered",) + _key(p)


def _open_seeds(a, skip):
    """Seeds of the discs with stretches of open boundary no vertex closes (open_stretches),
    most stretches first, then largest: across the middle of the shortest bridge between two
    stretches (weave_seeds.h's bridge_anchors: the curve there parts them), then the centre."""
    out = []
    regions = [(i, r) for i, r in enumerate(a["regions"]) if r["disc"] and r.get("open_sides", 0) >= 2]
    for i, r in sorted(regions, key=lambda x: (-x[1]["open_sides"], -x[1]["area"], x[0])):
        points = [p for p in r.get("bridge_anchors", []) + r["seeds"][:1] if _key(p) not in skip]
        if points:
            out.append(("open stretches of region", i, "open", points))
    return out


def _patchless_seeds(a, skip):
    """Seeds of the patchless discs (patchless), largest first: the point whose loop would cross
    a crease the disc holds (a cylinder's cap holds its rim: a loop across it is the one a
    crease-conforming layout wants there too), then the disc's seed points."""
    out = []
    for i, r in sorted(_patchless_regions(a), key=lambda x: (-x[1]["area"], x[0])):
        points = ([_crease_seed(r)] if "crease_seed" in r else []) + list(r["seeds"])
        points = [p for p in points if _key(p) not in skip]
        if points:
            out.append(("patchless region", i, "patchless", points))
    return out


def _crease_seed(region):
    """A crease region's seed (weave_assessment's crease_seed), directional across the crease
    where the assessment gives that direction."""
    across = list(region.get("crease_seed_across") or ())
    return list(region["crease_seed"]) + (across if any(across) else [])


def _key(p):
    if _anchor_list(p):
        return tuple(_key(a) for a in p)
    return tuple(round(float(x), 6) for x in p)


def _anchor_list(p):
    """Whether a seed is a list of anchors for one loop (an axis seed: _Weaver.axis_entries)
    rather than one point (with a direction, or without)."""
    return len(p) > 0 and isinstance(p[0], (list, tuple))


def _seed_point(p):
    """Where a seed is, for the log: its point, or its first anchor's."""
    return list(p[0] if _anchor_list(p) else p)[:3]


def _say(options, text):
    if options.verbose:
        print(f"stripweave weave: {text}", file=sys.stderr, flush=True)


# Work units per step (module doc), in proportion to their typical cost: a loop query
# costs by its own work count (polls, one per 4096 settled g' nodes, exact with one thread).
# Removing the strip just added (a rejected proposal) restores the design's state from before
# the addition (DesignState keeps it) instead of deriving it again: next to nothing.
WORK_QUERY, WORK_PER_POLL, WORK_ASSESS, WORK_DERIVE, WORK_LAYOUT, WORK_RESTORE = 0.5, 0.04, 0.5, 4.0, 1.0, 0.0
WORK_PREDICT = 1.5    # a layout with its regions' assessment (about 0.1 s on a 30K-triangle part)
WORK_PER_TARGET_PATCH = 5.0   # the budget a patch target gets at least, per patch asked for
CREASE_PAIR_LOOPS = 6         # loops a crease region's pairs are drawn from (_crease_pair: 15 pairs)
STRIPS_BEYOND_CUTS = 40       # the default strip cap past the cuts the topology asks for (the old fixed cap)


class _Weaver:
    def __init__(self, ds, options):
        self.ds, self.options = ds, options
        self.session = ds.loop_session.native
        self.work = 0.0             # units spent (module doc)
        self.spent = {}             # units by step (assess, predict, layout, derive, query): what dominates
        self.cancelled = 0          # loop queries cut by the timeout
        self.capped = 0             # loop queries stopped by query_polls
        self.capped_all_directions = False   # an all-directions query ran past query_polls (proposals)
        self.valid_at = None        # (work, seconds) when the design first had no red region
        self.coverage_spent = (0.0, 0.0)  # (work, seconds) of valid designs' COVERAGE strips (quality_work)
        self.cuts = None            # cuts the red regions of the first assessment need (red_allowance)
        self.looking_harder = False  # red regions ran out of seed points once (_weave)
        self.rims_counted = False   # the crease phase stalled with rims lacking crossings: score()
                                    # counts their lack from then on (rim_lack, _weave)
        self.red_again = None       # why the other colours stopped, once the red seed points were
                                    # asked once more at the end (_weave)
        self.user_strips = len(ds.design.strips)
        self.groups = {}            # index of an added strip -> 1 + its symmetric images, added after it
        self.image_tolerance = 0.0
        if options.symmetry:
            from .symmetry import image_tolerance
            self.image_tolerance = image_tolerance(ds.surface)
        # A loop that is its own image must be so within the symmetry's tolerance (design.md's 1e-3
        # of the diagonal): the symmetric solver mesh (symmetry.symmetric_surface) makes it exact.
        self.symmetry_tolerance = options.symmetry_tolerance * ds.surface.bbox_diagonal
        self.axis_seeds = []        # anchor lists of loops beside a rotation's axis (axis_entries)
        self.axis_placed = False    # one of them gave a strip
        if options.symmetry:
            from .symmetry import axis_seeds
            self.axis_seeds = axis_seeds(ds.surface, options.symmetry)

    def axis_entries(self, a, skip):
        """The seeds beside a rotation's axis (symmetry.axis_seeds), before every other seed
        until one gives a strip. Where the axis meets the surface, every loop through the point
        has its n - 1 images through it too, so the seeds of the region holding it (its centre,
        mostly the point itself on a part turned about its axis) give loops whose images the
        design refuses: a five-bladed hub took no strip at all. A loop beside the point, with
        its images, bounds the n-gon that holds the layout's valence-n vertex there. Judged as
        a cut while a region is red, else as coverage (the cap around the point lies in no
        patch until loops cross it)."""
        if self.axis_placed:
            return []
        seeds = [x for x in self.axis_seeds if _key(x) not in skip]
        if not seeds:
            return []
        colour = "red" if a["colours"]["red"] else "patchless"
        return [("beside the rotation's axis", -1, colour, seeds)]

    def spend(self, step, units):
        self.work += units
        self.spent[step] = self.spent.get(step, 0.0) + units

    def became_valid(self, elapsed):
        """Start the quality budget: the work (and time) spent so far went to validity."""
        if self.valid_at is None:
            self.valid_at = (self.work, elapsed())

    def quality_work(self, elapsed):
        """(work units, seconds) spent since the design became valid (all of it before), but for
        the strips that cover surface no patch would (COVERAGE: patchless discs, stretches of
        open boundary, open_stretches): what they leave is surface in no patch, which validity
        is for too, so like the red phase they do not take the crease, colour and refining
        phases' budget; they have one of their own (coverage_allowance). A range scan's ragged border left 17 such stretches after its red
        phase, and parting four of them took the rest of the budget: 14 patches, against 35."""
        work, seconds = self.valid_at or (0.0, 0.0)
        return self.work - work - self.coverage_spent[0], elapsed() - seconds - self.coverage_spent[1]

    def book_coverage(self, since):
        """Move what was spent since `since` (a mark from spent_now) to the COVERAGE account
        (quality_work)."""
        work, seconds = self.spent_now()
        self.coverage_spent = (self.coverage_spent[0] + work - since[0], self.coverage_spent[1] + seconds - since[1])

    def spent_now(self):
        """(work units, a clock in seconds) now: a mark for book_coverage."""
        return self.work, time.perf_counter()

    def coverage_allowance(self):
        """Whether a valid design's COVERAGE strips may go on: one budget (and time limit) of
        their own (quality_work)."""
        return self.coverage_spent[0] < self.options.budget and self.coverage_spent[1] < self.options.time_limit_s

    def out_of_work(self, elapsed):
        """Whether the budget (deterministic) or the safety net (wall clock) is used up. Both
        count from the moment the design became valid: the loops a part's handles and holes
        need are its topology's (every handle takes at least two, every extra boundary one),
        not a choice of quality, so the crease, colour and refining phases get the whole
        budget on a genus-10 casting as on a sphere (they got what the red phase left: 29 of
        200 units on a plate with holes, which then never reached its crease phase)."""
        work, seconds = self.quality_work(elapsed)
        return work >= self.options.budget or seconds > self.options.time_limit_s

    def count_cuts(self, a):
        """Fix the cuts validity takes, from the first assessment (red_allowance)."""
        if self.cuts is None:
            self.cuts = cuts_to_discs(a)

    def max_strips(self):
        """The strip cap: the options' own, else the cuts the topology asks for (cuts_to_discs)
        plus STRIPS_BEYOND_CUTS. A fixed cap of 40 stopped a plate with 23 bores, which
        needs some 46 strips to be valid at all, with three regions still red; the strips
        beyond the cuts are what the creases, colours and refinement may add."""
        if self.options.max_strips is not None:
            return self.options.max_strips
        return STRIPS_BEYOND_CUTS + (self.cuts or 0)

    def red_allowance(self):
        """(work units, seconds) red regions may spend in all: red_reserve budgets (and time
        limits), plus the work of one red strip per cut the part's topology asks for
        (cuts_to_discs). A fixed reserve is what a part of little topology needs; a loop
        lowers a region's genus by one at most, so a plate with 23 bores needs some 46 strips
        where a sphere needs two, and with a fixed reserve every part of high genus ran out
        of work with its handles half cut. The wall-clock net stays red_reserve time limits:
        it guards against a slow machine, not against the topology (and a batch's per-model
        limit, 600 s by default, must find the weave done and its files written)."""
        o = self.options
        work = o.red_reserve * o.budget + (self.cuts or 0) * work_per_red_strip(o)
        return work, o.red_reserve * o.time_limit_s

    def out_of_red_work(self, elapsed):
        """Whether even red regions must stop: their allowance (red_allowance) spent."""
        work, seconds = self.red_allowance()
        return self.work >= work or elapsed() > seconds

    def why_out_of_red(self, elapsed):
        """Why red regions stopped (out_of_red_work): their work allowance, or the wall clock."""
        work, _ = self.red_allowance()
        if self.work >= work:
            return f"work budget, red allowance of {work:g} units spent (red regions remain)"
        return f"time limit (safety net), {self.options.red_reserve:g} times over (red regions remain)"

    def why_out(self, elapsed):
        return "work budget" if self.quality_work(elapsed)[0] >= self.options.budget else "time limit (safety net)"

    def check_cancel(self):
        """Raise Cancelled once options.cancel is set (checked before every step that costs work)."""
        if self.options.cancel is not None and self.options.cancel.is_set():
            raise native.Cancelled("automatic weaving cancelled")

    def assess(self, extra=(), seeds=True):
        self.check_cancel()
        self.spend("assess", WORK_ASSESS)
        a = native.weave_assessment(self.ds.native, list(extra), self.options.seeds_per_region if seeds else 0)
        a["rims_counted"] = self.rims_counted
        return a

    def quality(self, a, layout, base_flaws=None):
        """What additions past validity lower: the real layout's mean corner deviation, plus
        region_penalty_deg per flaw the assessment sees (flaws()); given the flaws before the
        addition (base_flaws), fewer flaws than those count as those (module doc: removing a
        flaw does not pay for worse corners)."""
        # Each patch past the area bound (_oversized) counts as a flaw of the layout.
        uneven = len(_oversized(layout, self.options.max_area_ratio))
        if base_flaws is not None:
            return _deviation(layout) + self.options.region_penalty_deg * \
                (max(0, flaws(a) - base_flaws) + base_flaws + uneven)
        return _deviation(layout) + self.options.region_penalty_deg * (flaws(a) + uneven)

    def predict(self, loop):
        """The layout and assessment the design would have with the loop added, under the
        design's current singularities (no field or parameterization solve): one arrangement,
        whose regions give the assessment (_assessment_of)."""
        self.check_cancel()
        self.spend("predict", WORK_PREDICT)
        layout = self.ds.native.layout_with([loop])
        return layout, _assessment_of(layout, self.rims_counted)

    def predict_without(self, index):
        """predict() of taking strip `index` back: the other loops under the design's current
        singularities."""
        self.check_cancel()
        self.spend("predict", WORK_PREDICT)
        layout = self.ds.native.layout_with([], without=[index])
        return layout, _assessment_of(layout, self.rims_counted)

    def layout(self):
        self.check_cancel()
        self.spend("layout", WORK_LAYOUT)
        return _layout(self.ds)

    def remove(self, index):
        """Remove the strip just added (the last one, with its symmetric images): DesignState
        restores its kept state."""
        count = self.groups.pop(index, 1)
        self.spend("derive", WORK_RESTORE if index + count == len(self.ds.design.strips) and count == 1 else WORK_DERIVE)
        if count == 1:
            self.ds.remove_strip(index)
        else:
            self.ds.remove_strips(index, count)

    def add_images(self, index):
        """Add the images of strip `index` under the symmetries (symmetry.add_images). False
        if the design refuses an image (the strip is then removed too: a design stays
        symmetric or does not take the strip)."""
        from .symmetry import add_images
        try:
            count = add_images(self.ds, index, self.options.symmetry, self.image_tolerance, self.symmetry_tolerance)
        except native.InputError as e:
            self.spend("derive", WORK_DERIVE)
            _say(self.options, f"  rejected: {e}")
            return False
        except native.Cancelled:
            if not self.session.query_limited:
                raise
            self.spend("derive", WORK_DERIVE)
            _say(self.options, "  rejected: deriving a symmetric image ran past the query cap")
            return False
        if count:
            self.spend("derive", WORK_DERIVE)
            self.groups[index] = 1 + count
        return True

    def proposals(self, point, alternatives, both_families=False):
        """Loops through the point, best first.

        A seed point (no direction) gets the best loop over all directions, or, in the
        "principal" order, the best loops along its two principal directions, the
        all-directions search only where neither gives one. A good dual loop follows a
        principal direction (§5, criterion 1; the q term of eq. 1 pulls it there), so the
        best loop through a point leaves it near one of the two; a one-direction query
        settles one start's search, while the all-directions one searches every start
        direction until the best loop closes. On parts whose g' costs are nearly uniform
        (flat faces, terrain, a scan's smooth stretches) that search ran past query_polls at
        most seed points and gave nothing for 4 to 16 work units, three to eight times the
        two directional queries (traced on a pentagonal pyramid, a terrain and a face scan:
        40 to 63 % of all query work, and weaving ended on its budget after 2 or 3 strips).
        Whether it closes within the cap is a property of the part's metric, not of the
        point, so "adaptive" (the default) turns to the principal order for the rest of the
        weave at the first all-directions query that runs past the cap.

        `both_families` (a red region's points, once its seed points ran out: _weave) adds the
        loops along both principal directions to the all-directions one. A red region needs a
        cut of its topology, a loop that does not separate it, and the cheapest loop through a point is a separating one wherever the
        part is thin there: around a plate's rim, at every seed point of a plate with bosses
        (each the farthest from the others, so on the rim). The two principal directions give
        one loop of each family of good loops through the point (§5, criterion 1), and the
        one across the rim runs over the faces and through a bore."""
        self.check_cancel()
        if _anchor_list(point):
            # The loop through all its anchors, the best only: a strip keeps the anchors, and
            # deriving them gives the best loop, whichever ranked alternative was judged.
            return self._proposals(point, 1)
        if len(point) != 3:
            # A direction is a hint of where the loop should leave (across a crease between
            # two of its exits, across a bridge). Where it gives no loop, mostly because the
            # compatibility mask refuses it (a strip already runs that way: a ring of
            # parallel creases with a loop along the ring; a torus's second meridian), the
            # best loop through the same point in any direction may still part what the
            # point was chosen to part, or cut what it was chosen to cut.
            return self._proposals(point, alternatives) or \
                self.proposals(list(point)[:3], alternatives, both_families)
        order = self.options.seed_directions
        if order == "all" or (order == "adaptive" and not self.capped_all_directions):
            found = self._proposals(point, alternatives)
            if found and both_families:
                return _distinct(found + self.along_principal_directions(point))
            if found or not self.session.query_limited:
                return found or self.along_principal_directions(point)
            self.capped_all_directions = True
            return self.along_principal_directions(point)
        found = self.along_principal_directions(point)
        return found or self._proposals(point, alternatives)

    def along_principal_directions(self, point):
        """The best loops along the point's two principal directions (one of each family of
        good loops, §5 criterion 1), cheapest first."""
        found = []
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
            if _anchor_list(point):
                return list(self.session.loops([list(x) for x in point], alternatives, True))
            if alternatives <= 1 and len(point) == 3:
                return [self.session.best_loop(list(point), True)]
            return list(self.session.loops([list(point)], alternatives, True))
        except native.InputError:
            return []
        except native.Cancelled:
            if not self.session.query_limited:   # the clock, not the work cap, stopped it
                self.cancelled += 1
            else:
                self.capped += 1
            return []
        finally:
            self.spend("query", WORK_QUERY + WORK_PER_POLL * self.session.last_query_polls)
            watchdog.cancel()
            self.session.clear_disabled()

    def candidates(self, points, alternatives, current, every_point=False):
        """(score, cost, loop, point) of proposals at the points, best first (equal scores:
        the cheaper loop). Points are tried in order and, unless `every_point`, the search
        stops at the first point whose proposals improve on `current`: the region's centre
        usually does, and each further point costs a loop search and an arrangement. Red
        regions ask every point: the first strips fix the layout's coarse structure, and the
        first seed point can be a poor place for a loop (a cube's corner, where the belt
        through it costs three times a belt over the faces and leaves a 180-degree corner)."""
        out = []
        for point in points:
            for loop in self.proposals(point, alternatives, both_families=every_point and self.looking_harder):
                a = self.assess([loop], seeds=False)
                out.append((score(a), loop.cost, loop, point, a))
            if out and min(c[0] for c in out) < current and not every_point:
                break
        out.sort(key=lambda c: (c[0], c[1]))
        return out

    def add(self, loop, point):
        """Add the loop as one directional anchor (an axis seed's loop: through all its anchors,
        which the loop needs to come back to); None if the design rejects it."""
        self.check_cancel()
        anchors = [list(x) for x in point] if _anchor_list(point) else \
            [native.loop_anchor(self.session, loop, list(point)[:3])]
        if _DEBUG_DESIGN:   # the design about to be derived, for reproducing native failures
            d = self.ds.design.copy()
            d.add_strip(anchors)
            d.save(_DEBUG_DESIGN)
        self.spend("derive", WORK_DERIVE)
        try:
            index = self.ds.add_strip(anchors)
        except native.InputError as e:
            _say(self.options, f"  rejected by the design: {e}")
            return None
        except native.Cancelled:
            if not self.session.query_limited:
                raise
            # Deriving it searched past the query cap (from a node of the loop, not from the
            # seed the proposal came from): as a proposal that was never found.
            _say(self.options, "  rejected: deriving its loop ran past the query cap")
            return None
        if self.options.symmetry and not self.add_images(index):
            return None
        return index


def _assessment_of(layout, rims_counted=False):
    """What score() and flaws() read of weave_assessment (without seeds), from the regions of
    a layout: the same arrangement and singularities, computed once (a prediction built the
    arrangement twice, a fifth of its time). `rims_counted`: as _Weaver.rims_counted."""
    regions = [{**r, "singularities": len(r["singularities"])} for r in layout["regions"]]
    colours = dict.fromkeys(("red", "crease", "orange", "yellow", "none"), 0)
    for r in regions:
        colours[r["colour"]] += 1
    return {"regions": regions, "colours": colours, "valid": layout["valid"], "crossings": layout["crossings"],
            "rims_counted": rims_counted}


def _distinct(loops):
    """The loops without repeats (_loop_key), in their order."""
    seen = set()
    return [x for x in loops if not (_loop_key(x) in seen or seen.add(_loop_key(x)))]


def _loop_key(loop):
    """One key per loop, whichever seed found it and in which direction (equal costs)."""
    return len(loop.nodes), round(loop.cost, 9)


def _layout(ds):
    from .layout import compute_layout
    return compute_layout(ds)


def _deviation(layout):
    """The mean corner deviation from 90 degrees that refinement lowers: report.json's mean,
    with every patch that cannot be a clean quad counted as four corners 90 degrees off
    (_corner_deviations: report.json leaves them out, and a strip that breaks patches must
    not look like an improvement)."""
    if not layout["valid"] or not layout["patches"]:
        return 180.0
    flawed = _defect_vertices(layout)
    return sum(sum(_corner_deviations(p, flawed)) for p in layout["patches"]) / (4 * len(layout["patches"]))


def _defect_vertices(layout):
    """The layout's vertices the strict checks flag (valence 2, valence 7 and more): a corner
    there is no quad corner, whatever angle the patch shows at it."""
    return {i for i, v in enumerate(layout.get("vertices", ())) if v.get("defects")}


def _corner_deviations(p, flawed=frozenset()):
    """A patch's four corner deviations from 90 degrees; 90 each where it cannot be a clean
    quad (no quad, laid over a crease, flagged by the strict checks: degenerate, overlapping),
    and 90 at each corner on a flagged vertex (`flawed`, _defect_vertices)."""
    # A patch laid over a crease counts as 90 degrees off too: no smooth patch fits it, and a
    # coarse layout of such patches has good corners (the crease runs through them) that would
    # otherwise stop refinement (fandisk: 6 patches at 4.3 degrees, 4 of them over creases).
    if not p.get("quad", True) or p.get("creased", False) or p.get("defects"):
        return [90.0] * 4
    # A valence-2 vertex (two loops crossing twice bound a lens) can show corners near 90
    # degrees in the patches beside it while the layout is not clean; per corner, not per
    # patch, so that a strip splitting those patches lowers the figure step by step, as it
    # lowers the share of corners at the flagged vertex.
    return [90.0 if c in flawed else abs(x - 90.0) for c, x in zip(p.get("corners", ()), p["corner_angles_deg"])] \
        if len(p.get("corners", ())) == len(p["corner_angles_deg"]) else [abs(x - 90.0) for x in p["corner_angles_deg"]]


def _oversized(layout, ratio):
    """The patches whose area exceeds `ratio` times the median patch area, largest first: a
    layout whose strips bunched in one place (a bore, an ear) has a few huge patches beside
    many small ones, which no NURBS patch of the refit fits evenly (issue 18: at most 20
    times the median). None when ratio is 0 or there are fewer than 3 patches (a median of
    one or two patches says nothing about bunching)."""
    patches = layout.get("patches", ())
    if not ratio or len(patches) < 3:
        return []
    areas = sorted(p["area"] for p in patches)
    median = areas[len(areas) // 2] if len(areas) % 2 else 0.5 * (areas[len(areas) // 2 - 1] + areas[len(areas) // 2])
    big = [i for i, p in enumerate(patches) if p["area"] > ratio * median]
    return sorted(big, key=lambda i: (-patches[i]["area"], i))


def _creased(layout):
    """How much crease lies inside the layout's patches (model units, patches the layout
    marks "creased": more than 1% of the diagonal inside, layout.json). Refinement may not
    raise it: a patch over a crease is one no smooth patch fits (the handle's refinement
    laid one over its top rim, and its STEP missed the tolerance there), whatever its
    corners. Counting such patches as 90 degrees off instead left a tube whose creases run
    its whole length at one patch: every single strip still left each patch over a crease.
    (Not the crease length off the primal edges, crease_off_edges: measured on fandisk, that
    refused nearly every refining strip, 8 patches where this gives 60.)"""
    return sum(p.get("crease_length", 0.0) for p in layout.get("patches", ()) if p.get("creased", False))


def _at_length(points, t):
    """The point at fraction t of a polyline's length."""
    lengths = [math.dist(a, b) for a, b in zip(points, points[1:])]
    goal, run = t * sum(lengths), 0.0
    for a, b, l in zip(points, points[1:], lengths):
        if run + l >= goal and l > 0:
            s = (goal - run) / l
            return [x + s * (y - x) for x, y in zip(a, b)]
        run += l
    return list(points[-1])


def _split_need(p, flawed=frozenset()):
    """How much splitting the patch may gain: its area times its mean corner deviation (a
    patch that is not a quad: 90 degrees). Not the worst corner alone: refinement then
    worked where the corners were worst (often a narrow place, the rocker-arm's ring) and
    bunched loops there, leaving the large patches elsewhere as they were; area times
    deviation spreads the loops over the surface (measured on the rocker-arm, otherwise the
    same refinement: 18.5 against 25.4 degrees mean)."""
    return p["area"] * (sum(_corner_deviations(p, flawed)) / 4)


def _splits(layout, patch):
    """Directional anchors for loops that shorten the patch's longest side, best first.

    A patch holds one crossing of two loops, and each of its sides (primal edges) crosses one
    of the four arcs there: the loop A that crosses the longest side runs through the middle
    of the patch, parallel to the two short sides. A loop that shortens the long sides must be
    parallel to A, and the best place for it is the middle of the corridor between A and its
    next parallel loop, which is where the primal edge between them runs: a short side. So
    the anchor is the middle of a short side (where the perpendicular loop crosses it),
    pointing along it, the longer short side first. Not the middle of the long side pointing
    across first: that anchor lies on A itself, whose parallels the compatibility mask forbids
    there, and the loop found there bends away, often diagonally across the other loops (seen
    on the rocker-arm: corners of 60 and 120 degrees along it) or into a bunch of parallels
    where the mask allows them. It stays as the last candidate."""
    sides = layout["patches"][patch]["edges"]
    edges = layout["edges"]
    if len(sides) != 4 or _uncut(layout["patches"][patch]):
        # An uncut patch has no sides to measure; -1 would index the layout's last edge and
        # seed the loop of an unrelated place.
        return []
    k = max(range(4), key=lambda j: (edges[sides[j]]["length"], -sides[j]))
    short = sorted(((k + 1) % 4, (k + 3) % 4), key=lambda j: (-edges[sides[j]]["length"], sides[j]))
    out = []
    for j in short:
        if edges[sides[j]].get("sharp") or edges[sides[j]].get("boundary"):
            # A short side on a crease (or the open boundary): the loop anchored along it
            # would run along the crease, which then lies on no primal edge (the loop takes
            # the primal edge's place: crease_structure.h, "loop along a crease"). The
            # corridor's middle is the crease itself; no loop may go there.
            continue
        points = edges[sides[j]]["points"]
        p, a, b = _at_length(points, 0.5), _at_length(points, 0.25), _at_length(points, 0.75)
        d = [y - x for x, y in zip(a, b)]
        out.append(list(p) + d if any(d) else list(p))
    # Last, the middle of the long side pointing across to the opposite one: on A itself, so
    # the loop found there bends away from A (the mask), which sometimes splits a patch the
    # corridor loops cannot reach (ec_soapbox-A: 17.1 against 20.8 degrees with it).
    p, q = _at_length(edges[sides[k]]["points"], 0.5), _at_length(edges[sides[(k + 2) % 4]]["points"], 0.5)
    d = [b - a for a, b in zip(p, q)]
    out.append(list(p) + d if any(d) else list(p))
    return out


def _uncut(p):
    """Whether the layout could not cut the patch: no side along a primal edge (layout.json
    gives -1 for each), because edges around it overlap."""
    return any(e < 0 for e in p.get("edges", ()))


def _crowded_seeds(layout, a):
    """The seed points of the regions whose vertices carry more edges than a mesh vertex has
    room for, highest valence first: a primal vertex's edges leave it by distinct neighbours
    (they may not share a vertex), and a vertex of the solver mesh has about six, so at
    valence 7 and more (flagged high_valence) edges overlap and the patches around go uncut.
    A loop across such a region splits it and lowers its valence; _splits has nothing to
    offer there, as an uncut patch has no sides."""
    vertices = [v for v in layout.get("vertices", ()) if "high_valence" in v.get("defects", ())]
    out = []
    for v in sorted(vertices, key=lambda v: (-v["valence"], v["region"])):
        if 0 <= v["region"] < len(a["regions"]):
            out += [list(p) for p in a["regions"][v["region"]].get("seeds", ())]
    return out


def _defects(layout):
    """(area of the defective patches, number of flagged vertices): the strict checks'
    verdict (layout_defects.h) in two figures that a split of a defective patch into two
    defective halves leaves as they were, and a new sliver or flagged vertex raises."""
    area = sum(p["area"] for p in layout.get("patches", ()) if p.get("defects"))
    return area, len(_defect_vertices(layout))


def _less_clean(after_layout, after, before_layout, before):
    """Whether a refining strip takes the layout further from clean: worse validity or
    crease conformity (_less_conforming), more area in defective patches, more flagged
    vertices, or more crease inside patches (_creased). A defect is never traded for
    corners: a strip that left one degenerate sliver among 78 patches lowered the mean
    corner deviation by more than the sliver's four 90-degree corners raised it (a waisted
    solid of revolution), and the layout was no longer clean. Area, not a count: halving a patch that is no quad gives two, and is no
    step back (a plate with three holes stopped refining at 17 patches on the count)."""
    (area_after, flagged_after), (area_before, flagged_before) = _defects(after_layout), _defects(before_layout)
    total = sum(p["area"] for p in before_layout.get("patches", ())) or 1.0
    creased = _creased(before_layout)
    return _less_conforming(after, before) or flagged_after > flagged_before or \
        area_after > area_before + 1e-6 * total or _creased(after_layout) > creased + 1e-9 * (1 + creased)


def _less_conforming(after, before):
    """Whether a refining strip leaves the layout further from valid, covered and
    crease-conforming: score()'s first five figures (red genus, red badness, patchless discs,
    crease excess, open stretches) worse. Corners
    never pay for a crease region: the crease it leaves off the primal edges is a seam no
    smooth patch fits (a loop along the handle's top rim made its two crease regions)."""
    return score(after)[:5] > score(before)[:5]


def _refine_under_the_band(w, ds, options, a):
    """Switch the design to the band mask refinement works under, and return the assessment
    of the design then. Refinement splits patches by loops beside the ones there: the paper's
    mask refuses every loop parallel to a strip anywhere on it, a band only near its loop.
    Not earlier: with the band, the colour phase's best loops ran beside the first ones (a
    filleted box stayed two lens patches), where the paper's mask leaves only the crossing
    belt. An empty design only (the caller): a user's strips keep the mask they were drawn
    under. design.json keeps the band, so the design re-derives the same.

    Switching re-derives every strip under the new mask, and a strip's loop can then take
    a path the paper's mask refused, beside an earlier loop: the layout the earlier phases
    made valid can come back with red regions (a torus's crossing loop re-derived as a second
    meridian; a corpus block with crossed bores: two annuli). The design
    then keeps its own compatibility, as when the band refuses it outright (0088: "strip 2:
    the direction of anchor 1 ... is disabled"), and refinement goes on under the paper's
    mask: its loops can still split the patches, only not as close beside the strips.

    Nor may the switch cost what the earlier phases reached in conformity and defects: the
    same test a refining strip must pass (_less_clean) holds for the re-derived design. A
    loop re-derived beside an earlier one leaves the crease that ran between them inside a
    patch, and no later strip may take a patch back over a crease (a square-section ring
    whose crease phase ended clean, 6 patches, came back from the band with 6 crease
    regions, and refinement then only kept it there)."""
    band = options.band * ds.surface.report()["bbox_diagonal"]
    try:
        layout = w.layout()
    except ImportError:
        layout = None
    before = {k: ds.design.options.get(k) for k in ("compatibility_band", "compatibility_angle_deg")}
    ds.design.options["compatibility_band"] = band
    ds.native.compatibility_band = band
    if options.refine_angle_deg != ds.design.options.get("compatibility_angle_deg", 45):
        ds.design.options["compatibility_angle_deg"] = options.refine_angle_deg
        ds.native.compatibility_angle = float(options.refine_angle_deg)
    w.spend("derive", WORK_DERIVE)
    try:
        ds.update()
        after = w.assess()
        if score(after)[:2] > score(a)[:2]:
            why = f"{after['colours']['red']} red regions under it"
        elif layout is not None and _less_clean(w.layout(), after, layout, a):
            why = "its layout is further from clean"
        else:
            return after
    except native.InputError as e:
        why = str(e)
    _say(options, f"  refinement keeps the paper's compatibility: the band refuses the design ({why})")
    ds.design.options.update(before)
    ds.native.compatibility_band = before["compatibility_band"]
    ds.native.compatibility_angle = float(before["compatibility_angle_deg"] or 45)
    w.spend("derive", WORK_DERIVE)
    ds.update()
    return w.assess()


def _crease_phase_under_the_band(w, ds, options, result, elapsed):
    """The crease phase once more, under the band mask (_refine_under_the_band), before
    refinement: the loop that parts two creases running side by side runs beside them, so
    parallel to every strip that runs along them, which the paper's mask refuses anywhere on
    such a strip and the band only near it (a duct of rectangular section: once a loop runs
    along one face, the loops along the others are refused, and the layout stays one patch
    over all four faces, 18 units of crease excess; under the band the loop along the next
    face takes it to 12). Returns the assessment after it; its strips join the log."""
    _say(options, "crease regions remain: their seeds once more, under the band")
    # Not the last phase: taking strips back belongs to the end of the whole weave, and its
    # predictions here would spend what refinement is still to get.
    again = _weave(w, ds, replace(options, colours=("crease",), refine=False, take_back=False),
                   start=time.perf_counter() - elapsed())
    result.log.extend(again.log)
    return again.assessment


def _refine(w, ds, options, a, result, elapsed):
    """Past the paper's colours: a region can be fine by §4.2 and still give patches with
    corners far from 90 degrees (a cube-like layout wrapped on a cylinder). Add the best
    predicted of refine_candidates strips that would split the patches with the most area
    times deviation (_split_need, _splits), keep it if the real layout improves (w.quality),
    until the deviation or the patch target is reached or the work budget is spent (module
    doc)."""
    if options.band and ds.design.options.get("compatibility_band") is None and w.user_strips == 0:
        a = _refine_under_the_band(w, ds, options, a)
        if ds.design.options.get("compatibility_band") is not None and a["colours"]["crease"]:
            a = _crease_phase_under_the_band(w, ds, options, result, elapsed)
    try:
        layout = w.layout()
    except ImportError:
        return a
    if options.refine_query_polls:
        w.session.max_query_polls = min(options.query_polls or options.refine_query_polls, options.refine_query_polls)
    tried = set()
    predicted = set()     # loops predicted in the current design (_loop_key): seeds often share one
    while len(ds.design.strips) < w.max_strips() and not w.out_of_work(elapsed):
        deviation = _deviation(layout)
        patches = len(layout["patches"])
        oversized = _oversized(layout, options.max_area_ratio)
        # A patch target asks for density: below it, refinement goes on past good corners, and
        # a split may cost up to one flaw's worth of quality (a blob asked for 80 patches
        # stopped at 26 when every split had to improve the corners; taking any valid split
        # reached 58, not clean).
        short = bool(options.patches) and patches < options.patches
        slack = options.region_penalty_deg if short else 0.0
        if deviation <= options.refine_deviation_deg and not oversized and not short:
            result.stopped = "done"
            break
        limit = options.patches or options.refine_patches
        if limit and patches >= limit:
            result.stopped = "patch target"
            break
        current = w.quality(a, layout)
        base_flaws = flaws(a)
        # Patches by how much splitting them may gain (_split_need), and per patch the
        # anchors of the loops that would shorten its long sides (_splits).
        # With the corners good enough, only the patches past the area bound are split.
        flawed = _defect_vertices(layout)
        # Below a patch target with good corners, the largest patches first (even density).
        if deviation <= options.refine_deviation_deg:
            order = oversized + (sorted((i for i in range(patches) if i not in oversized),
                                        key=lambda i: (-layout["patches"][i]["area"], i)) if short else [])
        else:
            order = oversized + sorted((i for i in range(patches) if i not in oversized),
                                       key=lambda i: (-_split_need(layout["patches"][i], flawed), i))
        seeds = []
        crowded = False       # the seeds of the crowded regions are in (_crowded_seeds)
        for i in order:
            if len(seeds) >= options.refine_candidates:
                break
            splits = _splits(layout, i)
            if not splits and not crowded and _uncut(layout["patches"][i]):
                crowded = True
                splits = _crowded_seeds(layout, a)
            for p in splits:
                if _key(p[:3]) not in tried and len(seeds) < options.refine_candidates:
                    seeds.append((p, i))
        if not seeds:
            # No quad patch left to split (a coarse layout of patches that do not read as
            # quads): the largest regions' seed points, any direction.
            for i, r in sorted(enumerate(a["regions"]), key=lambda x: (-x[1]["area"], x[0])):
                p = next((list(q) for q in r.get("seeds", ()) if _key(q) not in tried), None)
                if p is not None:
                    seeds.append((p, f"of region {i}"))
                    break
        if not seeds:
            result.stopped = "no seed helps"
            break
        # Each candidate's layout is predicted under the design's singularities (w.predict: no
        # solve); only the best is derived and checked for real.
        best = None
        for seed, patch in seeds:
            if w.out_of_work(elapsed):
                break
            proposals = w.proposals(seed, 1)
            if not proposals or _loop_key(proposals[0]) in predicted:
                tried.add(_key(seed[:3]))
                continue
            predicted.add(_loop_key(proposals[0]))
            pred_layout, pred = w.predict(proposals[0])
            q = w.quality(pred, pred_layout, base_flaws)
            over = limit and len(pred_layout["patches"]) > limit and len(pred_layout["patches"]) > patches
            if pred["colours"]["red"] or _less_clean(pred_layout, pred, layout, a) or q >= current + slack or over:
                tried.add(_key(seed[:3]))    # no gain from here in this design
                continue
            if best is None or q < best[0]:
                best = (q, seed, patch, proposals[0])
        if best is None:
            continue
        q, seed, worst, loop = best
        tried.add(_key(seed[:3]))
        _say(options, f"strip {len(ds.design.strips) + 1}: refine patch {worst} (corner deviation "
                      f"{deviation:.1f} deg, {patches} patches, predicted quality {current:.2f} -> {q:.2f}, "
                      f"work {w.work:.0f}, {elapsed():.1f} s)")
        index = w.add(loop, seed)
        if index is None:
            continue
        after_layout = w.layout()
        after = w.assess()
        if after["colours"]["red"] or _less_clean(after_layout, after, layout, a) or \
                w.quality(after, after_layout, base_flaws) >= current + slack:
            w.remove(index)
            continue
        _record(ds, result, _entry(ds, index, "corner deviation", -1, "none", seed, loop.cost, elapsed,
                                   deviation_before=deviation, deviation_after=_deviation(after_layout)))
        a, layout = after, after_layout
        predicted.clear()
    else:
        result.stopped = "max strips" if len(ds.design.strips) >= w.max_strips() else w.why_out(elapsed)
    return a


def _take_back(w, ds, options, a, result, elapsed):
    """Take back added strips the layout is cleaner without (module doc, last phase).

    Every phase judges a strip where it is added, by what it fixes there (a region's colour,
    a patch's corners) and by the layout of that moment. Strips added later come to run
    beside it, or to cross it next to another crossing, and then it bounds patches narrower
    than a few solver edges (degenerate) or patches that are no quad, which no later strip
    mends: a further loop only cuts such a sliver into smaller ones. Taking one of the two
    loops back does: the sliver merges with its neighbour across that loop.

    Per round: the added strips whose loops bound a defective patch or end at a flagged
    vertex (_bounding_strips) are candidates; each one's removal is predicted (layout_with
    without it: the other loops under the design's singularities, no solve); the
    prediction that leaves the least defective area (_defects) and is cleaner (_cleaner) is
    removed for real, and kept only if the re-derived layout is cleaner too; else it is put
    back (DesignState restores the state it kept, at no cost) and not tried again. The
    user's strips and a symmetric design's strips are never taken back. The phase has its
    own work allowance (take_back_share of the budget): removing strip k re-derives the
    strips after it."""
    try:
        layout = w.layout()
    except ImportError:
        return a
    start_work = w.work
    refused = set()         # anchors whose removal the re-derived design did not confirm
    while w.work - start_work < options.take_back_share * options.budget and \
            elapsed() < options.time_limit_s * options.red_reserve:
        candidates = [k for k in _bounding_strips(layout, w.user_strips, len(ds.design.strips))
                      if not _grouped(w, ds, k) and _strip_key(ds, k) not in refused]
        best = None
        for k in candidates:
            pred_layout, pred = w.predict_without(k)
            if not _cleaner(pred_layout, pred, layout, a, options):
                continue
            rank = (*_defects(pred_layout), -k)
            if best is None or rank < best[0]:
                best = (rank, k)
        if best is None:
            break
        k = best[1]
        key = _strip_key(ds, k)
        before = _defects(layout)
        saved = copy.deepcopy(ds.design.strips)
        w.spend("derive", 0.5 * WORK_DERIVE * (len(ds.design.strips) - k))
        try:
            ds.remove_strip(k)
            after_layout, after = w.layout(), w.assess()
            confirmed = _cleaner(after_layout, after, layout, a, options)
        except native.InputError:
            # A later strip's anchor direction is refused without strip k's mask (it would
            # run along an earlier strip now): an internal refusal, never the user's error.
            confirmed = False
        except native.Cancelled:
            ds.design.strips = saved    # a cancelled weave ends with the design it had
            ds.update()
            raise
        if not confirmed:
            _say(options, f"  strip {k + 1} stays: the re-derived design is not cleaner without it")
            ds.design.strips = saved
            ds.update()           # the state before the removal, restored (DesignState)
            refused.add(key)
            continue
        _say(options, f"took back strip {k + 1}: defective area {before[0]:.4g} -> {_defects(after_layout)[0]:.4g}, "
                      f"flagged vertices {before[1]} -> {_defects(after_layout)[1]}, "
                      f"{len(layout['patches'])} -> {len(after_layout['patches'])} patches")
        _forget_strip(w, result, k, key, before, _defects(after_layout))
        a, layout = after, after_layout
    return a


def _bounding_strips(layout, first, count):
    """The added strips (indices first .. count - 1) whose loops bound a defective patch or
    end at a flagged vertex, latest first: the only ones whose removal can merge a sliver
    away (an edge's "loop" is the loop of the arc it crosses, the strip of that index)."""
    edges = layout.get("edges", ())
    out = set()
    for p in layout.get("patches", ()):
        if p.get("defects"):
            out.update(edges[e]["loop"] for e in p["edges"])
    flagged = _defect_vertices(layout)
    for e in edges:
        if flagged.intersection(e["vertices"]):
            out.add(e["loop"])
    return sorted((k for k in out if first <= k < count), reverse=True)


def _grouped(w, ds, k):
    """Whether strip k has symmetric images or is one (paper §5.8: taken back together only)."""
    return w.groups.get(k, 1) > 1 or "image_of" in ds.design.strips[k].extra or \
        any(ds.design.strips[j].extra.get("image_of") == k for j in range(len(ds.design.strips)))


def _strip_key(ds, k):
    return tuple(tuple(round(x, 9) for x in a.to_list()) for a in ds.design.strips[k].anchors)


def _cleaner(after_layout, after, before_layout, before, options):
    """Whether taking a strip back leaves the layout cleaner: valid, none of _less_clean's
    steps back (validity, crease conformity, defective area, flagged vertices, crease inside
    patches), no kind of defect more frequent, no more patches past the area bound, strictly
    less defective area or fewer flagged vertices, and corners no worse counting every
    defective patch as four 90-degree corners (_deviation: a sliver merged into its
    neighbour may leave it a worse quad, but not worse than the sliver was).

    Per kind, because the area alone trades: merging slivers away can leave a patch that is
    no quad, or surface in no patch, where there was none, and such a patch is not fitted at
    all (a CAD mesh's take-back lowered the defective area by 6 % and its fit coverage from
    99.6 % to 89.6 %)."""
    if not after_layout["valid"] or after["colours"]["red"]:
        return False
    if _less_clean(after_layout, after, before_layout, before):
        return False
    if any(after_layout["defects"][k] > n for k, n in before_layout["defects"].items()):
        return False
    if len(_oversized(after_layout, options.max_area_ratio)) > len(_oversized(before_layout, options.max_area_ratio)):
        return False
    if options.patches and len(after_layout["patches"]) < options.patches:
        return False      # a patch target is density asked for
    (area_a, flagged_a), (area_b, flagged_b) = _defects(after_layout), _defects(before_layout)
    total = sum(p["area"] for p in before_layout.get("patches", ())) or 1.0
    fewer = area_a < area_b - 1e-6 * total or flagged_a < flagged_b
    return fewer and _deviation(after_layout) <= _deviation(before_layout)


def _forget_strip(w, result, k, key, before, after):
    """Strip k was taken back: later strips move down one index (the log's, the groups'), its
    log entry goes, and result.taken_back says what the removal did."""
    entry = next((e for e in result.log if e["strip"] == k), None)
    result.log = [e for e in result.log if e["strip"] != k]
    for e in result.log:
        if e["strip"] > k:
            e["strip"] -= 1
    w.groups = {(i - 1 if i > k else i): c for i, c in w.groups.items() if i != k}
    result.taken_back.append({"anchor": [list(x) for x in key], "added_for": entry["reason"] if entry else None,
                              "defective_area": [before[0], after[0]], "flagged_vertices": [before[1], after[1]]})


def _entry(ds, index, reason, region, colour, seed, cost, elapsed, **figures):
    """The log entry of strip `index` just added: why (reason, region, colour, seed point),
    its anchor and loop cost, the figures it changed, when."""
    return {"strip": index, "reason": reason, "region": region, "colour": colour,
            "seed": [float(x) for x in _seed_point(seed)], "anchor": list(ds.design.strips[index].anchors[0].to_list()),
            "cost": cost, **figures, "time_s": round(elapsed(), 3)}


def _record(ds, result, entry):
    """Log an added strip, and keep why it was added in the design (design.json's added_by)."""
    ds.design.strips[entry["strip"]].extra["added_by"] = {k: entry[k] for k in ("reason", "region", "colour", "seed")}
    result.log.append(entry)


def _more_cuts(w, ds, options, rest, a, region, result, elapsed):
    """Add the other cuts one round of red-region queries found, before a new round asks again.

    Each round asks every seed point of the red region (candidates) and adds the best loop.
    On a part with many handles (a casting, a plate with many bores) each of the others was
    a cut too, mostly of another handle, and the next round finds them again at the same
    points: every handle cost a round of queries at all the region's points, whose number
    grows with the loops around it (a genus-15 NIST part: 10 to 16 queries, 70 to 160 units
    a strip, and red regions left at its allowance after 12 of its 30 cuts). So the round's
    other proposals that lowered the red regions' genus or badness (`rest`, best first) are
    tried next, each at the cost of a derivation: a strip is added by its anchor, so the
    design derives the loop through it in the design as it is now, and the strip is kept only
    if that lowers the genus or badness again (a second cut of a handle already cut lowers
    neither, and is removed), and only while red regions remain after it: the cut that makes
    the design valid comes from a fresh round. The next round then asks only for what is
    left.
    Returns the assessment after the strips kept."""
    for _, cost, loop, point, _ in rest:
        if not a["colours"]["red"] or len(ds.design.strips) >= w.max_strips() or w.out_of_red_work(elapsed):
            break
        current = score(a)
        index = w.add(loop, point)
        if index is None:
            continue
        after = w.assess()
        now = score(after)
        if not after["colours"]["red"]:
            # The cut that completes validity sets the layout every later phase starts
            # from: a fresh round chooses it, over all seed points of the design as it is now,
            # by the whole score (a square ring made valid by the round's second loop kept
            # a crease region the crease phase could not part; the fresh round's loop left
            # one it could).
            w.remove(index)
            break
        if now[:2] >= current[:2]:
            w.remove(index)
            continue
        _say(options, f"strip {index + 1}: red region {region}, the same round's next cut "
                      f"(genus and badness {tuple(current[:2])} -> {tuple(now[:2])})")
        _record(ds, result, _entry(ds, index, "red region", region, "red", point, cost, elapsed,
                                   score_before=list(current), score_after=list(now)))
        a = after
    return a


def _crease_pair(w, ds, options, a, points, found, region, elapsed):
    """Part a crease region by two loops where no single loop does: a crease cycle (the rim
    of a boss, a bore or a pocket) has to be crossed by loops that cross each other.

    One loop across a closed crease leaves each half of it with both exits on that loop's one
    arc (the crease excess stays or rises), and the loop between two crease cycles (round a
    boss's wall, between its top rim and its base) crosses nothing there, so it leaves an
    annulus, a red region. Together they part it: the ring cuts the crossing loop's arc
    between the exits, the crossing loop makes the ring's sides a disc. So the loops of the
    round (`found`, one per seed point) and the loops of both families at the region's crease
    seed (its principal directions: around and across the bridge between two pieces) are
    predicted in pairs (two extra loops in one assessment, no derivation), and the best pair
    that lowers the score is added, first loop first; both are removed unless the re-derived
    design is valid and lowers the score as predicted.
    Returns ([the two log entries], the assessment after them), or None."""
    current = score(a)
    pool = [(c[2], c[3], c[1], c[4]["crossings"]) for c in found]
    for loop in w.along_principal_directions(list(points[0])[:3]):
        pool.append((loop, points[0], loop.cost, None))
    firsts = {}           # one entry per loop (_loop_key), the first one found
    for entry in pool[:CREASE_PAIR_LOOPS]:
        firsts.setdefault(_loop_key(entry[0]), entry)
    loops = [(loop, point, cost, w.assess([loop], seeds=False)["crossings"] if crossings is None else crossings)
             for loop, point, cost, crossings in firsts.values()]
    best = None
    for i in range(len(loops)):
        for j in range(i + 1, len(loops)):
            pa = w.assess([loops[i][0], loops[j][0]], seeds=False)
            s = score(pa)
            # Only loops that cross each other (more crossings than each brings alone): two
            # of one family run side by side, and the design refuses the second where it
            # runs along the first (a loop's direction is disabled beside a strip's, §6.2).
            crossing = pa["crossings"] > loops[i][3] + loops[j][3] - a["crossings"]
            if crossing and s[:2] <= current[:2] and s < current and (best is None or s < best[0]):
                best = (s, i, j)
    if best is None:
        return None
    added = []
    for k in best[1:]:
        index = w.add(loops[k][0], loops[k][1])
        if index is None:
            break
        added.append(index)
    after = w.assess() if len(added) == 2 else None
    now = score(after) if after is not None else None
    if after is None or after["colours"]["red"] or now >= current:
        for index in reversed(added):
            w.remove(index)
        return None
    _say(options, f"  crease region {region} parted by a pair: strips {added[0] + 1} and {added[1] + 1}")
    scores = {"score_before": list(current), "score_after": list(now)}
    return [_entry(ds, index, "crease region (a pair)", region, "crease", loops[k][1], loops[k][2], elapsed,
                   **scores) for index, k in zip(added, best[1:])], after


def _coverage_pair(w, ds, options, a, candidate, elapsed, rescue):
    """Cover an area no single strip can: the loop proposed there, then the loop that makes
    the red region it leaves valid again (the red phase's choice: every seed point, ranked
    alternatives). On a part whose strips all lie on one handle (a key: two loops around its
    bow), every loop around the shaft cuts off a cap no loop crosses, a red region, and the
    layout stays one patch over the whole part; the cap's crossing loop runs along the
    shaft. Both are kept if the design ends valid with more crossings, less uncovered area
    and colours no worse (score), or with more of the part in patches the refit takes, at a
    cost to the creases and colours only (`rescue`, _FitRescue), else both are removed.
    Returns ([the two log entries], the assessment after them), or None."""
    current = score(a)
    _, cost, loop, point, _ = candidate
    rescue.measure()
    first = w.add(loop, point)
    if first is None:
        return None
    mid = w.assess()
    reds = [x for x in seeds_in_order(mid, options, set()) if x[2] == "red"]
    if reds:
        reason, region, _, points = reds[0]
        for s, cost2, loop2, point2, _ in w.candidates(points, options.alternatives, score(mid), True):
            if s[:2] > current[:2] or w.out_of_work(elapsed):
                break                 # sorted: no valid proposal after this one
            second = w.add(loop2, point2)
            if second is None:
                continue
            after = w.assess()
            if after["colours"]["red"] == 0 and after["crossings"] > a["crossings"] \
                    and after["uncovered"]["area"] < a["uncovered"]["area"] \
                    and (score(after) <= current or rescue.gained(after)):
                _say(options, f"  covered by a pair: strips {first + 1} and {second + 1}")
                scores = {"score_before": list(current), "score_after": list(score(after))}
                return [_entry(ds, first, "uncovered area (with the next strip)", -1, "uncovered", point, cost,
                               elapsed, **scores),
                        _entry(ds, second, reason, region, "red", point2, cost2, elapsed, **scores)], after
            w.remove(second)
    w.remove(first)
    return None


def _mostly_uncovered(a):
    """Whether most of the part lies in one area no strip covers (over half the surface)."""
    u = a["uncovered"]
    return u["largest_area"] > 0.5 * u["surface_area"]


def _fittable_area(layout):
    """The area of a layout's patches the refit takes: those with four corners (a patch with
    more or fewer gets no NURBS patch, surfacing.py). A patch over a crease counts: the refit
    fits it, if not within tolerance, and the crease phase can split it; counted out, the
    first loop along a key's shaft, whose patches all hold a crease ringing the shaft, gained
    nothing, and the key stayed one patch."""
    if not layout["valid"]:
        return 0.0
    return sum(p["area"] for p in layout["patches"] if p.get("quad", False))


class _FitRescue:
    """Most of the part in no patch the refit takes (_fittable_area): then a strip (or
    _coverage_pair's pair) that brings more of it into such patches is kept at any cost to the
    creases and colours, as long as the design stays valid with no more patchless discs
    (score's first three terms).

    Why: score() ranks the crease excess before coverage, a proxy that every separating loop
    lowers. A loop along a shaft crosses every crease ringing it, and each crossing is an exit
    of its two regions until loops around the shaft part them, so the excess can only rise
    with it (a key with a bit and a collar: 60 to 98), while its patches are the first the
    refit takes. Held to the whole score, the key stayed one non-quad patch over the whole
    part, and its STEP had nothing in it.

    Asked only where no seed helped by the score (the uncovered-area seed, last in order,
    and the pair after it). What it spends (a layout before, one after each strip it judges,
    the strips it tries) is booked to the COVERAGE account (_Weaver.book_coverage), so that
    where it takes nothing the other phases' budget is what it was."""

    def __init__(self, w, a):
        self.w, self.before = w, score(a)
        self.surface_area = a["uncovered"]["surface_area"]
        self.area = None     # fittable area of the design as it was (measure)

    def measure(self):
        """Measure the design as it is now, before a strip is added (once)."""
        if self.area is None:
            mark = self.w.spent_now()
            self.area = _fittable_area(self.w.layout())
            self.w.book_coverage(mark)

    def allows(self, s):
        """Whether a proposal's (predicted) score may be kept under the rescue: validity and
        patchless discs no worse, and the design as it was mostly in no fittable patch. Asked
        before the proposal is added (measure)."""
        if s[:3] > self.before[:3]:
            return False
        self.measure()
        return self.area < 0.5 * self.surface_area

    def gained(self, after):
        """Whether the design now in the weaver (assessed: after) is allowed and has more of
        the part in fittable patches than the design measured before the strip (none
        measured: the rescue was not asked for it, and does not judge it)."""
        if self.area is None or not self.allows(score(after)):
            return False
        mark = self.w.spent_now()
        gain = _fittable_area(self.w.layout()) > self.area
        self.w.book_coverage(mark)
        return gain


def _largest(ds, colour, limit):
    """The design's regions of one colour (weave_assessment's, with seeds), largest first; at
    most `limit` (None: all)."""
    a = native.weave_assessment(ds.native, [], 1)
    regions = sorted((r for r in a["regions"] if r["colour"] == colour), key=lambda r: -r["area"])
    return regions if limit is None else regions[:limit]


def red_regions(ds, limit=5):
    """The red regions of the design, largest first (at most `limit`): where each is (its
    centre, model units: where a strip by hand would start), its area, genus and boundary
    loops (a disc has genus 0 and one boundary loop), for report.json's "red_regions" (limit
    None: all of them)."""
    return [{"position": [float(x) for x in r["seeds"][0]] if r["seeds"] else None, "area": float(r["area"]),
             "genus": int(r["genus"]), "boundaries": int(r["boundaries"])}
            for r in _largest(ds, "red", limit)]


def crease_regions(ds, limit=5):
    """The crease regions of the design (they keep a valid layout from following the part's
    creases, issue 17), largest first (at most `limit`): where a strip by hand would go (the
    region's crease seed: where a loop across the crease parts what the region holds, else a
    point inside), its area and what is wrong (crease_structure.h's problem, e.g. "two crease
    nodes"), for report.json's "crease_regions"."""
    def position(r):
        p = r.get("crease_seed") or (r["seeds"][0] if r["seeds"] else None)
        return None if p is None else [float(x) for x in list(p)[:3]]
    return [{"position": position(r), "area": float(r["area"]), "problem": str(r.get("crease_problem", ""))}
            for r in _largest(ds, "crease", limit)]


def _point(p):
    return "(" + ", ".join(f"{x:.4g}" for x in p) + ")"


def _at(position):
    return "" if position is None else " at " + _point(position)


def why_crease(regions, total, stopped, budget):
    """One line for people, for a valid layout that is not crease-conforming: which crease
    regions remain, where, what keeps each from carrying its creases, why weaving stopped, and
    what to try (a strip by hand across the crease there separates what the region holds)."""
    shown = "; ".join(f"a region{_at(r['position'])} ({r['problem'] or 'crease'})" for r in regions[:3])
    first = next((r["position"] for r in regions if r["position"] is not None), None)
    by_hand = "adding a strip by hand through " + (_point(first) if first else "the crease region") + \
        ", across the crease"
    return (f"{total} crease region{'' if total == 1 else 's'} remain{'s' if total == 1 else ''}: "
            f"{shown}{'; ...' if total > 3 else ''}; weaving stopped: {stopped}; "
            f"try --budget {2 * budget:g}, or {by_hand}")


def why_red(red, total, stopped, max_strips, budget):
    """One line for people: which red regions remain, where, why each is no disc, why weaving
    stopped, and what to try."""
    def where(r):
        at = _at(r["position"])
        loops = f"{r['boundaries']} boundary loop{'' if r['boundaries'] == 1 else 's'}"
        return f"a region{at} (genus {r['genus']}, {loops}: not a disc)"
    shown = "; ".join(where(r) for r in red[:3]) + ("; ..." if total > 3 else "")
    tries = [f"--budget {2 * budget:g}"]
    if stopped == "max strips":
        tries.insert(0, f"--max-strips {max_strips + 20}")
    first = next((r["position"] for r in red if r["position"] is not None), None)
    by_hand = "adding a strip through " + (_point(first) if first else "the red region") + \
        " by hand (a loop that cuts it)"
    return (f"{total} red region{'' if total == 1 else 's'} remain{'s' if total == 1 else ''}: {shown}; "
            f"weaving stopped: {stopped}; try {', '.join(tries)}, or {by_hand}")


def auto_weave(ds, options=None):
    """Complete the design of `ds` (a DesignSession) by adding strips; see the module doc.
    The design's existing strips are kept, first and unchanged."""
    options = options or WeaveOptions()
    options.check()
    if options.patches:
        # A patch target is work in proportion to it: a refining strip costs 10 to 20 units
        # and adds 2 to 6 patches (measured on the bumpy sphere and the filleted box).
        options = replace(options, budget=max(options.budget, WORK_PER_TARGET_PATCH * options.patches))
    w = _Weaver(ds, options)
    # Loop queries on one thread, with a cap on their work: both make each query's outcome
    # the same on any machine (two threads share the search's bound by timing).
    threads, polls = w.session.threads, w.session.max_query_polls
    w.session.set_threads(1)
    w.session.max_query_polls = options.query_polls
    try:
        return _weave(w, ds, options)
    finally:
        w.session.max_query_polls = polls
        w.session.set_threads(threads)


def _weave(w, ds, options, start=None):
    """The colour phases (red, crease, orange, yellow: seeds_in_order), then refinement;
    `start`: the weave's start time (perf_counter) when this is a later pass of one weave."""
    start = time.perf_counter() if start is None else start
    result = WeaveResult()
    a = w.assess()
    w.count_cuts(a)
    skip = set()          # seed points that gave nothing useful
    crease_skipped = set()   # ... of them, the crease regions' (asked again with pairs)
    pairs = False         # crease regions get pairs of loops (_crease_pair) once singles ran out
    stalls = 0            # consecutive red-phase additions that did not lower the score

    def elapsed():
        return time.perf_counter() - start

    while True:
        if len(ds.design.strips) >= w.max_strips():
            result.stopped = "max strips"
            break
        current = score(a)
        valid = a["colours"]["red"] == 0
        if valid:
            w.became_valid(elapsed)
        if valid and (options.patches or options.refine_patches) and \
                a["crossings"] >= (options.patches or options.refine_patches):
            result.stopped = "patch target"
            break
        seeds = w.axis_entries(a, skip) + seeds_in_order(a, options, skip)
        if valid and not w.coverage_allowance():
            seeds = [x for x in seeds if x[2] not in COVERAGE]
        if not valid and w.red_again:
            seeds = [x for x in seeds if x[2] == "red"]
        # While a region is red, the other colours leave room under the cap for the cuts it
        # still needs: a cap reached by crease strips on an invalid design ends with no layout.
        no_room = not valid and bool(seeds) and seeds[0][2] != "red" and \
            len(ds.design.strips) >= w.max_strips() - cuts_to_discs(a)
        if no_room:
            seeds = []
        if valid and w.out_of_work(elapsed):
            result.stopped = w.why_out(elapsed)
            break
        if not valid and w.out_of_red_work(elapsed):
            result.stopped = w.why_out_of_red(elapsed)
            break
        if valid and a["crossings"] and options.refine and \
                w.quality_work(elapsed)[0] >= options.colour_share * options.budget:
            # The rest of the budget goes to refinement, which splits the worst patches: on
            # scans the colour seeds mostly give strips the real layout does not keep.
            result.stopped = "no seed helps"
            break
        if a["colours"]["red"] and not w.looking_harder and not any(x[2] == "red" for x in seeds):
            # Invalid and out of ideas for the red regions: look harder once (more seed points
            # per region, more ranked alternatives, both families of loops at each point:
            # proposals) before any strip goes to the other colours,
            # rather than end with no layout. Crease and colour strips refine a layout that does
            # not exist while a region is no disc, and each one adds loops the red region's
            # cut must then cross transversally too: later red proposals only get harder.
            w.looking_harder = True
            w.options = options = replace(options, seeds_per_region=3 * options.seeds_per_region,
                                          alternatives=2 * options.alternatives)
            _say(options, f"red regions: no seed point left; looking harder ({options.seeds_per_region} "
                          f"seed points a region, {options.alternatives} alternatives, both families of loops)")
            skip.clear()
            stalls = 0
            a = w.assess()
            continue
        if not seeds and not valid and not w.red_again:
            # The other colours are done (or out of room) and a region is still red: its seed
            # points once more, in the design those strips made. Each strip changes the
            # regions and the field, so a seed point that gave nothing may cut now (a
            # 23-bore plate's last annulus: its second-ranked loop there would have been
            # valid); once, at the end, because asking them after every strip costs the
            # crease phase its work.
            w.red_again = "max strips" if no_room else "no seed helps"
            _say(options, "red regions remain and the other colours are done: their seed points once more")
            skip.clear()
            stalls = 0
            continue
        if valid and not w.rims_counted and a["colours"]["crease"] and "crease" in options.colours and \
                not any(x[2] == "crease" for x in seeds) and any(r.get("crease_rim_lack") for r in a["regions"]):
            # Every crease region's seed points were asked for one loop, and rims still lack
            # crossings: from now on score() counts that lack before the excess (rim_lack), so
            # a loop across a rim is taken where it raises the excess, and the crease regions'
            # seeds are asked once more (one whose only problem is such a rim seeds on it).
            w.rims_counted = True
            skip -= crease_skipped
            a = w.assess()
            _say(options, f"crease regions remain and rims lack {rim_lack(a)} crossings: their seeds once more, "
                          f"rims counted first")
            continue
        if valid and options.crease_pairs and not pairs and a["colours"]["crease"] and "crease" in options.colours and \
                not any(x[2] == "crease" for x in seeds):
            # Every crease region's seed points were asked for one loop: now for two
            # (_crease_pair), after the single loops everywhere, as a pair costs what two
            # or three single strips do (a plate with three bores under a small budget spent
            # it on one region's pair, and the single loops that part two others never came).
            pairs = True
            skip -= crease_skipped
            _say(options, "crease regions remain: their seed points once more, with pairs of loops")
            continue
        if not seeds:
            colours_left = sum(1 for r in a["regions"] for c in ("crease", "orange", "yellow")
                               if c in options.colours and shows(r, c))
            result.stopped = "done" if valid and not colours_left else "max strips" if no_room else \
                w.red_again or "no seed helps"
            break
        reason, region, colour, points = seeds[0]
        _say(options, f"strip {len(ds.design.strips) + 1}: {reason} {region} "
                      f"(red {a['colours']['red']}, patchless {patchless(a)}, crease {a['colours']['crease']}, open {open_stretches(a)}, "
                      f"orange {a['colours']['orange']}, yellow {a['colours']['yellow']}, work {w.work:.0f}, "
                      f"{elapsed():.1f} s)")
        added = None
        rest = []             # the round's candidates after the one added (_more_cuts)
        tried_real = False
        splitting = []        # uncovered area: proposals that would leave a red region
        found = []            # the last round's candidates (_crease_pair)
        rescue = _FitRescue(w, a) if colour == "uncovered" and valid else None
        spent_before = w.spent_now()   # what this seed costs (coverage_spent)
        # Ranked alternatives (slow: a second search per rank) and both families of loops only
        # where validity or coverage is at stake (a region's second stretch lies in no patch).
        for alternatives in ((1, options.alternatives) if colour in ("red",) + COVERAGE else (1,)):
            tried = points if alternatives == 1 else points[:1]
            # Every point where the strip fixes coarse structure or covers surface no patch would
            # (a patchless disc's loop is a solid's second belt: the centre-first order of the
            # colours left a soap box 2 patches and 56 % of its surface within the tolerance).
            found = w.candidates(tried, alternatives, current, colour in ("red",) + COVERAGE)
            if colour == "uncovered":
                splitting = [c for c in found if c[0][:2] > current[:2]]
            for rank, (s, cost, loop, point, predicted) in enumerate(found):
                improves = s < current
                by_rescue = False     # tried only under the rescue: its work is coverage work
                if colour == "red" and not improves and s[:2] <= current[:2] and stalls < 3:
                    improves = True   # a handle can take two loops to cut (a torus: meridian, then equator)
                if colour == "uncovered":
                    improves = s <= current   # coverage, without spoiling the colours
                    by_rescue = not improves and rescue is not None and rescue.allows(s)
                    improves = improves or by_rescue
                    if not improves and a["crossings"] == 0 and s[:2] <= current[:2]:
                        improves = True       # no patch yet: any valid strip is progress
                if not improves and colour in ("crease", "orange", "yellow") and s[:2] <= current[:2] \
                        and not tried_real:
                    # The prediction keeps the old singularities, which the new strip moves:
                    # give the best proposal one real try.
                    improves = tried_real = True
                if not improves and colour != "red" and a["crossings"] == 0 and s[:2] <= current[:2]:
                    improves = True   # no patch yet: a valid strip that crosses is progress
                if not improves:
                    break             # candidates are sorted: none after this one is better
                mark = w.spent_now()
                index = w.add(loop, point)
                if index is None:
                    if by_rescue:
                        w.book_coverage(mark)
                    continue
                after = w.assess()
                # While there is no patch, only validity counts (the colours come with patches).
                worse = score(after) > current and not (a["crossings"] == 0 and score(after)[:2] <= current[:2]) \
                    and not (rescue is not None and rescue.gained(after))
                no_gain = colour == "uncovered" and after["uncovered"]["area"] >= a["uncovered"]["area"] \
                    and after["crossings"] <= a["crossings"]
                if worse or no_gain:
                    w.remove(index)          # the re-derived design is worse than predicted: reject
                if by_rescue:
                    w.book_coverage(mark)
                if worse or no_gain:
                    continue
                stalls = stalls + 1 if score(after)[:2] >= current[:2] and colour == "red" else 0
                added = _entry(ds, index, reason, region, colour, point, cost, elapsed,
                               score_before=list(current), score_after=list(score(after)))
                rest = [c for c in found[rank + 1:] if c[0][:2] < current[:2]]
                a = after
                break
            if added:
                break
        if not added and pairs and colour == "crease" and valid and found and \
                len(ds.design.strips) + 2 <= w.max_strips() and not w.out_of_work(elapsed):
            pair = _crease_pair(w, ds, options, a, points, found, region, elapsed)
            if pair is not None:
                entries, a = pair
                for entry in entries:
                    _record(ds, result, entry)
                continue
        if not added and splitting and valid and _mostly_uncovered(a):
            # Only where no strip reaches most of the part: elsewhere the single strips that
            # cover have been found, and a pair tried and taken back spends work refinement
            # would use better (the rocker-arm: 17.4 against 16.6 degrees).
            pair = _coverage_pair(w, ds, options, a, splitting[0], elapsed, rescue)
            if pair is not None:
                entries, a = pair
                for entry in entries:
                    _record(ds, result, entry)
                continue
        if colour in COVERAGE and valid:
            w.book_coverage(spent_before)
        if added:
            _record(ds, result, added)
            w.axis_placed = w.axis_placed or added["reason"] == "beside the rotation's axis"
            if colour == "red" and rest and a["colours"]["red"]:
                a = _more_cuts(w, ds, options, rest, a, region, result, elapsed)
                stalls = 0
            continue
        for p in points:      # nothing helped from this region's seeds: do not ask again
            skip.add(_coverage_key(p) if colour == "uncovered" else _key(p))
            if colour == "crease":
                crease_skipped.add(_key(p))

    if options.refine and a["colours"]["red"] == 0 and result.stopped in ("done", "no seed helps"):
        a = _refine(w, ds, options, a, result, elapsed)
    if options.take_back and a["colours"]["red"] == 0 and len(ds.design.strips) > w.user_strips:
        a = _take_back(w, ds, options, a, result, elapsed)
    result.assessment = a
    result.time_ms = elapsed() * 1000.0
    result.work, result.cancelled_queries, result.capped_queries = w.work, w.cancelled, w.capped
    result.max_strips = w.max_strips()
    _say(options, f"{result.stopped}: {len(ds.design.strips)} strips ({w.user_strips} given, "
                  f"{len(ds.design.strips) - w.user_strips} added), red {a['colours']['red']}, crease {a['colours']['crease']}, "
                  f"orange {a['colours']['orange']}, "
                  f"yellow {a['colours']['yellow']}, work {w.work:g} ("
                  + ", ".join(f"{k} {v:.0f}" for k, v in sorted(w.spent.items(), key=lambda kv: -kv[1]))
                  + f"), {elapsed():.1f} s"
                  + (f", {w.cancelled} loop queries cut by the timeout" if w.cancelled else ""))
    return result
