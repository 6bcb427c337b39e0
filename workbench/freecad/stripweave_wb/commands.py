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

    Returns the build controller (``builder.wait_for_builds()`` waits for
    it), or None when ``source`` cannot be used (the reason was reported).
    With a SurfaceModel as ``source`` it is rebuilt instead.
    """
    from . import builder, surface_model

    if surface_model.is_surface_model(source):
        return builder.rebuild(source)
    params = surface_model.parameter_defaults()
    if target_triangles is not None:
        params["target_triangles"] = int(target_triangles)
    if feature_angle_deg is not None:
        params["feature_angle_deg"] = float(feature_angle_deg)
    doc_name, source_name = source.Document.Name, source.Name

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
        (doc_name, "prepare:" + source_name), source, params,
        "Preparing surface of '{}'".format(source.Label), done)


class PrepareSurfaceCommand:
    """Prepare surface: build the StripWeave surface model of the selected
    Part or Mesh object and show its feature curves and boundaries."""

    def GetResources(self):
        return {
            "Pixmap": icon_path("PrepareSurface.svg"),
            "MenuText": "Prepare surface",
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

from . import design_commands  # noqa: E402  (registers the design commands)

COMMANDS = [PREPARE_SURFACE] + design_commands.COMMANDS
