"""Building a stripweave Surface on a worker thread.

No Qt and no document access here: :func:`snapshot_source` runs on the GUI
thread and copies what the native side needs out of the document object, then
:class:`SurfaceJob` hands that copy to ``stripweave.from_object`` on a Python
``threading.Thread``.  The native call releases the GIL, so the GUI thread stays
responsive and polls ``job.progress`` (see ``builder.py``).
"""

import threading
import time
import traceback

import FreeCAD as App

from . import import_stripweave
from .preferences import DEFAULT_FEATURE_ANGLE_DEG, DEFAULT_TARGET_TRIANGLES  # noqa: F401 (re-exported)


class SourceError(ValueError):
    """The selected object cannot be used as a source (raised on the GUI thread)."""


def source_kind(obj):
    """``"shape"`` for a Part-like object, ``"mesh"`` for a Mesh feature.

    Raises :class:`SourceError` with a message for the user otherwise.
    """
    if obj is None:
        raise SourceError("Select a Part or Mesh object first.")
    if obj.isDerivedFrom("Mesh::Feature") or (hasattr(obj, "Mesh") and not hasattr(obj, "Shape")):
        if obj.Mesh.CountFacets == 0:
            raise SourceError("'{}' is an empty mesh: nothing to prepare.".format(obj.Label))
        return "mesh"
    shape = _shape_of(obj)
    if shape is not None and hasattr(shape, "exportBrepToString"):
        if shape.isNull():
            raise SourceError("'{}' has an empty shape: nothing to prepare.".format(obj.Label))
        return "shape"
    raise SourceError(
        "'{}' ({}) is neither a Part nor a Mesh object: select an object that has "
        "a shape or a mesh.".format(obj.Label, obj.TypeId)
    )


def _shape_of(obj):
    """obj.Shape, or for links and containers (App::Link, App::Part) the
    shape FreeCAD resolves for them."""
    shape = getattr(obj, "Shape", None)
    if shape is not None:
        return shape
    try:
        import Part
        shape = Part.getShape(obj)
    except Exception:
        return None
    return None if shape.isNull() else shape


class SourceSnapshot:
    """A thread-safe stand-in for a Part::Feature / Mesh::Feature.

    Holds *copies* of the shape or mesh, taken on the GUI thread, and answers
    the few questions ``stripweave.from_object`` asks about the object, so the
    worker thread never touches the document.
    """

    def __init__(self, obj):
        self.Name = obj.Name
        self.Label = obj.Label
        self.TypeId = obj.TypeId
        self.kind = source_kind(obj)
        self._types = {
            t: bool(obj.isDerivedFrom(t))
            for t in ("App::DocumentObject", "App::GeoFeature", "Part::Feature", "Mesh::Feature")
        }
        self.Placement = obj.Placement.copy() if hasattr(obj, "Placement") else App.Placement()
        if self.kind == "mesh":
            self.Mesh = obj.Mesh.copy()
        else:
            self.Shape = _shape_of(obj).copy()

    def isDerivedFrom(self, type_name):
        return self._types.get(type_name, False)

    def __repr__(self):
        return "<SourceSnapshot of {} ({})>".format(self.Name, self.TypeId)


def snapshot_source(obj):
    return SourceSnapshot(obj)


class SurfaceJob:
    """One surface build on a worker thread.

    ``job.progress`` is the native ``stripweave.Progress`` (poll ``fraction()``
    and ``stage()``); after ``job.done()``: ``job.surface`` or ``job.error``
    (the exception) with ``job.error_traceback``; ``job.cancelled`` tells
    whether :meth:`cancel` was called.
    """

    def __init__(self, source, target_triangles=DEFAULT_TARGET_TRIANGLES,
                 feature_angle_deg=DEFAULT_FEATURE_ANGLE_DEG, label=None):
        self.sw = import_stripweave()
        self.source = source
        self.options = {
            "target_triangles": int(target_triangles),
            "feature_angle_deg": float(feature_angle_deg),
        }
        self.label = label or getattr(source, "Label", "?")
        self.progress = self.sw.Progress()
        self.surface = None
        self.error = None
        self.error_traceback = ""
        self.cancelled = False
        self.started_at = None
        self.seconds = 0.0
        self._thread = threading.Thread(target=self._run, name="StripWeave surface build", daemon=True)

    def start(self):
        self.started_at = time.monotonic()
        self._thread.start()
        return self

    def _run(self):
        try:
            self.surface = self.sw.from_object(self.source, progress=self.progress, **self.options)
        except BaseException as exc:  # reported on the GUI thread
            self.error = exc
            self.error_traceback = traceback.format_exc()
        finally:
            self.seconds = time.monotonic() - self.started_at

    def run_here(self):
        """Run synchronously on the calling thread (headless use)."""
        self.started_at = time.monotonic()
        self._run()
        return self

    def done(self):
        return self.started_at is not None and not self._thread.is_alive()

    def join(self, timeout=None):
        if self._thread.is_alive():
            self._thread.join(timeout)
        return self.done()

    def cancel(self):
        self.cancelled = True
        try:
            self.progress.cancel()
        except Exception:
            pass

    def fraction(self):
        try:
            return max(0.0, min(1.0, float(self.progress.fraction())))
        except Exception:
            return 0.0

    def stage(self):
        try:
            return str(self.progress.stage())
        except Exception:
            return ""

    def is_input_error(self):
        return self.error is not None and isinstance(self.error, self.sw.InputError)

    def is_cancel_error(self):
        """True when the build stopped because it was cancelled."""
        if self.error is None:
            return False
        cancelled_types = tuple(
            t for t in (getattr(self.sw, "Cancelled", None), getattr(self.sw, "CancelledError", None))
            if isinstance(t, type)
        )
        return self.cancelled or (bool(cancelled_types) and isinstance(self.error, cancelled_types))

    def error_message(self):
        """One line for the user (the InputError text as is)."""
        if self.error is None:
            return ""
        if self.is_input_error():
            return str(self.error)
        return "{}: {}".format(type(self.error).__name__, self.error)
