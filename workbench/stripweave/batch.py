"""`stripweave batch`: the main job over many models, one process per model (issue 16).

    stripweave batch MODEL_OR_DIR... --out OUT [--step] [--jobs N] [--time-limit S]
                     [--memory-limit MB] [--scheduler ADDRESS] [weave options]

    from stripweave.batch import run_batch
    summary = run_batch(["models/"], "corpus", step=True, jobs=2)

Inputs   model files, and folders searched recursively for MODEL_SUFFIXES (any case);
         a file named on the command line is taken whatever its suffix.
Outputs  OUT/<name>/      the weave outputs of one model, weave.log (its stderr) and
                          weave.json (its --json output: report.json's content and "paths",
                          "stopped" (why weaving ended), "work")
         OUT/summary.json {"format": "stripweave-batch", "version": 1, "models": [entry]},
                          entry {"model", "status", "error", "time_s", "peak_memory_mb",
                          "report", "out"} (design.md; "out" names OUT/<name>)
         OUT/summary.md, OUT/index.html (batch_report.py)
         all three rewritten after every model, so a killed batch leaves what it had.

Each model runs `stripweave weave MODEL --auto --out OUT/<name> --json [--step] [...]` as
a subprocess in its own process group: a crash (segfault, abort, out of memory) takes
down that model alone. Its status:
    ok       exit 0 and a report.json
    error    exit 1: its one-line error; or over the memory limit (killed), the limit named
    timeout  over the time limit: the whole process group killed
    crash    killed by a signal it did not get from us: the signal's name
The jobs run in a local pool of `jobs` at once, or, with `scheduler`, as tasks of a Dask
distributed cluster: a worker runs the same subprocess with the same limits. Workers
must see the models, OUT and the launcher at the same paths (a shared file system); the
job code is shipped to them by value, so they need only Python with distributed and psutil.
"""
import concurrent.futures
import json
import os
import signal
import subprocess
import sys
import threading
import time

import psutil

from .batch_report import format_progress, write_summary

MODEL_SUFFIXES = (".step", ".stp", ".iges", ".igs", ".brep", ".brp", ".stl", ".obj", ".off", ".ply", ".fcstd")
POLL_S = 0.1                     # how often a running job's time and memory are checked
WEAVE_OUTPUTS = ("design.json", "layout.json", "report.json", "preview.png", "deviation.png", "patches.step",
                 "weave.json")


# --- which models, and where their outputs go ------------------------------------------

def find_models(inputs):
    """The model files of `inputs` (files and folders), in order, each once. A missing
    input is an InputError (before anything runs)."""
    from ._native import native
    found, seen = [], set()
    for item in inputs:
        if os.path.isdir(item):
            paths = [os.path.join(root, name) for root, dirs, names in os.walk(item)
                     for name in names if not name.startswith(".") and name.lower().endswith(MODEL_SUFFIXES)]
            paths.sort()
        elif os.path.isfile(item):
            paths = [item]
        else:
            raise native.InputError(f"batch input {item} is neither a model file nor a folder")
        for p in paths:
            if os.path.realpath(p) not in seen:
                seen.add(os.path.realpath(p))
                found.append(p)
    if not found:
        raise native.InputError(f"no model files ({', '.join(MODEL_SUFFIXES)}) in {' '.join(inputs)}")
    return found


def output_names(models):
    """A folder name per model, unique: its file name without the suffix; where two
    collide, the file name with its suffix, then prefixed by as many parent folders as it
    takes (a/torus.obj and b/torus.obj -> a_torus_obj, b_torus_obj); the model's index
    settles what still collides."""
    parts = [os.path.abspath(m).split(os.sep) for m in models]
    depth = [0] * len(models)

    def name(i):
        stem, suffix = os.path.splitext(parts[i][-1])
        if depth[i] == 0:
            return stem
        return "_".join([p for p in parts[i][len(parts[i]) - depth[i]:-1] if p] + [stem + suffix.replace(".", "_")])

    while True:
        names = [name(i) for i in range(len(models))]
        clashing = [i for i, n in enumerate(names) if names.count(n) > 1]
        if not clashing:
            return names
        deepened = False
        for i in clashing:
            if depth[i] < len(parts[i]):
                depth[i] += 1
                deepened = True
        if not deepened:
            return [f"{n}_{i}" if i in clashing else n for i, n in enumerate(names)]


def launcher_command():
    """(argv prefix, environment) that runs the `stripweave` CLI: the build's launcher next
    to the native module, else this Python with this process's module path."""
    from ._native import native
    launcher = os.path.join(os.path.dirname(os.path.abspath(native.__file__)), "stripweave")
    env = dict(os.environ)
    if os.access(launcher, os.X_OK):
        env.pop("PYTHONPATH", None)   # the launcher sets its own
        return [launcher], env
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    return [sys.executable, "-m", "stripweave.cli"], env


# --- one model's job (runs in this process or on a Dask worker: stdlib and psutil only) --

