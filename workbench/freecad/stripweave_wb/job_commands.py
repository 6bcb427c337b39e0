"""GUI commands of the main job: Auto weave (Y, A), Show layout (Y, L),
Fit patches (Y, F), Export STEP... (Y, S).  One class per command; each runs
its work on a worker thread with the progress panel and a working Cancel
(tasks.py) and changes the document in one transaction.  The work itself is
in weave_job.py, layout_model.py and patches_model.py (also usable from
macros and freecadcmd)."""

import FreeCAD as App
import FreeCADGui as Gui

from . import icon_path, messages
from .design_commands import _internal_error

AUTO_WEAVE = "StripWeave_AutoWeave"
SHOW_LAYOUT = "StripWeave_ShowLayout"
FIT_PATCHES = "StripWeave_FitPatches"
EXPORT_STEP = "StripWeave_ExportStep"

STEP_FILTER = "STEP (*.step *.stp);;All files (*)"


def _selected():
    sel = Gui.Selection.getSelection()
    return sel[0] if len(sel) == 1 else None


def _only(kind_test):
    doc = App.ActiveDocument
    found = [o for o in doc.Objects if kind_test(o)] if doc else []
    return found[0] if len(found) == 1 else None


def selected_layout():
    """The selected Layout, the Layout of a selected Design or Patches, or
    the document's only Layout."""
    from .design_model import is_design
    from .layout_model import is_layout, layouts_of
    from .patches_model import is_patches
    obj = _selected()
    if obj is None:
        return _only(is_layout)
    if is_layout(obj):
        return obj
    if is_patches(obj):
        return obj.Layout
    if is_design(obj):
        found = layouts_of(obj)
        return found[0] if found else None
    return None


def selected_patches():
    """The selected Patches (or those of a selected PatchWires or Layout), or
    the document's only Patches object."""
    from .layout_model import is_layout
    from .patches_model import is_patch_wires, is_patches, patches_of
    obj = _selected()
    if obj is None:
        return _only(is_patches)
    if is_patches(obj):
        return obj
    if is_patch_wires(obj):
        return obj.Patches
    if is_layout(obj):
        found = patches_of(obj)
        return found[0] if found else None
    return None


def _design_for_layout():
    from .design_commands import selected_design
    from .layout_model import is_layout
    obj = _selected()
    if obj is not None and is_layout(obj):
        return obj.Design
    return selected_design()


class AutoWeaveCommand:
    """Auto weave: complete the selected design automatically."""

    def GetResources(self):
        return {"Pixmap": icon_path("AutoWeave.svg"), "Accel": "Y, A", "MenuText": "Auto weave",
                "ToolTip": "Auto weave (Y, A): complete the selected design automatically, keeping its strips "
                           "(red regions first, then orange and yellow, then splitting the worst patches). "
                           "Runs in the background; Cancel in the task panel stops it. Undoable."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            from . import preferences, weave_job
            from .design_commands import selected_design
            obj = selected_design()
            if obj is None:
                messages.error("Select a Design (New design makes one), then run Auto weave.")
                return
            weave_job.start(obj, max_strips=preferences.auto_weave_max_strips(),
                            crease_pairs=preferences.auto_weave_crease_pairs())
        except Exception:
            _internal_error("Auto weave")


class ShowLayoutCommand:
    """Show layout: the selected design's regions and primal quad layout."""

    def GetResources(self):
        return {"Pixmap": icon_path("Layout.svg"), "Accel": "Y, L", "MenuText": "Show layout",
                "ToolTip": "Show layout (Y, L): a Layout object with the selected design's patches, their "
                           "edges and vertices, the red/orange/yellow regions and the defects. It follows the "
                           "design as it changes."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            from . import layout_model
            design = _design_for_layout()
            if design is None:
                messages.error("Select a Design, then run Show layout.")
                return
            obj = layout_model.create(design)
            Gui.Selection.clearSelection()
            Gui.Selection.addSelection(obj)
        except Exception:
            _internal_error("Show layout")


class FitPatchesCommand:
    """Fit patches: NURBS faces on the selected layout's quad patches."""

    def GetResources(self):
        return {"Pixmap": icon_path("FitPatches.svg"), "Accel": "Y, F", "MenuText": "Fit patches",
                "ToolTip": "Fit patches (Y, F): fit a B-spline face to every quad patch of the selected layout "
                           "and sew them into a shell or solid, coloured by deviation (green within tolerance, "
                           "yellow at it, red at twice it); also the patch wires. Runs in the background."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            from . import patches_model, preferences
            layout = selected_layout()
            if layout is None:
                messages.error("Select a Layout (Show layout makes one from a design), then run Fit patches.")
                return
            if not layout.Valid:
                messages.error("Layout '{}' has no patches to fit: {}".format(layout.Label, layout.Status))
                return
            tol = preferences.tolerance() or None
            obj = patches_model.create(layout, tolerance=tol)
            Gui.Selection.clearSelection()
            Gui.Selection.addSelection(obj)
        except Exception:
            _internal_error("Fit patches")


class ExportStepCommand:
    """Export STEP...: write the selected fitted patches as a STEP file."""

    def GetResources(self):
        return {"Pixmap": icon_path("ExportStep.svg"), "Accel": "Y, S", "MenuText": "Export STEP...",
                "ToolTip": "Export STEP (Y, S): write the selected fitted patches (shell or solid of B-spline "
                           "faces) as a STEP file, and read it back to check it."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            obj = selected_patches()
            if obj is None:
                messages.error("Select fitted Patches (Fit patches makes them), then run Export STEP.")
                return
            path = step_file_dialog(obj.Label.split(" ")[0].lower() + ".step")
            if path:
                start_export(obj, path)
        except Exception:
            _internal_error("Export STEP")


def step_file_dialog(default_name):
    from .design_commands import _file_dialog
    return _file_dialog(True, "Export StripWeave patches as STEP", default_name, STEP_FILTER, ".step")


def start_export(obj, path):
    """Export on a worker thread (the shape copied here); returns the Task."""
    from . import tasks
    from .patches_model import export_shape, is_patches
    if not is_patches(obj) or obj.Shape.isNull() or not obj.Shape.Faces:
        messages.error("'{}' has no fitted faces to export".format(obj.Label))
        return None
    shape = obj.Shape.copy()
    label = obj.Label

    def done(info):
        messages.message("'{}' exported to {}: {} faces, read back {} ({}, {} solid{})".format(
            label, info["path"], info["faces"], info["faces_read_back"], "valid" if info["valid"] else "INVALID",
            info["solids"], "" if info["solids"] == 1 else "s"))
        if info["faces_read_back"] != info["faces"]:
            messages.error("the STEP file read back has {} faces, not {}".format(info["faces_read_back"],
                                                                                  info["faces"]))
    return tasks.start((obj.Document.Name, obj.Name, "step"), "Export STEP of '{}'".format(label),
                       lambda task: export_shape(shape, path), done)


COMMANDS = [AUTO_WEAVE, SHOW_LAYOUT, FIT_PATCHES, EXPORT_STEP]
_CLASSES = [AutoWeaveCommand, ShowLayoutCommand, FitPatchesCommand, ExportStepCommand]


def register():
    have = set(Gui.listCommands())
    for name, cls in zip(COMMANDS, _CLASSES):
        if name not in have:
            Gui.addCommand(name, cls())


register()
