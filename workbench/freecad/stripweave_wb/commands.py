"""StripWeave GUI commands (registered with FreeCADGui.addCommand on import)."""

import traceback

import FreeCAD as App
import FreeCADGui as Gui

from . import icon_path, messages

PREPARE_SURFACE = "StripWeave_PrepareSurface"


def _report_internal_error(what):
    App.Console.PrintLog(traceback.format_exc())
    messages.error("{} failed with an internal error (details in the log):\n{}".format(
        what, traceback.format_exc().strip().splitlines()[-1]))


def prepare_surface(source, target_triangles=None, feature_angle_deg=None):
    """Build the surface model of ``source`` (a Part or Mesh object) on a
    worker thread; when it is done, add a SurfaceModel object to the document
    (one undoable transaction), draw its overlay and print the report.

    A part prepared already keeps its one SurfaceModel: it is reused when
    up to date, else rebuilt (with the parameters given, if any), and a part
    being prepared with the same parameters is not prepared twice.

    Returns the build controller (``builder.wait_for_builds()`` waits for
    it), or None when nothing needs building or ``source`` cannot be used
    (the reason was reported).  With a SurfaceModel as ``source`` it is
    rebuilt instead.
    """
    from . import builder, surface_model

    if surface_model.is_surface_model(source):
        return builder.rebuild(source)
    existing = [o for o in source.InList if surface_model.is_surface_model(o) and o.Source == source]
    if existing:
        return _prepare_again(existing[0], target_triangles, feature_angle_deg)
    params = surface_model.parameter_defaults()
    if target_triangles is not None:
        params["target_triangles"] = int(target_triangles)
    if feature_angle_deg is not None:
        params["feature_angle_deg"] = float(feature_angle_deg)
    doc_name, source_name = source.Document.Name, source.Name
    key = (doc_name, "prepare:" + source_name)
    running = builder.running_for(key)
    if running is not None and not running.job.cancelled and running.job.options == params:
        messages.message("'{}' is being prepared already".format(source.Label))
        return running

    def done(ctl):
        doc = App.listDocuments().get(doc_name)
        src = doc.getObject(source_name) if doc else None
        if src is None:
            messages.warning("'{}' was deleted during the build; result dropped".format(ctl.source_label))
            return
        doc.openTransaction("Prepare surface")
        try:
            obj = surface_model.create(src, params["target_triangles"], params["feature_angle_deg"],
                                       surface=ctl.job.surface, doc=doc)
        except Exception:
            doc.abortTransaction()
            raise
        doc.commitTransaction()
        ctl.result_object = obj
        report = obj.Proxy.report(obj)
        builder.print_report(obj, ctl, report)

    return builder.start_build(
        key, source, params,
        "Preparing surface of '{}'".format(source.Label), done)


def _prepare_again(sm, target_triangles, feature_angle_deg):
    """Prepare surface on a part that has SurfaceModel ``sm``: set the
    parameters given (one transaction), then rebuild it if it is not up to
    date; selected either way."""
    from . import builder
    wanted = {"TargetTriangles": None if target_triangles is None else int(target_triangles),
              "FeatureAngle": None if feature_angle_deg is None else float(feature_angle_deg)}
    changes = {k: v for k, v in wanted.items() if v is not None and getattr(sm, k) != v}
    if changes:
        doc = sm.Document
        doc.openTransaction("Prepare surface")
        for k, v in changes.items():
            setattr(sm, k, v)
        doc.commitTransaction()
        sm.purgeTouched()  # rebuilt below: a recompute must not start a second build
    if App.GuiUp:
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(sm)
    running = builder.running_for((sm.Document.Name, sm.Name))
    if running is not None and not running.job.cancelled and not changes:
        messages.message("'{}' is being rebuilt already".format(sm.Label))
        return running
    if sm.Proxy.is_up_to_date(sm):
        messages.message("'{}' is prepared already: {} (up to date, reused)".format(
            sm.Source.Label, sm.Label))
        return None
    messages.message("'{}' is prepared already: rebuilding {}".format(sm.Source.Label, sm.Label))
    return builder.rebuild(sm)


class PrepareSurfaceCommand:
    """Prepare surface: build the StripWeave surface model of the selected
    Part or Mesh object and show its feature curves and boundaries."""

    def GetResources(self):
        return {
            "Pixmap": icon_path("PrepareSurface.svg"),
            "MenuText": "Prepare surface",
            "Accel": "Y, P",
            "ToolTip": ("Prepare surface: remesh the selected Part or Mesh object for "
                        "StripWeave, find its feature curves and boundaries, and show them."),
        }

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            sel = Gui.Selection.getSelection()
            if len(sel) != 1:
                messages.error("Select exactly one Part or Mesh object, then run Prepare surface.")
                return
            prepare_surface(sel[0])
        except Exception:
            _report_internal_error("Prepare surface")


def register():
    if PREPARE_SURFACE not in Gui.listCommands():
        Gui.addCommand(PREPARE_SURFACE, PrepareSurfaceCommand())


register()

from . import design_commands, job_commands, layout_commands  # noqa: E402  (register the other commands)

COMMANDS = [PREPARE_SURFACE] + design_commands.COMMANDS + job_commands.COMMANDS + layout_commands.COMMANDS