def run_job(job, running=None):
    """Run one model's weave subprocess under its limits; returns its summary entry.
    job: {"model", "out" (its folder), "argv", "env", "time_limit_s", "memory_limit_mb"}
    (limits: 0 or None for none). running: a _Running that tracks the job's process group
    (the local pool kills them on an interrupt), or None."""
    os.makedirs(job["out"], exist_ok=True)
    for name in WEAVE_OUTPUTS:    # a stale report must not pass for this run's
        try:
            os.remove(os.path.join(job["out"], name))
        except FileNotFoundError:
            pass
    start = time.monotonic()
    stdout_path = os.path.join(job["out"], "weave.stdout")
    with open(os.path.join(job["out"], "weave.log"), "w", encoding="utf-8") as log, \
            open(stdout_path, "w", encoding="utf-8") as stdout:
        proc = subprocess.Popen(job["argv"], stdout=stdout, stderr=log, stdin=subprocess.DEVNULL,
                                env=job["env"], start_new_session=True)
        if running is not None:
            running.add(proc.pid)
        try:
            killed, status, rusage, sampled_mb = _watch(proc, start, job)
        finally:
            _kill_group(proc.pid)     # strays of the job, if any
            if running is not None:
                running.discard(proc.pid)
    elapsed = time.monotonic() - start
    _split_stdout(stdout_path, job["out"])
    peak = max(sampled_mb, rusage.ru_maxrss / 1024.0)   # ru_maxrss: kB, the exact peak of the process
    state, error = _status(killed, os.waitstatus_to_exitcode(status), job, os.path.join(job["out"], "weave.log"))
    report = _read_report(job["out"])
    if state == "ok" and report is None:
        state, error = "error", "the job wrote no report.json"
    return {"model": job["model"], "status": state, "error": error, "time_s": round(elapsed, 2),
            "peak_memory_mb": round(peak, 1), "report": report}


def _split_stdout(stdout_path, folder):
    """weave --json prints one line of JSON; libraries may print more (OCCT's STEP writer
    does, for mesh inputs). The JSON line goes to weave.json, the rest to weave.log."""
    with open(stdout_path, encoding="utf-8", errors="replace") as f:
        lines = f.read().splitlines()
    os.remove(stdout_path)
    printed = [line for line in lines if line.startswith("{")]
    if printed:
        with open(os.path.join(folder, "weave.json"), "w", encoding="utf-8") as f:
            f.write(printed[-1] + "\n")
    rest = [line for line in lines if not line.startswith("{")]
    if rest:
        with open(os.path.join(folder, "weave.log"), "a", encoding="utf-8") as f:
            f.write("".join(f"{line}\n" for line in rest))


def _watch(proc, start, job):
    """Wait for the job, killing its process group when over a limit. Returns (why it was
    killed: None | "time" | ("memory", MB), wait status, rusage, peak sampled RSS in MB)."""
    time_limit = job.get("time_limit_s") or 0
    memory_limit = job.get("memory_limit_mb") or 0
    killed, sampled = None, 0.0
    while True:
        pid, status, rusage = os.wait4(proc.pid, os.WNOHANG)
        if pid == proc.pid:
            proc.returncode = os.waitstatus_to_exitcode(status)   # reaped here, not by Popen
            return killed, status, rusage, sampled
        if killed is None:
            rss = _tree_rss_mb(proc.pid)
            sampled = max(sampled, rss)
            if time_limit and time.monotonic() - start > time_limit:
                killed = "time"
            elif memory_limit and rss > memory_limit:
                killed = ("memory", rss)
            if killed is not None:
                _kill_group(proc.pid)
        time.sleep(POLL_S)


def _tree_rss_mb(pid):
    """Resident memory of a process and its descendants, in MB (0 once it is gone)."""
    try:
        root = psutil.Process(pid)
        procs = [root] + root.children(recursive=True)
    except psutil.NoSuchProcess:
        return 0.0
    total = 0
    for p in procs:
        try:
            total += p.memory_info().rss
        except psutil.NoSuchProcess:
            pass
    return total / (1024.0 * 1024.0)


