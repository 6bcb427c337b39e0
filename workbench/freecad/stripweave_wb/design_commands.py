"""GUI commands for designs: New design, Design strips, Remove strip,
Import design..., Export design... (registered with FreeCADGui.addCommand
on import; one class per command; shortcuts "Y, N", "Y, D", "Y, R", "Y, I",
"Y, E", and "Y, P" for Prepare surface: FreeCAD's built-in workbenches use
no "Y, _" sequence).  Every change to a design is one document
transaction, so Undo/Redo work."""

import os
import traceback

import FreeCAD as App
import FreeCADGui as Gui

from . import design_model, icon_path, messages
from .surface_model import is_surface_model

NEW_DESIGN = "StripWeave_NewDesign"
DESIGN_STRIPS = "StripWeave_DesignStrips"
REMOVE_STRIP = "StripWeave_RemoveStrip"
IMPORT_DESIGN = "StripWeave_ImportDesign"
EXPORT_DESIGN = "StripWeave_ExportDesign"

FILE_FILTER = "StripWeave design (*.json);;All files (*)"


def _internal_error(what):
    App.Console.PrintLog(traceback.format_exc())
    messages.error("{} failed with an internal error (details in the log):\n{}".format(
        what, traceback.format_exc().strip().splitlines()[-1]))


def _surface_models_of(obj):
    return [o for o in obj.InList if is_surface_model(o) and o.Source == obj]


def selected_surface_model():
    """The selected SurfaceModel (or that of a selected Design or source), or None."""
    sel = Gui.Selection.getSelection()
    if len(sel) != 1:
        return None
    obj = sel[0]
    if is_surface_model(obj):
        return obj
    if design_model.is_design(obj):
        return obj.Surface
    models = _surface_models_of(obj)
    return models[0] if len(models) == 1 else None


def selected_design():
    """The selected Design; else the only Design of a selected SurfaceModel;
    else the only Design in the document."""
    sel = Gui.Selection.getSelection()
    if len(sel) == 1:
        if design_model.is_design(sel[0]):
            return sel[0]
        sm = selected_surface_model()
        if sm is not None:
            designs = design_model.designs_of(sm)
            return designs[0] if len(designs) == 1 else None
        return None
    if not sel and App.ActiveDocument is not None:
        designs = [o for o in App.ActiveDocument.Objects if design_model.is_design(o)]
        return designs[0] if len(designs) == 1 else None
    return None


def new_design(surface_model, design=None, name="New design"):
    """Add a Design on ``surface_model`` in one transaction and recompute."""
    doc = surface_model.Document
    with design_model.transaction(doc, name):
        obj = design_model.create(surface_model, design)
        doc.recompute()
    return obj


def _file_dialog(save, title, default_name="", file_filter=FILE_FILTER, extension=".json"):
    """A file name from Qt's own file dialog (the same on every desktop and
    under Xvfb); ``extension`` is added to a saved name without one."""
    from PySide import QtGui
    start = os.path.join(App.ParamGet("User parameter:BaseApp/Preferences/General").GetString(
        "FileOpenSavePath", os.path.expanduser("~")), default_name)
    fn = QtGui.QFileDialog.getSaveFileName if save else QtGui.QFileDialog.getOpenFileName
    path = fn(Gui.getMainWindow(), title, start, file_filter, "", QtGui.QFileDialog.DontUseNativeDialog)
    path = path[0] if isinstance(path, tuple) else path
    if path and save and not os.path.splitext(path)[1]:
        path += extension
    return path or None


