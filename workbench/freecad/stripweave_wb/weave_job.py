"""Auto weave: complete a Design by automatic weaving (``stripweave.weave``,
issue 6), keeping the user's strips first and unchanged.

    from freecad.stripweave_wb import weave_job
    result = weave_job.run(design, max_strips=20)      # blocking (macros, freecadcmd)
    task = weave_job.start(design)                    # GUI: background, progress, Cancel

Options are those of ``stripweave.weave.WeaveOptions`` (max_strips,
patches, budget, seed, ...); an unknown one is an InputError naming it.
The new design is written as one transaction "Auto weave"; a cancelled or
failed weave leaves the document unchanged.
"""

import dataclasses

import FreeCAD as App

from . import import_stripweave, messages


def weave_options(**options):
    """WeaveOptions from keyword options, checked (InputError names an unknown one)."""
    sw = import_stripweave()
    from stripweave.weave import WeaveOptions
    known = {f.name for f in dataclasses.fields(WeaveOptions)} - {"cancel"}
    unknown = sorted(set(options) - known)
    if unknown:
        raise sw.InputError("auto weave: unknown option{} {} (known: {})".format(
            "s" if len(unknown) > 1 else "", ", ".join(unknown), ", ".join(sorted(known))))
    opts = WeaveOptions(**options)
    opts.check()
    return opts


def summary(result, before, after):
    text = "{} strips ({} kept, {} added); stopped: {}; red {}, orange {}, yellow {}; work {:.0f}".format(
        after, before, after - before, result.stopped, result.assessment["colours"]["red"],
        result.assessment["colours"]["orange"], result.assessment["colours"]["yellow"], result.work)
    return text


def _write(obj, data, result, before):
    from .design_model import write_design
    write_design(obj, data, "Auto weave")
    text = summary(result, before, len(data["strips"]))
    messages.message("auto weave of '{}': {}".format(obj.Label, text))
    return text


def run(obj, **options):
    """Complete ``obj`` (a Design) here, blocking; returns the WeaveResult."""
    from .design_model import is_design
    if not is_design(obj):
        raise ValueError("StripWeave: '{}' is not a Design".format(getattr(obj, "Label", obj)))
    opts = weave_options(**options)
    obj.Proxy.sync(obj)
    cache = obj.Proxy.cache()
    before = len(cache.session.design.strips)
    result, data, _derived = cache.weave(opts)
    _write(obj, data, result, before)
    return result


def start(obj, **options):
    """GUI: derive the design if needed, then weave on a worker thread with
    the progress panel; Cancel stops it at its next step (a running loop
    query at once).  Returns nothing (``tasks.running`` finds the task)."""
    from . import derive_async
    opts = weave_options(**options)
    doc_name, name = obj.Document.Name, obj.Name
    if obj.Proxy.derived(obj) is None:
        derive_async.request(obj, callback=lambda o, err: _start(doc_name, name, opts) if err is None else
                             messages.error("auto weave: design '{}' cannot be derived: {}".format(o.Label, err)))
        return
    _start(doc_name, name, opts)


def _start(doc_name, name, opts):
    from . import tasks
    doc = App.listDocuments().get(doc_name)
    obj = doc.getObject(name) if doc else None
    if obj is None:
        return None
    cache = obj.Proxy.cache()
    before = len(obj.Proxy.design(obj).strips)
    state = {}

    def work(task):
        opts.cancel = task.cancelled
        return cache.weave(opts, on_session=lambda ds: state.update(ds=ds))

    def progress():
        ds = state.get("ds")
        if ds is None:
            return 0.0, "deriving the design's strips"
        n = len(ds.design.strips)
        if opts.max_strips is None:
            # The cap follows the part's topology (WeaveOptions.max_strips): no fraction of it
            # to show, only that the strips grow.
            return 0.05 + 0.9 * n / (n + 20.0), "weaving: {} strips".format(n)
        return (0.05 + 0.9 * min(1.0, n / max(1, opts.max_strips)),
                "weaving: {} strips (at most {})".format(n, opts.max_strips))

    def done(out):
        o = App.listDocuments()[doc_name].getObject(name) if doc_name in App.listDocuments() else None
        if o is None:
            return
        result, data, _derived = out
        _write(o, data, result, before)

    def cancel_query():
        if cache.session is not None:
            cache.session.loop_session.native.cancel()

    task = tasks.start((doc_name, name, "weave"), "Auto weave of '{}'".format(obj.Label), work, done,
                       [cancel_query])
    task.progress_fn = progress
    return task
