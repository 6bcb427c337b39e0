"""Design feedback (issue 20 item 4, workbench/freecad/stripweave_wb/feedback.py): an empty
strip, a sliver strip (narrower on average than two solver edges: no vertex inside it across)
and fold-overs a change added are warned about; a healthy strip on a generated torus is not."""
import importlib.util
import os

import pytest

import stripweave as sw
from models import torus
from stripweave.design import Design
from stripweave.strips import DesignSession

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_spec = importlib.util.spec_from_file_location(
    "feedback", os.path.join(REPO, "workbench", "freecad", "stripweave_wb", "feedback.py"))
feedback = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(feedback)


@pytest.fixture(scope="module")
def meridian():
    surface = sw.from_shape(torus(10, 3), target_triangles=4000)
    design = Design()
    design.add_strip([(13, 0, 0, 0, 0, 1)])
    ds = DesignSession(surface, design)
    s = ds.strip(0)
    summary = {"strips": [{"length": s["length"], "area_fraction": s["area_fraction"]}],
               "fold_overs": int(ds.native.fold_overs)}
    return summary, feedback.mesh_scale(surface.vertices, surface.triangles)


def test_a_full_strip_gives_no_warning(meridian):
    summary, (area, edge) = meridian
    assert area == pytest.approx(4 * 3.14159265 ** 2 * 10 * 3, rel=0.02)
    assert feedback.strip_warnings(summary, area, edge, summary["fold_overs"]) == []


def test_empty_and_sliver_strips_are_named(meridian):
    summary, (area, edge) = meridian
    length = summary["strips"][0]["length"]
    sliver = 1.5 * edge * length / area          # 1.5 solver edges wide on average
    wide = 2.5 * edge * length / area
    strips = [{"length": length, "area_fraction": 0.0}, {"length": length, "area_fraction": sliver},
              {"length": length, "area_fraction": wide}]
    warnings = feedback.strip_warnings({"strips": strips, "fold_overs": 0}, area, edge)
    assert len(warnings) == 2
    assert warnings[0].startswith("strip 1 is empty")
    assert warnings[1].startswith("strip 2 is a sliver")


def test_fold_overs_that_rose_are_warned_once(meridian):
    summary, (area, edge) = meridian
    risen = dict(summary, fold_overs=summary["fold_overs"] + 19)
    warnings = feedback.strip_warnings(risen, area, edge, summary["fold_overs"])
    assert len(warnings) == 1 and "fold-overs rose" in warnings[0]
    assert feedback.strip_warnings(risen, area, edge, risen["fold_overs"]) == []
    assert feedback.strip_warnings(risen, area, edge, None) == []
