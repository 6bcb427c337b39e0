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
        from . import commands, preferences

        self.appendToolbar("StripWeave", commands.COMMANDS)
        self.appendMenu("StripWeave", commands.COMMANDS)
        preferences.register_page()

    def Activated(self):
        native_library_check()

    def Deactivated(self):
        pass


def native_library_check():
    """Say what to run when the native library cannot be imported (once per
    session): the report view and a message box.  True if it imports."""
    from . import import_stripweave, messages
    global _checked
    try:
        import_stripweave()
        return True
    except ImportError as exc:
        if not _checked:
            messages.error(str(exc))
        _checked = True
        return False


_checked = False
Gui.addWorkbench(StripWeaveWorkbench())
