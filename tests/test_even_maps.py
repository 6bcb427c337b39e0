"""Even maps (issue 19, fit step 6): a patch that misses the tolerance at its most spans
is mapped again with its stretch spread evenly (native surfacing/patch_parameterization.h)
before any split. The harmonic map squashes a protrusion exponentially in its height, so
evenly spaced knots cannot resolve it at any span count; the even map gives it its share
of the square.

The part: the box [0, 10]^3 with a knob on its top face (a Gaussian of height 3 and sigma
1.2, as tall as 2.5 sigma), as a mesh; its clean layout is the cube's 6 faces, so the top
patch holds the whole knob (test_split_strip.part)."""
import numpy as np
import pytest

from stripweave._native import native
from stripweave.surfacing import fit_report
from test_split_strip import TOP, assert_conforming, part


@pytest.fixture(scope="module")
def knob():
    return part(height=3.0, sigma=1.2)


def uv_areas(uv, triangles):
    a, b = uv[triangles[:, 1]] - uv[triangles[:, 0]], uv[triangles[:, 2]] - uv[triangles[:, 0]]
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def test_the_even_map_gives_the_knob_its_share_of_the_square(knob):
    """The top patch's two maps: both bijections onto the unit square with the same
    boundary; the knob's top (above half its height) holds 9 % of the patch's area, the
    harmonic map gives it 3.4 % of the square, the even map at least 1.5 times that and
    nearer its 9 %."""
    _, net = knob
    patch = net["patches"][TOP]
    V, F = np.asarray(patch["vertices"]), np.asarray(patch["triangles"])
    harmonic, gain = native.square_map(dict(patch, even_stretch=False))
    even, gain_again = native.square_map(dict(patch, even_stretch=True))
    assert gain == gain_again > 1.4
    for uv in (harmonic, even):
        assert (uv_areas(uv, F) > 0).all()  # counter-clockwise, none folded
        assert uv_areas(uv, F).sum() == pytest.approx(1.0, abs=1e-9)
        assert uv.min() >= 0 and uv.max() <= 1
    border = ((harmonic <= 1e-12) | (harmonic >= 1 - 1e-12)).any(axis=1)
    assert np.abs(even[border] - harmonic[border]).max() < 1e-12  # the sides are pinned alike
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    top = V[F].mean(axis=1)[:, 2] > 10 + 1.5
    share = area[top].sum() / area.sum()
    in_harmonic, in_even = uv_areas(harmonic, F)[top].sum(), uv_areas(even, F)[top].sum()
    assert in_even > 1.5 * in_harmonic and abs(in_even - share) < abs(in_harmonic - share)


def test_a_flat_patch_has_one_map(knob):
    """The bottom face is flat and square: its harmonic map spreads it evenly already, so
    the even map is the same map, and its gain is 1."""
    _, net = knob
    harmonic, _ = native.square_map(dict(net["patches"][0], even_stretch=False))
    even, gain = native.square_map(dict(net["patches"][0], even_stretch=True))
    assert np.array_equal(harmonic, even) and gain == pytest.approx(1.0, abs=1e-9)


def test_the_harmonic_map_leaves_a_knob_unresolved(knob):
    surface, net = knob
    r = native.refit(surface, net, split_patches=False, even_maps=False)
    top = r["per_patch"][TOP]
    assert top["nu"] == top["nv"] == 24  # max_spans: refinement cannot do more
    assert top["max_deviation"] > 1.5 * r["tolerance"] and not r["tolerance_met"]
    assert not any(p["even_stretch"] for p in r["per_patch"])


def test_an_even_map_resolves_the_knob_without_a_split(knob):
    surface, net = knob
    harmonic = native.refit(surface, net, split_patches=False, even_maps=False)
    r = native.refit(surface, net, return_network=True)
    assert r["tolerance_met"], (r["max_deviation"], r["tolerance"])
    assert r["splits"] == [] and len(r["per_patch"]) == 6
    # Only the patch that missed is mapped evenly; the others keep their harmonic maps
    # and, the knob resolved, the top's own distance falls by more than half.
    assert [p["even_stretch"] for p in r["per_patch"]] == [i == TOP for i in range(6)]
    assert r["per_patch"][TOP]["fit_max_deviation"] < 0.5 * harmonic["per_patch"][TOP]["fit_max_deviation"]
    assert r["per_patch"][TOP]["max_deviation_patch_to_source"] <= r["tolerance"]
    assert r["closed"] and r["valid_shell"] and r["max_seam_gap"] < 1e-6 * 10 * 3 ** 0.5
    # The fitted network records the even map, so a refit of it reproduces the fit.
    out = r["network"]
    assert out is not net and [p["even_stretch"] for p in out["patches"]] == [i == TOP for i in range(6)]
    assert_conforming(out)
    again = native.refit(surface, out, even_maps=False)
    assert again["max_deviation"] == pytest.approx(r["max_deviation"], rel=1e-9)
    # report.json's per-patch block says which map each patch has.
    assert [p["even_stretch"] for p in fit_report(r)["per_patch"]] == [i == TOP for i in range(6)]


def test_a_part_that_fits_keeps_harmonic_maps():
    """The gentle bump of test_split_strip (height 1, sigma 0.8) meets the tolerance at
    the default spans: no patch is mapped evenly and the fit is the harmonic one."""
    surface, net = part()
    r = native.refit(surface, net, return_network=True)
    plain = native.refit(surface, net, even_maps=False)
    assert r["tolerance_met"] and r["network"] is net
    assert not any(p["even_stretch"] for p in r["per_patch"])
    assert [p["max_deviation"] for p in r["per_patch"]] == [p["max_deviation"] for p in plain["per_patch"]]


def rippled_box(amplitude=0.5, waves=4):
    """The box [0, 10]^3 with its top rippled: waves x waves sine bumps."""
    def onto(p):
        q = 5.0 + 5.0 * np.asarray(p, float)
        if p[2] > 1 - 1e-12:
            q[2] += amplitude * np.sin(np.pi * waves * q[0] / 10) * np.sin(np.pi * waves * q[1] / 10)
        return q
    return onto


def test_a_miss_an_even_map_cannot_mend_costs_no_refit():
    """A top rippled too finely for 6 spans misses, but its harmonic map already spreads it
    evenly: the even map could lower the miss by its gain to the fourth power at most, far
    from enough, so it is not tried, and the fit is the harmonic one with no other fit."""
    surface, net = part(mapping=rippled_box())
    r = native.refit(surface, net, max_spans=6, split_patches=False)
    assert not r["tolerance_met"] and r["per_patch"][TOP]["max_deviation"] > 2 * r["tolerance"]
    assert not any(p["even_stretch"] for p in r["per_patch"])
    assert "other_fits" not in r["timings_ms"]
