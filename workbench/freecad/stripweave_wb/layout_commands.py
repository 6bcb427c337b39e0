"""GUI commands on a Layout's primal vertices (paper §7, manual): Edit
layout vertices (Y, V; the tool on and off, layout_tool.py) and Clear
layout pins (layout_pins.clear_pins, one undoable transaction).  Each acts
on the selected Layout (or the Layout of a selected Design or Patches, or
the document's only Layout)."""

import FreeCAD as App
import FreeCADGui as Gui

from . import icon_path, messages
from .design_commands import _internal_error

EDIT_VERTICES = "StripWeave_EditLayoutVertices"
CLEAR_PINS = "StripWeave_ClearLayoutPins"


def _layout_or_say(what):
    from .job_commands import selected_layout
    from . import layout_tool
    tool = layout_tool.active_tool()
    layout = selected_layout() or (tool.obj() if tool is not None else None)
    if layout is None:
        messages.error("Select a Layout (Show layout makes one), then run {}.".format(what))
    return layout


class EditLayoutVerticesCommand:
    """Edit layout vertices: drag primal vertices within their regions, and edges through
    points of their corridors."""

    def GetResources(self):
        return {"Pixmap": icon_path("EditLayoutVertices.svg"), "Accel": "Y, V", "MenuText": "Edit layout vertices",
                "ToolTip": "Edit layout vertices (Y, V): drag a vertex of the selected Layout within its region; "
                           "where you release it on the part it stays (a pin of the design, drawn as a green "
                           "square). Drag an edge to route it through the point where you release it (an edge "
                           "route of the design). Esc or this command again ends it."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            from . import layout_tool
            if layout_tool.active_tool() is not None:
                layout_tool.active_tool().close()
                return
            layout = _layout_or_say("Edit layout vertices")
            if layout is not None:
                layout_tool.start(layout)
        except Exception:
            _internal_error("Edit layout vertices")


class ClearLayoutPinsCommand:
    """Clear layout pins: every vertex and edge of the layout back to its automatic place."""

    def GetResources(self):
        return {"Pixmap": icon_path("ClearLayoutPins.svg"), "MenuText": "Clear layout pins",
                "ToolTip": "Clear layout pins: remove the vertices placed and the edges routed by hand from the "
                           "selected Layout's design; they go back to their automatic places (undoable)."}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        try:
            from . import layout_pins
            layout = _layout_or_say("Clear layout pins")
            if layout is not None and not layout_pins.clear_pins(layout):
                messages.message("'{}' has no pinned vertices".format(layout.Label))
        except Exception:
            _internal_error("Clear layout pins")


COMMANDS = [EDIT_VERTICES, CLEAR_PINS]
_CLASSES = [EditLayoutVerticesCommand, ClearLayoutPinsCommand]


def register():
    have = set(Gui.listCommands())
    for name, cls in zip(COMMANDS, _CLASSES):
        if name not in have:
            Gui.addCommand(name, cls())


register()
