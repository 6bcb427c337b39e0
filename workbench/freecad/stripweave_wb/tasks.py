"""Background work of the main-job commands (Auto weave, Show layout, Fit
patches, Export STEP): a Python function on a worker thread, a progress
panel with a working Cancel, and the document written on the GUI thread.

    task = tasks.start(key, "Auto weave of 'Design'", work, on_done, cancel_hooks=[session.cancel])
    tasks.wait_for_tasks()            # tests and macros

``work(task)`` runs on the worker thread and never touches the document: it
reads what the GUI thread copied for it, reports with ``task.report(fraction,
stage)`` and checks ``task.cancelled`` (a threading.Event) between steps.
The native calls it makes release the GIL, so the GUI stays live.  Cancel
sets the event and calls the ``cancel_hooks`` (e.g. the loop engine's
``cancel()``, which stops a running loop query at once); the panel then says
"cancelling" until the thread has really stopped, and ``on_done`` is not
called.  ``on_done(result)`` runs on the GUI thread and writes the document,
normally as one transaction.  Without the GUI (``freecadcmd``) :func:`run_here`
runs the same work on the calling thread.

One task per key at a time: starting a task whose key is running returns
the running one (the user clicked twice).
"""

import threading
import time
import traceback

import FreeCAD as App

from . import messages

POLL_MS = 100

# key -> Task for every task in progress
_active = {}


class Task:
    """One piece of background work; see the module doc."""

    def __init__(self, key, title, work, on_done=None, cancel_hooks=(), on_failure=None):
        self.key = key
        self.title = title
        self.work = work
        self.on_done = on_done
        self.on_failure = on_failure
        self.cancel_hooks = list(cancel_hooks)
        self.cancelled = threading.Event()
        self.fraction = 0.0
        self.stage = "starting"
        self.result = None
        self.error = None
        self.error_traceback = ""
        self.started_at = None
        self.seconds = 0.0
        self.cancel_requested_at = None
        self.stopped_at = None
        self.finished = False
        self.panel = None
        self.timer = None
        self.progress_fn = None   # optional: () -> (fraction, stage), polled on the GUI thread
        self._thread = threading.Thread(target=self._run, name="StripWeave " + title, daemon=True)

    # -- worker side -------------------------------------------------------------
    def report(self, fraction, stage):
        self.fraction = max(0.0, min(1.0, float(fraction)))
        self.stage = str(stage)

    def _run(self):
        try:
            self.result = self.work(self)
        except BaseException as exc:  # reported on the GUI thread
            self.error = exc
            self.error_traceback = traceback.format_exc()
        finally:
            self.stopped_at = time.monotonic()
            self.seconds = self.stopped_at - self.started_at

    # -- either side ---------------------------------------------------------------
    def cancel(self):
        if self.cancelled.is_set():
            return
        self.cancel_requested_at = time.monotonic()
        self.cancelled.set()
        for hook in self.cancel_hooks:
            try:
                hook()
            except Exception:
                pass

    def done(self):
        return self.started_at is not None and not self._thread.is_alive()

    def join(self, timeout=None):
        if self._thread.is_alive():
            self._thread.join(timeout)
        return self.done()

    def cancel_seconds(self):
        """How long the work ran on after Cancel (None if not cancelled or still running)."""
        if self.cancel_requested_at is None or self.stopped_at is None:
            return None
        return max(0.0, self.stopped_at - self.cancel_requested_at)

    def was_cancelled(self):
        if self.cancelled.is_set():
            return True
        from . import import_stripweave
        return isinstance(self.error, import_stripweave().Cancelled)

    def error_message(self):
        from . import import_stripweave
        if self.error is None:
            return ""
        if isinstance(self.error, import_stripweave().InputError):
            return str(self.error)
        return "{}: {}".format(type(self.error).__name__, self.error)

    # -- GUI side -------------------------------------------------------------------
    def start(self):
        from PySide import QtCore
        from .progress_panel import ProgressTaskPanel, status_message
        _active[self.key] = self
        self.started_at = time.monotonic()
        self._thread.start()
        panel = ProgressTaskPanel(self.title, on_cancel=self.cancel)
        if panel.show():
            self.panel = panel
        else:
            messages.log("task view busy, showing progress in the status bar")
        status_message(self.title)
        self.timer = QtCore.QTimer()
        self.timer.setInterval(POLL_MS)
        self.timer.timeout.connect(self._poll)
        self.timer.start()
        return self

    def _poll(self):
        from .progress_panel import status_message
        try:
            if not self.done():
                if self.progress_fn is not None:
                    try:
                        self.fraction, self.stage = self.progress_fn()
                    except Exception:
                        pass
                if self.panel is not None:
                    self.panel.update(self.fraction, self.stage)
                status_message("{}: {} {:.0f}%".format(self.title, self.stage, 100 * self.fraction))
                return
            self._finish()
        except Exception:  # a bug here must not leave a timer firing forever
            self.timer.stop()
            _active.pop(self.key, None)
            messages.error("internal error after {}:\n{}".format(self.title, traceback.format_exc()))

    def _finish(self):
        from .progress_panel import status_message
        self.timer.stop()
        self.finished = True
        if _active.get(self.key) is self:
            del _active[self.key]
        if self.panel is not None:
            self.panel.close()
        status_message("", 1)
        self._deliver()

    def _deliver(self):
        if self.was_cancelled():
            messages.message("{}: cancelled ({:.2f} s after Cancel)".format(
                self.title, self.cancel_seconds() or 0.0))
            if self.on_failure is not None:
                self.on_failure(self)
            return
        if self.error is not None:
            App.Console.PrintLog(self.error_traceback)
            messages.error("{} failed: {}".format(self.title, self.error_message()))
            if self.on_failure is not None:
                self.on_failure(self)
            return
        if self.on_done is not None:
            try:
                self.on_done(self.result)
            except Exception:
                App.Console.PrintLog(traceback.format_exc())
                messages.error("{} failed while writing the document: {}".format(
                    self.title, traceback.format_exc().strip().splitlines()[-1]))

    def run_here(self):
        """Run on the calling thread, then deliver (headless use)."""
        self.started_at = time.monotonic()
        self._run()
        self.finished = True
        self._deliver()
        return self


def start(key, title, work, on_done=None, cancel_hooks=(), on_failure=None):
    """Start ``work`` in the background (GUI) or run it now (no GUI); returns
    the Task (``on_failure(task)`` also runs after a Cancel: ``task.was_cancelled()``).  A task of the same key still running is returned instead."""
    running = _active.get(key)
    if running is not None and not running.cancelled.is_set():
        messages.message("{} is running already".format(running.title))
        return running
    task = Task(key, title, work, on_done, cancel_hooks, on_failure)
    if not App.GuiUp:
        return task.run_here()
    return task.start()


def running(key=None):
    """The tasks in progress (of ``key`` only, when given)."""
    return [t for k, t in _active.items() if key is None or k == key]


def cancel_all():
    for t in list(_active.values()):
        t.cancel()


def wait_for_tasks(timeout=300.0):
    """Process GUI events until no task is running (tests and macros).
    True if all finished within ``timeout`` seconds."""
    from .progress_panel import process_events
    end = time.monotonic() + timeout
    while _active:
        if time.monotonic() > end:
            return False
        process_events()
        time.sleep(0.02)
    process_events()
    return True
