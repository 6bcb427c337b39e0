"""The design tool's hover on screen with the real X pointer (run_hover_gui.py,
a generated torus): each hovered point shows its loop, the latency from the
query to the drawn preview is measured (info "hover_on_screen_ms"), and in a
fast sweep the newest query wins.  The screenshot is copied to
/tmp/stripweave_hover.png for a human to look at."""

import shutil
from pathlib import Path

import pytest

from launch import assert_passed, run_scenario

SCRIPT = Path(__file__).resolve().parent / "run_hover_gui.py"
TIMEOUT = 400


@pytest.fixture(scope="module")
def gui_run(tmp_path_factory):
    run = run_scenario(SCRIPT, tmp_path_factory.mktemp("stripweave_hover"), TIMEOUT, tools=("xdotool",))
    if (run["tmp"] / "hover.png").is_file():
        shutil.copyfile(run["tmp"] / "hover.png", "/tmp/stripweave_hover.png")
    return run


def test_scenario_passes(gui_run):
    assert_passed(gui_run)


def test_hover_latency_is_measured(gui_run):
    figures = gui_run["result"]["info"]["hover_on_screen_ms"]
    assert figures["runs"] >= 10 and figures["median"] > 0 and figures["p95"] >= figures["median"]


def test_newest_query_wins(gui_run):
    checks = {c["name"]: c["ok"] for c in gui_run["result"]["checks"]}
    assert checks["sweep: the preview is the loop through the last point (the newest query wins)"]
    assert gui_run["result"]["info"]["sweep"]["queries"] >= 5
