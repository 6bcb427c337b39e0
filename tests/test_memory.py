"""The job's memory figures (memory.py, issue 22): they are this process's own."""
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_peak_is_the_process_own_not_an_earlier_child_of_its_shell():
    """A shell that waited for a 400 MB child and then exec'd the job (what `.ci/setup &&
    build/stripweave ...` does in a subshell) must not hand that child's peak to the job, nor
    may a job forked from a large parent (here 300 MB of ballast) report the parent's:
    getrusage's ru_maxrss carries both over exec, VmHWM neither."""
    ballast = bytearray(300 << 20)
    ballast[::4096] = b"x" * len(ballast[::4096])
    big = f"{sys.executable} -c 'b = bytearray(400 << 20); b[::4096] = b\"x\" * len(b[::4096])'"
    job = (f"exec {sys.executable} -c 'import sys; sys.path.insert(0, \"{REPO}/workbench\"); "
           "from stripweave.memory import peak_memory_mb; print(peak_memory_mb())'")
    out = subprocess.run(["bash", "-c", f"{big} && {job}"], capture_output=True, text=True, check=True)
    peak = float(out.stdout.strip())
    assert 0 < peak < 200, peak
    del ballast
