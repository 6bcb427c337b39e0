"""Registers the StripWeave workbench with the FreeCAD GUI (imported by
FreeCAD at GUI start-up; keep it light: everything else loads in Initialize)."""

import FreeCADGui as Gui

from . import WORKBENCH_ICON


class StripWeaveWorkbench(Gui.Workbench):
    """StripWeave: quad patch layouts by Dual Strip Weaving."""

    MenuText = "StripWeave"
    ToolTip = "Design quad patch layouts by Dual Strip Weaving"
    Icon = WORKBENCH_ICON

    def GetClassName(self):
        return "Gui::PythonWorkbench"

    def Initialize(self):
        from . import commands

        self.appendToolbar("StripWeave", commands.COMMANDS)
        self.appendMenu("StripWeave", commands.COMMANDS)

    def Activated(self):
        pass

    def Deactivated(self):
        pass


Gui.addWorkbench(StripWeaveWorkbench())
