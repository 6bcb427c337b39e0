"""The design tool adds exactly the loop it shows (issue 20): every proposal
through a point (the hover's best loop and the Ctrl+wheel alternatives)
carries anchors on it from which the design's own loop search derives the
same loop, and adding it gives that loop as the strip.  Headless: the
SessionCache the tool's worker thread uses, on generated parts."""

import numpy as np
import pytest

import models
from freecad.stripweave_wb.design_session import SessionCache, anchor_sets
from freecad.stripweave_wb.loop_match import loop_gap, same_loop_tolerance
from stripweave import surface
from stripweave.design import Design

TRIANGLES = 4000


def cache_of(shape):
    c = SessionCache()
    c.sync(surface.from_shape(shape, target_triangles=TRIANGLES), Design(), True)
    return c


@pytest.fixture(scope="module")
def box():
    return cache_of(models.box())


@pytest.fixture(scope="module")
def cylinder():
    return cache_of(models.cylinder())


def test_loop_gap_is_a_symmetric_polyline_distance():
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ring = np.c_[np.cos(t), np.sin(t), np.zeros_like(t)]
    assert loop_gap(ring, np.roll(ring, 37, axis=0)) == 0.0      # another start, the same loop
    assert loop_gap(ring, ring + [0, 0, 0.3]) == pytest.approx(0.3)
    assert loop_gap(ring, ring[:100]) == pytest.approx(np.sqrt(2), abs=0.01)  # half a loop is not the loop
    assert loop_gap(ring, ring[:100]) == loop_gap(ring[:100], ring)


@pytest.mark.parametrize("part, points", [
    ("box", [(5, 5, 10), (0, 3, 5), (2, 0, 7)]),
    ("cylinder", [(5, 0, 10), (0, 5, 3), (0, 0, 20)]),
])
def test_every_alternative_is_reproduced_by_anchors_on_it(part, points, request):
    c = request.getfixturevalue(part)
    tolerance = same_loop_tolerance(c.session.surface.vertices)
    shown = 0
    for p in points:
        proposals, _revision = c.proposals(p, 6)
        best, _ = c.proposals(p, 1)
        assert len(best) == 1 and len(proposals) >= 2
        for d in best + proposals:
            assert len(d["anchors"]) == 4 and all(len(a) == 6 for a in d["anchors"])
            anchors, gap = c.reproducing_anchors(d["anchors"], d["points"])
            assert anchors is not None, "proposal of length {:.4g} through {} not reproduced ({:.3g})".format(
                d["length"], p, gap)
            assert gap <= tolerance
            shown += 1
    assert shown >= 9


def test_some_alternatives_need_several_anchors(box, cylinder):
    """Why anchor_sets goes beyond one anchor: an alternative need not be the
    best loop through any single node of it."""
    needing = 0
    for c, p in ((box, (2, 0, 7)), (cylinder, (0, 5, 3)), (cylinder, (5, 0, 10))):
        for d in c.proposals(p, 6)[0]:
            single = [s for s in anchor_sets(d["anchors"]) if len(s) == 1]
            tolerance = same_loop_tolerance(c.session.surface.vertices)
            with c.lock:
                c._apply_mask()
                gaps = [loop_gap(c.session.loop_session.loops(s, 1)[0]["points"], d["points"]) for s in single]
            needing += min(gaps) > tolerance
    assert needing >= 1


def test_add_shown_adds_the_loop_shown():
    c = cache_of(models.torus())
    tolerance = same_loop_tolerance(c.session.surface.vertices)
    c.add_strip([(13, 0, 0, 0, 0, 1)])                  # a meridian
    for p in ((0, -13, 0), (7, 0, 0), (9.5, -2.5, 2.9), (-10, 0, 3)):
        proposals, _ = c.proposals(p, 6)
        if len(proposals) >= 2:
            break
    assert len(proposals) >= 2
    alternative = proposals[-1]                          # the worst one shown
    data, derived = c.add_shown(alternative["anchors"], alternative["points"])
    assert len(data["strips"]) == 2 and len(derived.strips) == 2
    assert loop_gap(derived.strips[1]["points"], alternative["points"]) <= tolerance
    assert loop_gap(derived.strips[1]["points"], proposals[0]["points"]) > tolerance
