"""What the Layout and Patches document objects share: a result computed
from a Design's derived state (on a worker thread with the GUI up,
synchronously without it), kept on the proxy under the key of what it was
computed from, and published to the object's properties by ``execute``.

A subclass sets ``TYPE_NAME``, ``TITLE`` and implements::

    design_of(obj)            the Design object the result is computed from (or None)
    parameters(obj)           what besides the design the result depends on (JSON-able)
    compute(ds, params, task) on the worker: the result from the DesignSession ``ds``
    publish(obj, result)      on the GUI thread: write the output properties
    clear(obj, status)        no result: empty outputs and a one-line Status

``execute`` (a recompute) publishes the kept result when its key is current;
otherwise, with the GUI up, it starts the computation in the background
(tasks.py: progress, Cancel) and recomputes the object when it is done; with
no GUI it computes at once.  The stored outputs (properties, the Shape) are
what a reopened document shows until the inputs change.
"""

import json

import FreeCAD as App

from . import messages
from .proxy_state import TypeOnlyState

# addProperty attribute bits (App::PropertyType)
PROP_OUTPUT = 8


class DerivedObject(TypeOnlyState):
    TITLE = ""
    # _result: (key, result), None after a restore (TypeOnlyState)

    def __init__(self, obj):
        self.Type = self.TYPE_NAME
        self.add_properties(obj)
        obj.Proxy = self

    def add_properties(self, obj):
        raise NotImplementedError

    def onDocumentRestored(self, obj):
        self.add_properties(obj)

    # -- keys -------------------------------------------------------------------------
    def key(self, obj):
        """What the result depends on, or None while the design is not derived."""
        design = self.design_of(obj)
        if design is None:
            return None
        derived = design.Proxy.derived(design)
        if derived is None:
            return None
        cache = design.Proxy.cache()
        return json.dumps([id(cache.session), derived.key, self.parameters(obj)])

    def kept(self, obj):
        """The kept result if it is current, else None."""
        key = self.key(obj)
        if key is not None and self._result is not None and self._result[0] == key:
            return self._result[1]
        return None

    def keep(self, obj, key, result):
        self._result = (key, result)

    # -- computing ----------------------------------------------------------------------
    def work_for(self, obj):
        """(key, work) on the GUI thread: ``work(task)`` computes on the
        worker from copies, never touching the document."""
        design = self.design_of(obj)
        key = self.key(obj)
        cache = design.Proxy.cache()
        params = self.parameters(obj)
        return key, lambda task: cache.run(lambda ds: self.compute(ds, params, task))

    def compute_now(self, obj):
        """Derive the design and compute here (blocking); keeps and returns the result."""
        design = self.design_of(obj)
        design.Proxy.sync(design)
        key, work = self.work_for(obj)
        result = work(None)
        self.keep(obj, key, result)
        return result

    def execute(self, obj):
        design = self.design_of(obj)
        if design is None:
            self.clear(obj, "error: no Design linked")
            return
        result = self.kept(obj)
        if result is not None:
            self.publish(obj, result)
            return
        if App.GuiUp:
            obj.Status = "computing in the background"
            request(obj)
            return
        try:
            self.publish(obj, self.compute_now(obj))
        except Exception as exc:
            self.clear(obj, "error: {}".format(exc))
            messages.error("{} '{}': {}".format(self.TITLE, obj.Label, exc), dialog=False)
            raise


def _lookup(doc_name, name):
    doc = App.listDocuments().get(doc_name)
    return doc.getObject(name) if doc else None


def request(obj, on_done=None, then_recompute=True):
    """Compute ``obj``'s result in the background (GUI): derive its design
    first if needed (derive_async), then a task with progress and Cancel.
    When it is done the result is kept and ``on_done(obj)`` runs (default:
    recompute the object, which publishes it).  Returns nothing; the task
    is found with ``tasks.running((doc, name))``."""
    from PySide import QtCore
    doc_name, name = obj.Document.Name, obj.Name
    QtCore.QTimer.singleShot(0, lambda: _request(doc_name, name, on_done, then_recompute))


def _request(doc_name, name, on_done, then_recompute):
    from . import derive_async, tasks
    obj = _lookup(doc_name, name)
    if obj is None or tasks.running((doc_name, name)):
        return
    proxy = obj.Proxy
    design = proxy.design_of(obj)
    if design is None:
        return
    if proxy.key(obj) is None:   # the design is not derived (yet): derive it, then come back
        def derived(d, error):
            if error is None and proxy.key(obj) is not None:
                _request(doc_name, name, on_done, then_recompute)
            elif error is not None:
                o = _lookup(doc_name, name)
                if o is not None:
                    o.Proxy.clear(o, "error: the design cannot be derived: {}".format(error))
        derive_async.request(design, callback=derived)
        return
    key, work = proxy.work_for(obj)

    def done(result):
        o = _lookup(doc_name, name)
        if o is None:
            return
        o.Proxy.keep(o, key, result)
        if on_done is not None:
            on_done(o)
        elif then_recompute:
            o.touch()
            o.Document.recompute()

    def failed(task):
        o = _lookup(doc_name, name)
        if o is not None:
            o.Proxy.clear(o, "cancelled: recompute to compute it again" if task.was_cancelled()
                          else "error: {}".format(task.error_message()))

    hooks = [design.Proxy.cache().interrupt]
    tasks.start((doc_name, name), "{} of '{}'".format(proxy.TITLE, design.Label), work, done, hooks, failed)
