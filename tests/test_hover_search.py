"""Hover (the best loop through a point over all directions, paper §5) on a CAD-like part:
flat faces and creases, where the alignment term is zero in every direction and the start
directions are searched coarse-to-fine around the cheapest loop so far, each search a
bidirectional search that grows its smaller side (Pohl's rule) and an unbounded start is put
off at a doubling budget. None of that may change the result: the hover loop must cost what
the cheapest of every direction's own loop costs (each searched to the end), and what plain
Dijkstra on one thread finds, and be the same loop on one thread or two."""
import numpy as np
import pytest

import stripweave as sw
from stripweave.loops import LoopSession

import FreeCAD  # noqa: F401
import Part


@pytest.fixture(scope="module")
def slab():
    """A 30 x 12 x 6 box with sharp edges: its loops run around the short way, and on the
    big faces every direction costs the same locally, so only the search order finds them."""
    return sw.from_shape(Part.makeBox(30, 12, 6), target_triangles=12000)


def face_points(surface, count, seed):
    rng = np.random.default_rng(seed)
    return [tuple(surface.vertices[i]) for i in rng.choice(len(surface.vertices), size=count, replace=False)]


def test_hover_equals_the_cheapest_direction_searched_to_the_end(slab):
    session = LoopSession(slab)
    for p in face_points(slab, 6, seed=7):
        hover = session.best_loop(p)
        # Every direction's best loop on its own (the alternatives search each start with a
        # cost cap of 6x the best, no shared bound, no ordering): the cheapest of them.
        every = session.loops([p], alternatives=1000)
        assert hover["cost"] == pytest.approx(min(l["cost"] for l in every), rel=1e-9)
        assert hover["closed"]


def test_hover_equals_plain_dijkstra_and_does_not_depend_on_threads(slab):
    plain = LoopSession(slab, algorithm="dijkstra", threads=1)
    one = LoopSession(slab, threads=1)
    two = LoopSession(slab, threads=2)
    for p in face_points(slab, 6, seed=8):
        a, b, c = one.best_loop(p), two.best_loop(p), plain.best_loop(p)
        assert a["nodes"] == b["nodes"]
        assert a["cost"] == b["cost"]
        assert a["cost"] == pytest.approx(c["cost"], rel=1e-9)


def test_the_loop_through_the_top_face_runs_around_the_short_way(slab):
    """The geometric fact behind the order: from the middle of the top face the cheapest
    loop goes around the 12 x 6 section (length 36), not the 30 x 6 one (72)."""
    session = LoopSession(slab)
    loop = session.best_loop((15, 6, 6))
    p = np.asarray(loop["points"])
    length = np.linalg.norm(np.diff(p, axis=0), axis=1).sum()
    assert length == pytest.approx(36, rel=0.05)
    assert np.ptp(p[:, 0]) < 2.0  # stays in one x section
