"""The fuzz harness's short run (issue 23), part of the suite: tests/fuzz/run.sh for 60 s per
target (STRIPWEAVE_FUZZ_SECONDS overrides), from the seed corpus in a fresh work folder, at most 60 s
per input. libFuzzer (clang, ASan, UBSan) on the native mesh readers; the mutation fuzzer on the
design parser. Any crash, sanitizer report, other exception or hang fails the run (non-zero exit).
The long run (3600 s per target) is the same command; README "What happens to bad input"."""
import os
import subprocess

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SECONDS = int(os.environ.get("STRIPWEAVE_FUZZ_SECONDS", "60"))


@pytest.mark.parametrize("target", ["mesh", "design"])
def test_short_fuzz_run_finds_nothing(tmp_path, target):
    env = {**os.environ, "FUZZ_OUT": str(tmp_path), "FUZZ_TIMEOUT": "60"}
    r = subprocess.run(["bash", os.path.join(REPO, "tests", "fuzz", "run.sh"), str(SECONDS), target], cwd=REPO,
                       env=env, capture_output=True, text=True, timeout=SECONDS + 900)
    assert r.returncode == 0, (r.stdout + r.stderr)[-4000:]
    if target == "mesh":
        executed = [line for line in r.stderr.splitlines() if line.startswith("stat::number_of_executed_units")]
        assert executed and int(executed[0].split()[-1]) > 0
        assert not [f for f in os.listdir(tmp_path) if f.startswith(("crash-", "timeout-", "oom-", "leak-"))]
    else:
        assert ", 0 findings" in r.stdout
