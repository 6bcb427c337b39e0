"""Deriving a Design in the background (GUI only).

When a document is reopened, or the SurfaceModel is being rebuilt, a Design
has no DesignSession yet.  :func:`request` gets one without freezing the GUI:
it waits for the SurfaceModel's surface (starting its rebuild on a worker
thread, with the usual progress panel, when nobody else has), then builds or
updates the session on a worker thread (the native code releases the GIL),
and finally calls back on the GUI thread.  The document is only read and
written on the GUI thread, from a QTimer poll.
"""

import threading
import traceback

import FreeCAD as App
from PySide import QtCore

from . import messages

POLL_MS = 50

# (document name, object name) -> _Job, one per Design being derived
_jobs = {}


def _lookup(doc_name, name):
    doc = App.listDocuments().get(doc_name)
    return doc.getObject(name) if doc else None


def _surface_build_running(sm):
    from . import builder
    key = (sm.Document.Name, sm.Name)
    return any(ctl.key == key for ctl in builder.active_builds())


class _Job:
    def __init__(self, obj):
        self.doc_name, self.name, self.label = obj.Document.Name, obj.Name, obj.Label
        self.callbacks = []
        self.then_recompute = False
        self.started_surface_build = False
        self.thread = None
        self.error = None
        self.timer = QtCore.QTimer()
        self.timer.setInterval(POLL_MS)
        self.timer.timeout.connect(self._poll)

    def _stop(self, obj):
        self.timer.stop()
        _jobs.pop((self.doc_name, self.name), None)
        for cb in self.callbacks:
            try:
                cb(obj, self.error)
            except Exception:
                messages.error("internal error after deriving '{}':\n{}".format(
                    self.label, traceback.format_exc()), dialog=False)
        if obj is not None and self.error is None:
            if self.then_recompute:
                obj.touch()
                obj.Document.recompute()
            else:
                obj.Proxy.refresh_outputs(obj)  # Status and StripCount as derived now

    def _poll(self):
        try:
            self._step()
        except Exception:
            self.error = traceback.format_exc().strip().splitlines()[-1]
            messages.error("deriving '{}' failed: {}".format(self.label, self.error), dialog=False)
            self._stop(_lookup(self.doc_name, self.name))

    def _step(self):
        obj = _lookup(self.doc_name, self.name)
        if obj is None:
            self._stop(None)
            return
        if self.thread is not None:
            if self.thread.is_alive():
                return
            self.thread = None
            if self.error is None and obj.Proxy.derived(obj) is None:
                return  # the design changed meanwhile: derive again on the next tick
            self._stop(obj)
            return
        proxy, sm = obj.Proxy, obj.Surface
        surface = proxy.surface_if_ready(obj)
        if surface is None:
            if sm is None:
                self.error = "no SurfaceModel linked"
                self._stop(obj)
            elif _surface_build_running(sm):
                pass
            elif not self.started_surface_build:
                from . import builder
                self.started_surface_build = True
                if builder.rebuild(sm) is None:
                    self.error = "the surface model '{}' cannot be built".format(sm.Label)
                    self._stop(obj)
            else:  # our build ended without a surface (failed or cancelled)
                self.error = "the surface model '{}' is not available".format(sm.Label)
                self._stop(obj)
            return
        # read the document here, on the GUI thread; derive on a worker
        design, features, cache = proxy.design(obj), bool(obj.Features), proxy.cache()

        def run():
            try:
                cache.sync(surface, design, features)
            except Exception as exc:
                self.error = "{}: {}".format(type(exc).__name__, exc)
        self.thread = threading.Thread(target=run, name="StripWeave design derivation", daemon=True)
        self.thread.start()


def request(obj, callback=None, then_recompute=False):
    """Derive ``obj`` in the background; ``callback(obj, error)`` runs on the
    GUI thread when done (error is None or a one-line text).  With
    ``then_recompute`` the Design is recomputed afterwards (to publish)."""
    key = (obj.Document.Name, obj.Name)
    job = _jobs.get(key)
    if job is None:
        job = _jobs[key] = _Job(obj)
        job.timer.start()
    if callback is not None:
        job.callbacks.append(callback)
    job.then_recompute = job.then_recompute or then_recompute
    return job


def pending(obj=None):
    """True while ``obj`` (or any Design, without argument) is being derived."""
    if obj is None:
        return bool(_jobs)
    return (obj.Document.Name, obj.Name) in _jobs
