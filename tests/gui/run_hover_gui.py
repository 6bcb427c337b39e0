"""GUI scenario: the hover of the Design strips tool on screen, with the real
X pointer (xdotool).  Run by tests/gui/test_hover_gui.py under Xvfb on a
generated torus; with STRIPWEAVE_HOVER_MODEL (a STEP or mesh file) and
STRIPWEAVE_HOVER_TRIANGLES it measures that model instead (the figures of
the README: the shipped handle and corpus models).

* Hover: the pointer moves to HOVERS points of the model spread over the
  view (a seeded choice of the screen-grid points that hit it); at each the
  preview must show the best loop through the point under the cursor.
  info "hover_on_screen_ms": median and p95 of the tool's latency (from the
  query the last motion event started to its preview drawn; the tool's
  ``latencies_ms``), and "no_loop" (points where no loop passes).
* Sweep: the pointer crosses SWEEP points without waiting; afterwards the
  preview is the loop through the last point (the newest query wins: no
  older answer is shown last); info "sweep": queries started and previews
  drawn (fewer previews when the answers are slower than the pointer).
Screenshot hover.png.
"""

import os
import statistics
import sys

sys.path.insert(0, os.environ.get("STRIPWEAVE_GUI_TESTS") or os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

import FreeCAD as App  # noqa: E402
import FreeCADGui as Gui  # noqa: E402

import gui_harness as h  # noqa: E402
from gui_harness import check  # noqa: E402

WORKDIR = os.environ.get("STRIPWEAVE_GUI_WORKDIR") or "/tmp"
MODEL = os.environ.get("STRIPWEAVE_HOVER_MODEL")
TRIANGLES = int(os.environ.get("STRIPWEAVE_HOVER_TRIANGLES", "30000" if MODEL else "8000"))
HOVERS = int(os.environ.get("STRIPWEAVE_HOVER_COUNT", "30"))
SWEEP = 10
GRID = (24, 18)


def load_part(doc):
    if not MODEL:
        return h.torus_in_view(doc)
    if MODEL.lower().endswith((".step", ".stp", ".brep", ".iges", ".igs")):
        import Part
        part = doc.addObject("Part::Feature", "Part")
        part.Shape = Part.read(MODEL)
    else:
        import Mesh
        part = doc.addObject("Mesh::Feature", "Part")
        part.Mesh = Mesh.Mesh(MODEL)
    doc.recompute()
    view = Gui.activeDocument().activeView()
    view.viewIsometric()
    view.fitAll()
    h.pump(0.3)
    return part


def model_points(view, tool, count, seed):
    """Screen positions (Coin) of the view grid that hit the model, a seeded choice of ``count``."""
    width, height = view.getSize()
    hits = []
    for i in range(1, GRID[0]):
        for j in range(1, GRID[1]):
            x, y = int(width * i / GRID[0]), int(height * j / GRID[1])
            p = tool.pick(x, y)
            if p is not None:
                hits.append(((x, y), p))
    rng = np.random.default_rng(seed)
    order = rng.permutation(len(hits))[:count]
    return [hits[k] for k in order]


def gap(points, p):
    return float(np.linalg.norm(np.asarray(points, dtype=float) - np.asarray(p), axis=1).min())


def hover_each(view, tool, targets, scale):
    shown, no_loop, misses = [], 0, []
    for (x, y), _p in targets:
        before = len(tool.latencies_ms)
        h.mouse_move(view, x, y)   # two motion events: the second's query is the one that counts
        ok = h.wait_until(lambda: "no compatible" in tool.panel.proposal.text() or (
            tool.worker.idle() and len(tool.latencies_ms) > before and tool.shown_proposal() is not None), 20)
        if "no compatible" in tool.panel.proposal.text():
            no_loop += 1
            continue
        proposal = tool.shown_proposal()
        if not ok or proposal is None:
            misses.append((x, y, ok, tool.panel.proposal.text(), tool.point))
            continue
        shown.append(tool.latencies_ms[-1])
        if gap(proposal["points"], tool.point) > 0.02 * scale:
            misses.append((x, y, "loop off the cursor's point"))
    return shown, no_loop, misses


def sweep(view, tool, targets, scale):
    asked = tool.proposal_serial
    drawn = len(tool.latencies_ms)
    for (x, y), _p in targets:
        gx, gy = h.x11_position(view, x, y)
        h.xdotool("mousemove", gx, gy, settle=0.02)
    last = tool.point
    tool.wait_idle(60)
    h.pump(0.2)
    queries, previews = tool.proposal_serial - asked, len(tool.latencies_ms) - drawn
    h.result["info"]["sweep"] = {"queries": queries, "previews": previews}
    proposal = tool.shown_proposal()
    check("sweep: the preview is the loop through the last point (the newest query wins)",
          proposal is not None and last is not None and gap(proposal["points"], last) <= 0.02 * scale,
          None if proposal is None else gap(proposal["points"], last))


def scenario():
    Gui.activateWorkbench("StripWeaveWorkbench")
    doc = App.newDocument("StripWeaveHover")
    started = h.design_tool_on(doc, load_part(doc), TRIANGLES, derive_timeout=200)
    if started is None:
        return
    view, design, tool = started
    d = design.Proxy.derived(design)
    scale = float(np.linalg.norm(np.ptp(d.vertices, axis=0)))
    h.result["info"]["model"] = os.path.basename(MODEL) if MODEL else "generated torus"
    h.result["info"]["triangles"] = int(len(d.triangles))
    targets = model_points(view, tool, HOVERS + SWEEP, seed=1)
    if not check("enough of the model in view", len(targets) >= SWEEP + 5, len(targets)):
        return
    shown, no_loop, misses = hover_each(view, tool, targets[:-SWEEP], scale)
    if shown:
        h.result["info"]["hover_on_screen_ms"] = {
            "median": statistics.median(shown), "p95": float(np.percentile(shown, 95)), "runs": len(shown),
            "no_loop": no_loop}
    check("hover: every point showed its loop (or said no loop passes)", not misses and shown, misses)
    shot = os.path.join(WORKDIR, "hover.png")
    check("screenshot hover.png", h.save_screenshot(view, shot), shot)
    sweep(view, tool, targets[-SWEEP:], scale)
    tool.close()
    h.pump(0.3)
    errors = h.tracebacks_in_report_view()
    check("no tracebacks in the report view", not errors, errors[:5])


h.run(scenario)
