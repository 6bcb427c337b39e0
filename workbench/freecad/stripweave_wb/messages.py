"""Report-view messages and (GUI only) non-blocking message boxes."""

import FreeCAD as App

PREFIX = "StripWeave: "

# Message boxes we opened and that are still visible (kept so that Qt does
# not garbage-collect them; also lets tests find and close them).
_open_boxes = []


def _line(text):
    text = str(text)
    return text if text.endswith("\n") else text + "\n"


def message(text):
    App.Console.PrintMessage(_line(PREFIX + text))


def log(text):
    App.Console.PrintLog(_line(PREFIX + text))


def warning(text):
    App.Console.PrintWarning(_line(PREFIX + text))


def error(text, title="StripWeave", dialog=True):
    """Print ``text`` as an error in the report view and, with the GUI up,
    show it in a message box that does not block the event loop."""
    App.Console.PrintError(_line(PREFIX + text))
    if dialog and App.GuiUp:
        _show_box(title, text)


def _show_box(title, text):
    try:
        import FreeCADGui as Gui
        from PySide import QtCore, QtGui

        box = QtGui.QMessageBox(Gui.getMainWindow())
        box.setIcon(QtGui.QMessageBox.Warning)
        box.setWindowTitle(title)
        box.setText(text)
        box.setObjectName("StripWeaveMessageBox")
        box.setAttribute(QtCore.Qt.WA_DeleteOnClose, True)
        _open_boxes.append(box)

        def _forget(*_args):
            if box in _open_boxes:
                _open_boxes.remove(box)

        box.finished.connect(_forget)
        # open() is window-modal but returns at once: the worker thread's
        # completion (and any test driving the GUI) keeps running.
        box.open()
    except Exception as exc:  # never let a message box take FreeCAD down
        App.Console.PrintLog(PREFIX + "could not show message box: {}\n".format(exc))


def open_message_boxes():
    """The StripWeave message boxes currently open (for tests)."""
    return list(_open_boxes)
