"""What the task panels of the interactive tools share (design_panel.py,
layout_panel.py): FreeCAD's Gui.Control protocol, where Close ends the
tool, and the status line.  A panel sets ``self.tool`` (with
``close(from_panel=True)``) and ``self.status`` (a QLabel)."""

from PySide import QtGui

ERROR_STYLE = "color: #c92a2a;"


class ToolPanel:
    # -- Gui.Control protocol -----------------------------------------------------------
    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        self.tool.close(from_panel=True)
        return True

    def accept(self):
        return self.reject()

    def set_status(self, text, error=False):
        self.status.setStyleSheet(ERROR_STYLE if error else "")
        self.status.setText(text)