class NewDesignCommand:
    """New design: an empty Design on the selected SurfaceModel."""

    def GetResources(self):
        return {"Pixmap": icon_path("NewDesign.svg"), "Accel": "Y, N", "MenuText": "New design",
                "ToolTip": "New design: start an empty strip design on the selected surface model "
                           "(or on the surface model of the selected part)."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            sm = selected_surface_model()
            if sm is None:
                messages.error("Select a SurfaceModel (run Prepare surface on a part first), then New design.")
                return
            obj = new_design(sm)
            Gui.Selection.clearSelection()
            Gui.Selection.addSelection(obj)
        except Exception:
            _internal_error("New design")


class DesignStripsCommand:
    """Design strips: the interactive tool (hover, Ctrl+wheel, click)."""

    def GetResources(self):
        return {"Pixmap": icon_path("DesignStrips.svg"), "Accel": "Y, D", "MenuText": "Design strips",
                "ToolTip": "Design strips (Y, D): hover the surface to see the best strip through the cursor, "
                           "Ctrl+wheel or Page Down / Page Up to browse alternatives, click to add it, Esc to end. "
                           "Works on the selected design "
                           "(a new one is made on a selected surface model without designs)."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            from . import design_tool
            obj = selected_design()
            if obj is None:
                sm = selected_surface_model()
                if sm is None or design_model.designs_of(sm):
                    messages.error("Select a Design (or a SurfaceModel), then run Design strips.")
                    return
                obj = new_design(sm)
            design_tool.start(obj)
        except Exception:
            _internal_error("Design strips")


class RemoveStripCommand:
    """Remove strip: pick one of the selected design's strips and remove it."""

    def GetResources(self):
        return {"Pixmap": icon_path("RemoveStrip.svg"), "Accel": "Y, R", "MenuText": "Remove strip",
                "ToolTip": "Remove strip: remove a strip of the selected design (the one whose loop edge "
                           "is selected, or one chosen from a list). Undoable."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            obj = selected_design()
            if obj is None:
                messages.error("Select a Design, then run Remove strip.")
                return
            n = len(obj.Proxy.design(obj).strips)
            if n == 0:
                messages.error("Design '{}' has no strips.".format(obj.Label))
                return
            index = self._selected_loop(obj)
            if index is None:
                index = self._ask(obj, n)
            if index is not None:
                design_model.remove_strip(obj, index)
        except Exception:
            _internal_error("Remove strip")

    @staticmethod
    def _selected_loop(obj):
        """The strip whose loop edge is selected (Part display modes), or None."""
        for sx in Gui.Selection.getSelectionEx():
            if sx.Object != obj:
                continue
            for sub in sx.SubElementNames:
                if not sub.startswith("Edge"):
                    continue
                edge = obj.Shape.getElement(sub)
                for i, wire in enumerate(obj.Shape.Wires):
                    if any(e.isSame(edge) for e in wire.Edges):
                        return i
        return None

    @staticmethod
    def _ask(obj, n):
        from PySide import QtGui
        strips = obj.Proxy.summary(obj).get("strips", [])
        items = []
        for i in range(n):
            if i < len(strips):
                s = strips[i]
                items.append("Strip {}: length {:.4g}, area {:.1f}%".format(
                    i + 1, s["length"], 100 * s["area_fraction"]))
            else:
                items.append("Strip {}: failed".format(i + 1))
        item, ok = QtGui.QInputDialog.getItem(Gui.getMainWindow(), "Remove strip",
                                              "Strip of '{}' to remove:".format(obj.Label), items, n - 1, False)
        return items.index(item) if ok and item in items else None


class ImportDesignCommand:
    """Import design...: read a design file into the selected Design (or a
    new Design on the selected SurfaceModel)."""

    def GetResources(self):
        return {"Pixmap": icon_path("ImportDesign.svg"), "Accel": "Y, I", "MenuText": "Import design...",
                "ToolTip": "Import design: replace the selected design by a design file (JSON), or start a "
                           "new design from it on the selected surface model. Undoable."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            obj = selected_design()
            sm = selected_surface_model()
            if obj is None and sm is None:
                messages.error("Select a Design or a SurfaceModel, then run Import design.")
                return
            path = _file_dialog(False, "Import StripWeave design")
            if not path:
                return
            import_design(obj, sm, path)
        except Exception:
            _internal_error("Import design")


def import_design(obj, surface_model, path):
    """Import into ``obj`` (a Design) or, with obj None, a new Design on
    ``surface_model``.  A file that does not parse is reported, nothing changes."""
    from . import import_stripweave
    sw = import_stripweave()
    from stripweave.design import Design
    try:
        data = Design.load(path).to_dict()
    except (sw.InputError, OSError) as exc:
        messages.error("cannot import {}: {}".format(path, exc))
        return None
    if obj is None:
        return new_design(surface_model, data, name="Import design")
    design_model.write_design(obj, data, "Import design")
    return obj


class ExportDesignCommand:
    """Export design...: write the selected Design as a design file."""

    def GetResources(self):
        return {"Pixmap": icon_path("ExportDesign.svg"), "Accel": "Y, E", "MenuText": "Export design...",
                "ToolTip": "Export design: save the selected design as a design file (JSON) for the "
                           "stripweave command line or another model."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            obj = selected_design()
            if obj is None:
                messages.error("Select a Design, then run Export design.")
                return
            path = _file_dialog(True, "Export StripWeave design", obj.Label.split(" ")[0].lower() + ".json")
            if not path:
                return
            design_model.export_design(obj, path)
            messages.message("design '{}' exported to {}".format(obj.Label, path))
        except Exception:
            _internal_error("Export design")


COMMANDS = [NEW_DESIGN, DESIGN_STRIPS, REMOVE_STRIP, IMPORT_DESIGN, EXPORT_DESIGN]
_CLASSES = [NewDesignCommand, DesignStripsCommand, RemoveStripCommand, ImportDesignCommand, ExportDesignCommand]


def register():
    have = set(Gui.listCommands())
    for name, cls in zip(COMMANDS, _CLASSES):
        if name not in have:
            Gui.addCommand(name, cls())


register()
