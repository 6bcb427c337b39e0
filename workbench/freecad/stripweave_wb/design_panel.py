"""Task panel of the "Design strips" tool: how to use it, the current
proposal, the strips (length, widths, area %) with Remove buttons, the
singularity counts and fold-overs, and Close.  Widgets only: every action
goes back to the tool (design_tool.py)."""

from PySide import QtCore, QtGui

from . import WORKBENCH_ICON

HELP = ("Hover the surface: the best strip through the cursor.\n"
        "Ctrl+wheel: browse alternative strips.\n"
        "Click: add the strip.   Esc: close.")
COLUMNS = ("#", "", "length", "width L / R", "area %")  # Remove second: visible in a narrow panel
REMOVE_COLUMN = 1


def _fmt(x, digits=3):
    try:
        return "{:.{}g}".format(float(x), digits + 1)
    except (TypeError, ValueError):
        return "-"


class DesignPanel:
    def __init__(self, tool, label):
        self.tool = tool
        self.form = QtGui.QWidget()
        self.form.setObjectName("StripWeaveDesignPanel")
        self.form.setWindowTitle("Design strips")
        self.form.setWindowIcon(QtGui.QIcon(WORKBENCH_ICON))
        layout = QtGui.QVBoxLayout(self.form)

        self.title = QtGui.QLabel("<b>{}</b>".format(label))
        help_label = QtGui.QLabel(HELP)
        help_label.setWordWrap(True)
        layout.addWidget(self.title)
        layout.addWidget(help_label)

        box = QtGui.QGroupBox("Proposal")
        bl = QtGui.QVBoxLayout(box)
        self.proposal = QtGui.QLabel("move the cursor over the surface")
        self.proposal.setObjectName("StripWeaveProposal")
        self.proposal.setWordWrap(True)
        bl.addWidget(self.proposal)
        layout.addWidget(box)

        box = QtGui.QGroupBox("Strips")
        bl = QtGui.QVBoxLayout(box)
        self.table = QtGui.QTableWidget(0, len(COLUMNS))
        self.table.setObjectName("StripWeaveStripTable")
        self.table.setHorizontalHeaderLabels(list(COLUMNS))
        self.table.verticalHeader().setVisible(False)
        self.table.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        self.table.setSelectionMode(QtGui.QAbstractItemView.NoSelection)
        self.table.horizontalHeader().setStretchLastSection(True)
        # never wider than the task view (the combo view is often narrow): scroll instead
        self.table.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Expanding)
        self.table.setMinimumHeight(120)
        bl.addWidget(self.table)
        self.singularities = QtGui.QLabel("")
        self.singularities.setWordWrap(True)
        self.singularities.setObjectName("StripWeaveSingularityCounts")
        self.fold_overs = QtGui.QLabel("")
        bl.addWidget(self.singularities)
        bl.addWidget(self.fold_overs)
        layout.addWidget(box)

        self.status = QtGui.QLabel("")
        self.status.setObjectName("StripWeaveDesignStatus")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        layout.addStretch(1)
        self.remove_buttons = []

    # -- Gui.Control protocol -----------------------------------------------------------
    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        self.tool.close(from_panel=True)
        return True

    def accept(self):
        return self.reject()

    # -- filled in by the tool ------------------------------------------------------------
    def set_proposal(self, text):
        self.proposal.setText(text)

    def set_status(self, text, error=False):
        self.status.setStyleSheet("color: #c92a2a;" if error else "")
        self.status.setText(text)

    def set_busy(self, busy):
        """No removals while a strip is being added (it is based on the
        current design)."""
        for b in self.remove_buttons:
            b.setEnabled(not busy)

    def refresh(self, summary):
        """Fill the strip table and counts from a Design ``Summary`` dict."""
        strips = summary.get("strips", [])
        self.table.setRowCount(len(strips))
        self.remove_buttons = []
        for i, s in enumerate(strips):
            values = (str(i + 1), _fmt(s.get("length")),
                      "{} / {}".format(_fmt(s.get("width_left"), 2), _fmt(s.get("width_right"), 2)),
                      "{:.1f}".format(100.0 * float(s.get("area_fraction", 0.0))))
            for col, text in zip((0, 2, 3, 4), values):
                item = QtGui.QTableWidgetItem(text)
                item.setTextAlignment(QtCore.Qt.AlignRight | QtCore.Qt.AlignVCenter)
                if col == 0:
                    item.setToolTip("{} loop; sides stop at: {} / {}".format(
                        "closed" if s.get("closed", True) else "open (dual curve ending on boundaries)",
                        s.get("stop_left", "?"), s.get("stop_right", "?")))
                self.table.setItem(i, col, item)
            button = QtGui.QPushButton("Remove")
            button.setObjectName("StripWeaveRemoveStrip{}".format(i + 1))
            button.setToolTip("Remove strip {} (undoable)".format(i + 1))
            button.clicked.connect(lambda checked=False, index=i: self.tool.remove(index))
            self.table.setCellWidget(i, REMOVE_COLUMN, button)
            self.remove_buttons.append(button)
        self.table.resizeColumnsToContents()
        counts = summary.get("singularity_counts") or {"+1/4": 0, "-1/4": 0, "other": 0}
        self.singularities.setText("Singularities  +1/4: {}   \u22121/4: {}   other: {}".format(
            counts.get("+1/4", 0), counts.get("-1/4", 0), counts.get("other", 0)))
        self.fold_overs.setText("Fold-overs  {}".format(summary.get("fold_overs", 0)))
        error = summary.get("error")
        if error:
            self.set_status("{} (strips after it are not shown; remove or re-import it)".format(error), True)
        elif summary.get("warnings"):
            self.set_status("Warning: " + "\nWarning: ".join(summary["warnings"]), True)
        requested = summary.get("requested_strips", len(strips))
        if requested > len(strips):
            for i in range(len(strips), requested):  # the failed strips can be removed too
                self.table.insertRow(i)
                self.table.setItem(i, 0, QtGui.QTableWidgetItem(str(i + 1)))
                self.table.setItem(i, 2, QtGui.QTableWidgetItem("failed"))
                button = QtGui.QPushButton("Remove")
                button.setObjectName("StripWeaveRemoveStrip{}".format(i + 1))
                button.clicked.connect(lambda checked=False, index=i: self.tool.remove(index))
                self.table.setCellWidget(i, REMOVE_COLUMN, button)
                self.remove_buttons.append(button)

    def row_count(self):
        return self.table.rowCount()
