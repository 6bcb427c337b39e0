"""GUI side of a surface build: worker thread + QTimer poll + progress panel.

Everything here runs on the GUI thread except ``SurfaceJob._run``.  The
document is read when the build starts (a snapshot of the source) and written
when it ends (``on_success``), both on the GUI thread; in between the GUI only
polls the native ``Progress`` object.
"""

import traceback

import FreeCAD as App
from PySide import QtCore, QtGui

from . import messages
from .progress_panel import ProgressTaskPanel, process_events, status_message
from .worker import SourceError, SurfaceJob, snapshot_source

POLL_MS = 100

# key -> BuildController for every build in progress
_active = {}
_quit_hook_installed = False


def _install_quit_hook():
    """Cancel running builds when FreeCAD quits, so no worker thread is
    left inside native code while the interpreter shuts down."""
    global _quit_hook_installed
    if _quit_hook_installed:
        return
    app = QtGui.QApplication.instance()
    if app is not None:
        app.aboutToQuit.connect(cancel_all)
        _quit_hook_installed = True


class BuildController:
    """Builds the Surface of ``source`` and calls ``on_success(controller)``
    (or ``on_failure(controller)``) on the GUI thread when done.

    ``controller.job`` is the :class:`SurfaceJob`: ``job.surface``,
    ``job.error``, ``job.seconds``.
    """

    def __init__(self, key, source, params, title, on_success, on_failure=None):
        self.key = key
        self.doc_name = source.Document.Name
        self.source_name = source.Name
        self.source_label = source.Label
        self.title = title
        self.on_success = on_success
        self.on_failure = on_failure
        self.job = SurfaceJob(snapshot_source(source), label=source.Label, **params)
        self.panel = None
        self.timer = QtCore.QTimer()
        self.timer.setInterval(POLL_MS)
        self.timer.timeout.connect(self._poll)
        self.finished = False
        self._after = None  # an older build of the same key, still stopping

    def start(self):
        """Start the build, or, while an older build of the same key is
        still running, cancel it and start once it has stopped (two builds
        of one source at once would compete for the cores and the result)."""
        previous = _active.get(self.key)
        if previous is not None:
            previous.cancel(quiet=True)
            if not previous.finished:
                self._after = previous
        _active[self.key] = self
        _install_quit_hook()
        if self._after is None:
            self.job.start()
        panel = ProgressTaskPanel(self.title, on_cancel=self.cancel)
        if panel.show():
            self.panel = panel
        else:  # another task dialog is open: progress in the status bar only
            messages.log("task view busy, showing progress in the status bar")
        status_message(self.title)
        self.timer.start()
        return self

    def cancel(self, quiet=False):
        if not self.job.cancelled:
            self.job.cancel()
            if not quiet:
                messages.message("cancelling {} ...".format(self.title))

    def _poll(self):
        try:
            if self._after is not None:
                if not self._after.finished:
                    return
                self._after = None
                if self.job.cancelled:  # cancelled while waiting
                    self._finish()
                    return
                self.job.start()
            if not self.job.done():
                frac, stage = self.job.fraction(), self.job.stage()
                if self.panel is not None:
                    self.panel.update(frac, stage)
                status_message("{}: {} {:.0f}%".format(self.title, stage, 100 * frac))
                return
            self._finish()
        except Exception:  # a bug here must not leave a timer firing forever
            self.timer.stop()
            if _active.get(self.key) is self:
                del _active[self.key]
            messages.error("internal error while finishing the build:\n" + traceback.format_exc())

    def _finish(self):
        self.timer.stop()
        self.finished = True
        if _active.get(self.key) is self:
            del _active[self.key]
        if self.panel is not None:
            self.panel.close()
        status_message("", 1)
        job = self.job
        superseded = _active.get(self.key) is not None
        if job.cancelled or job.is_cancel_error():
            if not superseded:
                messages.message("{}: cancelled".format(self.title))
            return
        if self.doc_name not in App.listDocuments():
            messages.log("document {} closed during the build; result dropped".format(self.doc_name))
            return
        if job.error is not None:
            if job.is_input_error():
                messages.error("cannot prepare '{}': {}".format(self.source_label, job.error_message()))
            else:
                App.Console.PrintLog(job.error_traceback)
                messages.error("building the surface of '{}' failed: {}".format(
                    self.source_label, job.error_message()))
            if self.on_failure is not None:
                self.on_failure(self)
            return
        self.on_success(self)


def start_build(key, source, params, title, on_success, on_failure=None):
    """Start a build; returns the controller, or None after telling the user
    why the source cannot be used."""
    try:
        ctl = BuildController(key, source, params, title, on_success, on_failure)
    except SourceError as exc:
        messages.error(str(exc))
        return None
    except ImportError as exc:
        messages.error(str(exc))
        return None
    return ctl.start()


def _key(obj):
    return (obj.Document.Name, obj.Name)


def schedule_rebuild(obj):
    """Rebuild a SurfaceModel after its parameters or source changed.

    Called from ``execute`` (inside a recompute): the build starts from the
    event loop right after, never inside the recompute.
    """
    doc_name, name = obj.Document.Name, obj.Name
    QtCore.QTimer.singleShot(0, lambda: _rebuild(doc_name, name))


def _rebuild(doc_name, name):
    from .surface_model import is_surface_model
    doc = App.listDocuments().get(doc_name)
    obj = doc.getObject(name) if doc else None
    if obj is None or not is_surface_model(obj):
        return None
    if obj.Source is None:
        return None

    def done(ctl):
        o = _lookup(ctl.doc_name, name)
        if o is None:
            return
        report = o.Proxy.set_surface(o, ctl.job.surface)
        print_report(o, ctl, report)

    def failed(ctl):
        o = _lookup(ctl.doc_name, name)
        if o is not None:
            o.Proxy.clear(o, error=ctl.job.error_message())

    return start_build(_key(obj), obj.Source, obj.Proxy.parameters(obj),
                       "Rebuilding '{}'".format(obj.Label), done, failed)


def rebuild(obj):
    """Public: rebuild a SurfaceModel now (on a worker thread)."""
    return _rebuild(obj.Document.Name, obj.Name)


def _lookup(doc_name, name):
    doc = App.listDocuments().get(doc_name)
    return doc.getObject(name) if doc else None


def print_report(obj, ctl, report):
    from .surface_model import format_report
    messages.message("surface model '{}' of '{}' ready in {:.1f} s\n{}".format(
        obj.Label, ctl.source_label, ctl.job.seconds, format_report(report)))


def cancel_for(obj):
    ctl = _active.get(_key(obj))
    if ctl is not None:
        ctl.cancel()


def running_for(key):
    """The build in progress under ``key``, or None."""
    return _active.get(key)


def cancel_all():
    for ctl in list(_active.values()):
        ctl.cancel(quiet=True)
    for ctl in list(_active.values()):
        ctl.job.join(2.0)


def active_builds():
    return list(_active.values())


def wait_for_builds(timeout=120.0):
    """Process GUI events until no build is running (for tests and macros).
    Returns True if all finished within ``timeout`` seconds."""
    import time
    end = time.monotonic() + timeout
    while _active:
        if time.monotonic() > end:
            return False
        process_events()
        time.sleep(0.02)
    process_events()
    return True
