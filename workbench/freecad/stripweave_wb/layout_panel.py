"""Task panel of the "Edit layout vertices" tool (paper §7, manual
primalization): how to use it, what was placed by hand, and the layout.

* a table of the Design's pins (vertices placed by hand) and edge routes
  (edges routed by hand through a point), each with its point as tooltip
  and a Remove button (one undoable transaction each: layout_pins.remove_pin,
  layout_pins.remove_route);
* Clear all (layout_pins.clear_pins, undoable);
* the layout's state: valid, clean, patches, and its defects in words;
* the status line (the tool's last message) and Close, which ends the tool.

Widgets only: every action goes back to the tool (layout_tool.py), which
refreshes the panel from the Design and the Layout."""

from PySide import QtCore, QtGui

from . import WORKBENCH_ICON
from .tool_panel import ToolPanel

HELP = ("Drag a vertex within its region: it stays where you release it. Drag an edge: it is "
        "routed through the point where you release it. Esc or Close ends the tool.")
COLUMNS = ("", "placed by hand")   # Remove first: visible in a narrow panel


def _point_text(p):
    return "({})".format(", ".join("{:.6g}".format(float(c)) for c in p))


class LayoutPanel(ToolPanel):
    def __init__(self, tool, label):
        self.tool = tool
        self.form = QtGui.QWidget()
        self.form.setObjectName("StripWeaveLayoutPanel")
        self.form.setWindowTitle("Edit layout vertices")
        self.form.setWindowIcon(QtGui.QIcon(WORKBENCH_ICON))
        layout = QtGui.QVBoxLayout(self.form)
        layout.addWidget(QtGui.QLabel("<b>{}</b>".format(label)))
        help_label = QtGui.QLabel(HELP)
        help_label.setWordWrap(True)
        layout.addWidget(help_label)

        self.table = QtGui.QTableWidget(0, len(COLUMNS))
        self.table.setObjectName("StripWeaveHandPlacedTable")
        self.table.setHorizontalHeaderLabels(list(COLUMNS))
        self.table.verticalHeader().setVisible(False)
        self.table.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        self.table.setSelectionMode(QtGui.QAbstractItemView.NoSelection)
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Preferred)
        self.table.setMaximumHeight(170)
        self.table.setMinimumHeight(90)
        layout.addWidget(self.table)
        self.clear_all = QtGui.QPushButton("Clear all")
        self.clear_all.setObjectName("StripWeaveClearHandPlaced")
        self.clear_all.setToolTip("Every vertex and edge back to its automatic place (undoable)")
        self.clear_all.clicked.connect(lambda: self.tool.clear_all())
        layout.addWidget(self.clear_all)

        self.state = QtGui.QLabel("")
        self.state.setObjectName("StripWeaveLayoutState")
        self.state.setWordWrap(True)
        self.state.setFrameShape(QtGui.QFrame.StyledPanel)
        layout.addWidget(self.state)
        self.status = QtGui.QLabel("")
        self.status.setObjectName("StripWeaveLayoutToolStatus")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        layout.addStretch(1)
        self.remove_buttons = []   # per row: (kind, index, button)
        self._shown = None

    # -- filled in by the tool ------------------------------------------------------------
    def refresh(self, pins, routes, state):
        """Rows for ``pins`` ([[x, y, z]]) and ``routes`` ([{"through",
        "across"}]); ``state``: one line on the layout.  Rebuilt only when
        something changed (a rebuilt button under the pointer would lose its
        click)."""
        shown = (repr(pins), repr(routes), state)
        if shown == self._shown:
            return
        self._shown = shown
        self.state.setText(state)
        rows = [("pin", i, "vertex pin", p) for i, p in enumerate(pins)]
        rows += [("route", i, "edge route", r["through"]) for i, r in enumerate(routes)]
        self.table.setRowCount(len(rows))
        self.remove_buttons = []
        for row, (kind, index, words, point) in enumerate(rows):
            button = QtGui.QPushButton("Remove")
            button.setObjectName("StripWeaveRemove_{}_{}".format(kind, index))
            button.clicked.connect(lambda checked=False, k=kind, i=index: self.tool.remove(k, i))
            self.table.setCellWidget(row, 0, button)
            # The point in the tooltip: the narrow combo view would cut it off.
            item = QtGui.QTableWidgetItem("{} {}".format(words, index + 1))
            item.setToolTip("{} {} at {}".format(words, index + 1, _point_text(point)))
            self.table.setItem(row, 1, item)
            self.remove_buttons.append((kind, index, button))
        self.table.resizeColumnToContents(0)
        self.clear_all.setEnabled(bool(rows))


def layout_state(layout_obj, layout=None):
    """One line on a Layout object: valid, clean, patches, defects, and the
    hand routes its layout.json (``layout``, parsed here if not given) refused."""
    if layout_obj is None:
        return ""
    status = getattr(layout_obj, "Status", "")
    if status.startswith("computing"):
        return "layout: computing ..."
    if not layout_obj.Valid:
        return "layout: not valid (red regions: add strips)"
    from .layout_model import route_problems
    defects = list(layout_obj.Defects or [])
    words = "clean" if layout_obj.Clean else "not clean: {}".format("; ".join(defects[:2]) or "see the report")
    refused = route_problems(layout if layout is not None else layout_obj.Proxy.layout(layout_obj))
    return "layout: {} patches, {}".format(layout_obj.PatchCount, words) + "".join("\n" + p for p in refused)
