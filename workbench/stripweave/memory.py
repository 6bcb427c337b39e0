"""The memory of the main job's stages (issue 22): what each stage holds and what it needs.

    meter = StageMemory()          # at the start of the job
    ...                            # a stage's work
    meter.note("graph")            # {"rss", "peak"} (and "stage_peak", see below), MB
    meter.stages                   # {stage: {...}} in order: report.json's memory_mb

rss is the resident memory after the stage, once the heap's free pages went back to the
system (release_freed_memory): what the stage keeps for later ones. peak is the process's
peak so far. With stage peaks (STRIPWEAVE_STAGE_PEAKS=1 in the environment, or
stage_peaks=True; `stripweave bench --job` asks for them), "stage_peak" is the peak within
the stage alone: Linux's high-water mark is reset after each note (/proc/self/clear_refs),
so the step from the previous stage's rss to this stage_peak is what the stage needed
while it ran. Off by default: the reset also lowers the peak that the process's parent
sees at its exit (ru_maxrss of wait4, which `batch` and /usr/bin/time report), so with
stage peaks only "peak" here is the process's true peak.
"""
import os
import resource

STAGE_PEAKS_ENV = "STRIPWEAVE_STAGE_PEAKS"


def peak_memory_mb():
    """Peak resident memory of this process image, in MB: what the weave needed at its
    heaviest. Linux's VmHWM, which starts afresh at exec; getrusage's ru_maxrss (the fallback
    without /proc) does not: RUSAGE_SELF keeps the high-water mark of the image before exec
    (a fork of a large parent: the test suite's 845 MB) and RUSAGE_CHILDREN that of every
    child the process waited for before it (the README's first command: `.ci/setup`'s
    compiler, 1.2 GB, became the handle's peak). The job starts no child of its own."""
    hwm = _high_water_mb()
    if hwm is not None:
        return hwm
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1)


def resident_memory_mb():
    """This process's resident memory now, in MB (Linux /proc; 0 where there is none)."""
    try:
        with open("/proc/self/statm") as f:
            pages = int(f.read().split()[1])
    except (OSError, ValueError, IndexError):
        return 0.0
    return round(pages * os.sysconf("SC_PAGE_SIZE") / 2**20, 1)


def release_freed_memory(first=False):
    """Hand the heap's free pages back to the system (glibc malloc_trim), so a stage's peak
    does not stack on what earlier stages freed but malloc kept. `first`: also fix glibc's
    mmap threshold at 1 MB: by default it grows to 32 MB after the first large free, and
    every later large array (graph, factor, images) then comes from a heap that never
    shrinks. Results do not change; elsewhere than glibc this does nothing."""
    try:
        import ctypes
        libc = ctypes.CDLL("libc.so.6")
        if first:
            libc.mallopt(-3, 1 << 20)   # M_MMAP_THRESHOLD
        libc.malloc_trim(0)
    except (OSError, AttributeError):
        pass


def _high_water_mb():
    """The resident high-water mark since the last reset (VmHWM), MB; None without /proc."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return round(int(line.split()[1]) / 1024.0, 1)
    except (OSError, ValueError, IndexError):
        pass
    return None


def _reset_high_water():
    """Reset VmHWM to the resident memory now (Linux 4.0+); False where that is not possible."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


class StageMemory:
    """Resident memory after each stage of a job, and its peaks (the module doc)."""

    def __init__(self, stage_peaks=None):
        if stage_peaks is None:
            stage_peaks = os.environ.get(STAGE_PEAKS_ENV, "") not in ("", "0")
        self.stages = {}
        release_freed_memory(first=True)
        self.peak = peak_memory_mb()      # before the first reset: the process's peak so far
        self.stage_peaks = bool(stage_peaks) and _high_water_mb() is not None and _reset_high_water()

    def note(self, stage):
        """Record the stage that just ended (a stage noted twice keeps its larger figures)."""
        entry = {}
        if self.stage_peaks:
            entry["stage_peak"] = _high_water_mb()
            self.peak = max(self.peak, entry["stage_peak"])
        else:
            self.peak = peak_memory_mb()
        release_freed_memory()
        entry = {"rss": resident_memory_mb(), "peak": self.peak, **entry}
        if self.stage_peaks:
            _reset_high_water()
        old = self.stages.get(stage)
        if old is not None:
            entry = {k: max(v, old.get(k, v)) for k, v in entry.items()}
        self.stages[stage] = entry
        return entry

    def peak_mb(self):
        """The process's peak so far (with stage peaks, including the stage under way)."""
        if self.stage_peaks:
            return max(self.peak, _high_water_mb() or 0.0)
        return peak_memory_mb()
