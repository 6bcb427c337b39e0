"""Task panel showing the progress of a surface build, with a Cancel button."""

import time

import FreeCADGui as Gui
from PySide import QtCore, QtGui

from . import WORKBENCH_ICON


def _is_alive(widget):
    """False once the task dialog is gone: FreeCAD sets the panel's ``form``
    to None when it destroys the dialog, or Qt has deleted the widget."""
    if widget is None:
        return False
    try:
        widget.objectName()
        return True
    except RuntimeError:
        return False


def _in_main_window(widget):
    """True while ``widget`` sits in the main window (i.e. its task dialog is
    still open; FreeCAD detaches or deletes the form when the dialog goes)."""
    try:
        w = widget
        while w is not None:
            if isinstance(w, QtGui.QMainWindow):
                return True
            w = w.parentWidget()
    except RuntimeError:
        pass
    return False


class ProgressTaskPanel:
    """``Gui.Control`` task panel: title, progress bar, stage, elapsed time.

    ``on_cancel`` is called (once) when the user presses Cancel (or Esc);
    the panel then stays open, saying "cancelling", until the builder closes
    it when the work has really stopped (a second Cancel closes it at once).
    """

    def __init__(self, title, on_cancel):
        self._on_cancel = on_cancel
        self._started = time.monotonic()
        self.closed = False
        self.cancelling = False
        self.form = QtGui.QWidget()
        self.form.setObjectName("StripWeaveProgressPanel")
        self.form.setWindowTitle("StripWeave")
        self.form.setWindowIcon(QtGui.QIcon(WORKBENCH_ICON))
        layout = QtGui.QVBoxLayout(self.form)
        self.title = QtGui.QLabel(title)
        self.title.setWordWrap(True)
        self.bar = QtGui.QProgressBar()
        self.bar.setObjectName("StripWeaveProgressBar")
        self.bar.setRange(0, 1000)
        self.bar.setValue(0)
        self.bar.setFormat("%p%")
        self.stage = QtGui.QLabel("starting")
        self.stage.setObjectName("StripWeaveProgressStage")
        self.elapsed = QtGui.QLabel("")
        for w in (self.title, self.bar, self.stage, self.elapsed):
            layout.addWidget(w)
        layout.addStretch(1)

    # -- Gui.Control protocol -------------------------------------------------
    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Cancel)

    def reject(self):
        cb, self._on_cancel = self._on_cancel, None
        if cb is None:  # the second Cancel: the user does not want to wait
            self.closed = True
            return True
        cb()
        self.cancelling = True
        if _is_alive(getattr(self, "form", None)):
            self.stage.setText("cancelling: stopping the build ...")
        return False

    def accept(self):
        return self.reject()

    # -- driven by the builder's timer -------------------------------------------
    def update(self, fraction, stage):
        if self.closed or self.cancelling or not _is_alive(getattr(self, "form", None)):
            return
        self.bar.setValue(int(round(1000 * max(0.0, min(1.0, fraction)))))
        self.stage.setText(stage or "working")
        self.elapsed.setText("{:.1f} s".format(time.monotonic() - self._started))

    def show(self):
        """Open in the task view; False when another task dialog is open."""
        try:
            Gui.Control.showDialog(self)
            return True
        except Exception:
            return False

    def close(self):
        """Close the panel if it is still the open task dialog (it may have
        gone already: Cancel, or another tool closed it)."""
        if self.closed:
            return
        self.closed = True
        form = getattr(self, "form", None)
        if _is_alive(form) and _in_main_window(form) and Gui.Control.activeDialog():
            Gui.Control.closeDialog()


def status_message(text, ms=0):
    try:
        Gui.getMainWindow().statusBar().showMessage(text, ms)
    except Exception:
        pass


def process_events():
    QtGui.QApplication.processEvents(QtCore.QEventLoop.AllEvents, 50)