def _kill_group(pgid):
    try:
        os.killpg(pgid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _status(killed, code, job, log_path):
    """(status, error text or None) of a finished job."""
    if killed == "time":
        return "timeout", f"time limit of {job['time_limit_s']:g} s exceeded"
    if isinstance(killed, tuple):
        return "error", (f"memory limit of {job['memory_limit_mb']:g} MB exceeded "
                         f"({killed[1]:.0f} MB resident when killed)")
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return "crash", f"killed by {name}"
    if code == 0:
        return "ok", None
    line = _last_error_line(log_path)
    return "error", line if code == 1 else f"exit status {code}: {line}"


def _last_error_line(log_path):
    """The job's one-line error: the last `stripweave: ...` line of its stderr, else its
    last line (a traceback's ends with the exception)."""
    try:
        with open(log_path, encoding="utf-8", errors="replace") as f:
            lines = [line.strip() for line in f if line.strip()]
    except OSError:
        lines = []
    for line in reversed(lines):
        if line.startswith("stripweave: "):
            return line[len("stripweave: "):].removeprefix("error: ")
    return lines[-1] if lines else "failed without a message"


def _read_report(folder):
    try:
        with open(os.path.join(folder, "report.json"), encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


# --- the batch ------------------------------------------------------------------------------

def run_batch(inputs, out, step=False, jobs=1, time_limit_s=600.0, memory_limit_mb=0.0, scheduler=None,
              weave_args=(), command=None, progress=sys.stderr):
    """Weave every model of `inputs` into OUT/<name>; returns summary.json's content.
    weave_args  extra `weave` options, e.g. ["--target-triangles", "3000"]
    command     (argv prefix, environment) of the CLI (default launcher_command())
    scheduler   a Dask scheduler address: the jobs run on its workers (jobs is then unused)
    progress    a text stream for one line per finished model (None: quiet)"""
    from ._native import native
    if jobs < 1:
        raise native.InputError(f"--jobs must be at least 1, got {jobs}")
    models = find_models(inputs)
    names = output_names(models)
    prefix, env = command or launcher_command()
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    specs = [{"model": m, "out": os.path.join(out, n), "time_limit_s": time_limit_s,
              "memory_limit_mb": memory_limit_mb, "env": env,
              "argv": [*prefix, "weave", os.path.abspath(m), "--auto", "--out", os.path.join(out, n), "--json",
                       *(["--step"] if step else []), *weave_args]}
             for m, n in zip(models, names)]
    entries = [None] * len(specs)

    def done(i, entry):
        entries[i] = {**entry, "out": names[i]}
        finished = [e for e in entries if e is not None]
        write_summary(out, finished)
        if progress is not None:
            print(format_progress(len(finished), len(entries), entries[i]), file=progress, flush=True)

    write_summary(out, [])
    with _stopped_by_signals():
        if scheduler:
            _run_on_dask(specs, scheduler, done)
        else:
            _run_locally(specs, jobs, done)
    return {"format": "stripweave-batch", "version": 1, "models": entries}


class _stopped_by_signals:
    """While a batch runs, SIGTERM and SIGHUP stop it as Ctrl-C does (an exception, so the
    running jobs are killed): its jobs have process groups of their own, and would outlive
    a batch that died at once. Only in the main thread, where Python takes signals."""

    SIGNALS = (signal.SIGTERM, signal.SIGHUP)

    def __enter__(self):
        self.saved = {}
        if threading.current_thread() is threading.main_thread():
            for s in self.SIGNALS:
                self.saved[s] = signal.signal(s, self._raise)
        return self

    @staticmethod
    def _raise(number, frame):
        raise SystemExit(128 + number)

    def __exit__(self, *exc):
        for s, handler in self.saved.items():
            signal.signal(s, handler)
        return False


class _Running:
    """The process groups of the jobs running in this process (thread-safe)."""

    def __init__(self):
        self._groups, self._lock = set(), threading.Lock()

    def add(self, pgid):
        with self._lock:
            self._groups.add(pgid)

    def discard(self, pgid):
        with self._lock:
            self._groups.discard(pgid)

    def kill_all(self):
        with self._lock:
            for pgid in self._groups:
                _kill_group(pgid)


def _run_locally(specs, jobs, done):
    """`jobs` models at a time, each a subprocess watched by a thread of this process.
    An interrupt (Ctrl-C) kills the running jobs: they are in process groups of their own,
    so the terminal's signal does not reach them."""
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=jobs)
    running = _Running()
    try:
        futures = {pool.submit(run_job, spec, running): i for i, spec in enumerate(specs)}
        for future in concurrent.futures.as_completed(futures):
            done(futures[future], future.result())
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        running.kill_all()
        raise
    pool.shutdown()


def _run_on_dask(specs, address, done):
    """The same jobs as tasks of the Dask cluster at `address`; a task that fails (its
    worker lost, say) is recorded as an error and the batch goes on."""
    import cloudpickle
    from distributed import Client, as_completed
    from ._native import native
    cloudpickle.register_pickle_by_value(sys.modules[__name__])   # workers need not import stripweave
    try:
        client = Client(address, timeout=30)
    except OSError as exc:
        raise native.InputError(f"cannot reach the Dask scheduler at {address}: {exc}") from None
    try:
        futures = {client.submit(run_job, spec, pure=False): i for i, spec in enumerate(specs)}
        for future in as_completed(futures):
            i = futures[future]
            try:
                entry = future.result()
            except Exception as exc:   # the task, not the model, failed: record it, go on
                entry = {"model": specs[i]["model"], "status": "error", "error": f"Dask task failed: {exc}",
                         "time_s": None, "peak_memory_mb": None, "report": None}
            done(i, entry)
    finally:
        client.close()
