"""The design tool's worker thread: loop queries and strip additions on a
Design's SessionCache, off the GUI thread.

Two kinds of requests:

* proposals (hover: the best loop through a point; browse: the ranked
  alternatives through it).  Only the newest is kept: submitting one drops
  the pending one and interrupts the running one (the native query raises
  Cancelled), so the cursor never waits for stale work;
* edits (add a strip: through given anchors, or the loop shown, from the
  first candidate anchor that derives it again; replace a strip's anchors:
  a grab-and-drag's re-route, an anchor deleted or made positional), run in
  order, never dropped nor interrupted;
* the regions and defects of the current design (region_list.py), the
  newest only, when no edit and no proposal waits.

Results are collected in a list the GUI thread takes with
:meth:`QueryWorker.take_results` (from a QTimer poll); each carries its
request's serial number and the cache revision it was computed at, so the
GUI can drop stale ones.  No Qt and no document access here.
"""

import collections
import threading
import traceback

from . import import_stripweave


class Request:
    def __init__(self, serial, kind, args):
        self.serial = serial
        self.kind = kind          # "best", "alternatives", "add" or "edit"
        self.args = args


class Result:
    def __init__(self, request, value=None, error=None, cancelled=False, revision=None):
        self.serial = request.serial
        self.kind = request.kind
        self.args = request.args
        self.value = value
        self.error = error        # one line for the user, or None
        self.cancelled = cancelled
        self.revision = revision  # SessionCache.revision the value belongs to


class QueryWorker:
    def __init__(self, cache, name="StripWeave design tool"):
        self.sw = import_stripweave()
        self.cache = cache
        self._cond = threading.Condition()
        self._proposal = None
        self._regions = None
        self._edits = collections.deque()
        self._results = []
        self._serial = 0
        self._busy = False
        self._stopped = False
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    # -- GUI thread -----------------------------------------------------------------
    def propose(self, kind, point, alternatives=1, masked=True):
        """Queue a proposal query ("best" or "alternatives") through ``point``
        (``masked``: see SessionCache.proposals); returns its serial.
        Replaces and interrupts older proposals."""
        with self._cond:
            self._serial += 1
            self._proposal = Request(self._serial, kind, (tuple(point), int(alternatives), bool(masked)))
            self._cond.notify()
            serial = self._serial
        self.cache.interrupt()
        return serial

    def add_strip(self, anchors, shown=None):
        """Queue adding a strip through ``anchors``, or, given ``shown`` (the
        polyline of the proposal shown), the strip of that loop from the
        first of the candidate ``anchors`` that derives it again; returns
        its serial."""
        with self._cond:
            self._serial += 1
            args = ([list(a) for a in anchors], None if shown is None else [list(p) for p in shown])
        return self._edit("add", args)

    def regions(self):
        """Queue listing the design's regions and defects; returns its serial."""
        with self._cond:
            self._serial += 1
            self._regions = Request(self._serial, "regions", ())
            self._cond.notify()
            return self._serial

    def edit_strip(self, index, anchors):
        """Queue replacing strip ``index``'s anchors; returns its serial."""
        return self._edit("edit", (int(index), [list(a) for a in anchors]))

    def _edit(self, kind, args):
        with self._cond:
            self._serial += 1
            self._edits.append(Request(self._serial, kind, args))
            self._proposal = None  # computed before the edit: stale anyway
            self._cond.notify()
            serial = self._serial
        self.cache.interrupt()
        return serial

    def take_results(self):
        with self._cond:
            out, self._results = self._results, []
        return out

    def idle(self):
        with self._cond:
            return (not self._busy and self._proposal is None and self._regions is None and not self._edits
                    and not self._results)

    def stop(self):
        with self._cond:
            self._stopped = True
            self._proposal = self._regions = None
            self._edits.clear()
            self._cond.notify()
        self.cache.interrupt()

    def join(self, timeout=None):
        self._thread.join(timeout)
        return not self._thread.is_alive()

    # -- worker thread ----------------------------------------------------------------
    def _next(self):
        with self._cond:
            while not self._stopped and self._proposal is None and self._regions is None and not self._edits:
                self._cond.wait()
            if self._stopped:
                return None
            self._busy = True
            if self._edits:
                return self._edits.popleft()
            if self._proposal is not None:
                req, self._proposal = self._proposal, None
            else:
                req, self._regions = self._regions, None
            return req

    def _run(self):
        while True:
            req = self._next()
            if req is None:
                return
            try:
                result = self._execute(req)
            except self.sw.Cancelled:
                result = Result(req, cancelled=True)
            except self.sw.InputError as exc:
                result = Result(req, error=str(exc))
            except Exception as exc:
                traceback.print_exc()
                result = Result(req, error="{}: {}".format(type(exc).__name__, exc))
            with self._cond:
                self._busy = False
                if not self._stopped:
                    self._results.append(result)

    def _execute(self, req):
        if req.kind == "regions":
            from . import region_list
            cache = self.cache
            value, revision = cache.run(lambda ds: (region_list.compute(ds), cache.revision))
            return Result(req, value=value, revision=revision)
        if req.kind == "edit":
            index, anchors = req.args
            data, derived = self.cache.edit_strip(index, anchors)
            return Result(req, value=data, revision=derived.revision)
        if req.kind == "add":
            anchors, shown = req.args
            if shown is None:
                data, derived = self.cache.add_strip(anchors)
            else:
                data, derived = self.cache.add_shown(anchors, shown)
            return Result(req, value=data, revision=derived.revision)
        point, alternatives, masked = req.args
        value, revision = self.cache.proposals(point, alternatives if req.kind == "alternatives" else 1, masked)
        return Result(req, value=value, revision=revision)
