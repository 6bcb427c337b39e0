"""Task panel of the "Design strips" tool: how to use it and the current
proposal; then tabs (the panel fits the default combo view):

* Strips: the strips (length, widths, area %) with Remove buttons, the
  singularity counts and fold-overs; a selected row's anchors are listed in
* Anchors: with their direction flags; Delete anchor, Make positional;
* Layout: the regions by colour (red, crease, orange, yellow; §4.2), each
  with where it is, and the layout's defects (region_list.py);
* Options: the compatibility band and the boundary mode of the design,
  applied to the running session (each change one undoable transaction),
  and its symmetry (paper §5.8): None, or Detect (the surface's reflections
  and rotations, each with its max error in model units), a checkbox per
  symmetry to accept it (stored in the design, one undoable transaction;
  the tool draws the accepted ones and adds every strip with its images).
  On the Options tab, not a tab of its own: five side tabs are taller than
  the default combo view, which would then scroll;

and the status line and Close.  Widgets only: every action goes back to
the tool (design_tool.py)."""

from PySide import QtCore, QtGui

from . import WORKBENCH_ICON
from .tool_panel import ToolPanel

HELP = ("Hover: the best strip. Ctrl+wheel: others. Click: add it. Drag: give its direction. "
        "Drag a strip: move it. Shift+click, Enter: several anchors. Esc: close.")
COLUMNS = ("#", "", "length", "width L / R", "area %")  # Remove second: visible in a narrow panel
REMOVE_COLUMN = 1
TABS = ("Strips", "Anchors", "Layout", "Options")
SYMMETRY_MODES = ("None", "Detect")
WHOLE_STRIP = "whole strip"   # the band's special value (0): the paper's compatibility (§6.2)
BOUNDARY_MODES = ("aligned", "trimmed")


def _fmt(x, digits=3):
    try:
        return "{:.{}g}".format(float(x), digits + 1)
    except (TypeError, ValueError):
        return "-"


def _compact(widget, height):
    """Never wider than the task view (scroll instead), at most ``height`` high."""
    widget.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Preferred)
    widget.setMaximumHeight(height)
    return widget


def _vec(v):
    return "({})".format(", ".join(_fmt(c) for c in v))


def symmetry_text(sym):
    """One line: the kind, where, and the max error in model units."""
    if sym.get("kind") == "reflection":
        where = "reflection in the plane through {} normal {}".format(_vec(sym["point"]), _vec(sym["normal"]))
    else:
        where = "rotation of order {} about {} through {}".format(sym.get("order"), _vec(sym["axis"]),
                                                                 _vec(sym["point"]))
    error = sym.get("max_error")
    return where + ("; max error {}".format(_fmt(error, 2)) if error is not None else "")


def _same_symmetry(a, b):
    keys = ("kind", "point", "normal", "axis", "order")
    return all(a.get(k) == b.get(k) for k in keys)


class DesignPanel(ToolPanel):
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
        self.proposal = QtGui.QLabel("move the cursor over the surface")
        self.proposal.setObjectName("StripWeaveProposal")
        self.proposal.setWordWrap(True)
        self.proposal.setFrameShape(QtGui.QFrame.StyledPanel)
        layout.addWidget(self.proposal)

        self.tabs = QtGui.QTabWidget()
        self.tabs.setObjectName("StripWeaveDesignTabs")
        self.tabs.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Preferred)
        # Tabs on the side: four names never fit across the narrow combo view (the
        # bar would scroll and hide some).
        self.tabs.setTabPosition(QtGui.QTabWidget.West)
        for name, page in zip(TABS, (self._strip_page(), self._anchor_box(), self._layout_page(),
                                     self._options_page())):
            self.tabs.addTab(page, name)
        bar = self.tabs.tabBar()
        bar.setUsesScrollButtons(False)
        bar.setElideMode(QtCore.Qt.ElideNone)
        self.tabs.setMinimumHeight(bar.sizeHint().height() + 8)   # every tab in sight
        layout.addWidget(self.tabs)

        self.status = QtGui.QLabel("")
        self.status.setObjectName("StripWeaveDesignStatus")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        layout.addStretch(1)
        self.remove_buttons = []
        self.anchors = []             # per strip its anchors, (x,y,z[,dx,dy,dz]) lists
        self._show_anchors()

    def _strip_page(self):
        page = QtGui.QWidget()
        bl = QtGui.QVBoxLayout(page)
        self.table = QtGui.QTableWidget(0, len(COLUMNS))
        self.table.setObjectName("StripWeaveStripTable")
        self.table.setHorizontalHeaderLabels(list(COLUMNS))
        self.table.verticalHeader().setVisible(False)
        self.table.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        self.table.setSelectionMode(QtGui.QAbstractItemView.SingleSelection)
        self.table.setSelectionBehavior(QtGui.QAbstractItemView.SelectRows)
        self.table.setToolTip("Select a strip to edit its anchors (Anchors tab)")
        self.table.itemSelectionChanged.connect(self._show_anchors)
        self.table.horizontalHeader().setStretchLastSection(True)
        _compact(self.table, 160).setMinimumHeight(110)
        bl.addWidget(self.table)
        self.singularities = QtGui.QLabel("")
        self.singularities.setWordWrap(True)
        self.singularities.setObjectName("StripWeaveSingularityCounts")
        self.fold_overs = QtGui.QLabel("")
        bl.addWidget(self.singularities)
        bl.addWidget(self.fold_overs)
        return page

    def _layout_page(self):
        page = QtGui.QWidget()
        bl = QtGui.QVBoxLayout(page)
        self.region_counts = QtGui.QLabel("regions: not computed yet")
        self.region_counts.setObjectName("StripWeaveRegionCounts")
        self.region_counts.setWordWrap(True)
        bl.addWidget(self.region_counts)
        self.region_list = _compact(QtGui.QListWidget(), 160)
        self.region_list.setObjectName("StripWeaveRegionList")
        self.region_list.setWordWrap(True)
        bl.addWidget(self.region_list)
        return page

    def _options_page(self):
        page = QtGui.QWidget()
        fl = QtGui.QFormLayout(page)
        fl.setRowWrapPolicy(QtGui.QFormLayout.WrapAllRows)   # labels above: the view is narrow
        self.band = QtGui.QDoubleSpinBox()
        self.band.setObjectName("StripWeaveCompatibilityBand")
        self.band.setDecimals(3)
        self.band.setRange(0.0, 1e6)
        self.band.setSpecialValueText(WHOLE_STRIP)
        self.band.setKeyboardTracking(False)   # applied on Enter, an arrow or leaving the field
        self.band.setToolTip("How far from its loop (model units) a strip refuses parallel loops; "
                             "'whole strip' (0) is the paper's. A finite band allows denser layouts.")
        self.band.valueChanged.connect(self._band_changed)
        fl.addRow("Compatibility band", self.band)
        self.boundary = QtGui.QComboBox()
        self.boundary.setObjectName("StripWeaveBoundaryMode")
        self.boundary.addItems(list(BOUNDARY_MODES))
        self.boundary.setToolTip("Dual curves at open boundaries: aligned (run along them) or trimmed (end on them)")
        self.boundary.currentIndexChanged.connect(self._boundary_changed)
        fl.addRow("Boundary", self.boundary)
        self._symmetry_rows(fl)
        return page

    def _symmetry_rows(self, fl):
        self.symmetry_mode = QtGui.QComboBox()
        self.symmetry_mode.setObjectName("StripWeaveSymmetryMode")
        self.symmetry_mode.addItems(list(SYMMETRY_MODES))
        self.symmetry_mode.setToolTip("None: strips are added alone. Detect: find the part's mirror planes and "
                                      "rotation axes; tick one to add every strip with its symmetric images")
        self.symmetry_mode.activated.connect(self._symmetry_mode_chosen)
        fl.addRow("Symmetry", self.symmetry_mode)
        self.symmetry_list = _compact(QtGui.QListWidget(), 90)
        self.symmetry_list.setObjectName("StripWeaveSymmetryList")
        self.symmetry_list.setWordWrap(True)
        self.symmetry_list.itemChanged.connect(self._symmetry_ticked)
        fl.addRow(self.symmetry_list)
        self.symmetries = []          # the symmetries listed, design.md's dicts

    def _symmetry_mode_chosen(self, index):
        if index == 0:
            self.symmetries = []   # nothing listed: the refresh that follows lists nothing
            self.tool.set_symmetry([])
            self.show_symmetries([], [])
        else:
            found = self.tool.detect_symmetry()
            self.show_symmetries(found, self.tool.accepted_symmetry())

    def _symmetry_ticked(self, _item):
        # After the signal: accepting refreshes the panel, which rebuilds this list (the
        # item that signals would be deleted inside its own signal).
        ticked = [s for s, row in zip(self.symmetries, range(self.symmetry_list.count()))
                  if self.symmetry_list.item(row).checkState() == QtCore.Qt.Checked]
        QtCore.QTimer.singleShot(0, lambda: self.tool.set_symmetry(ticked))

    def show_symmetries(self, found, accepted):
        """List ``found`` and the ``accepted`` symmetries (those ticked; an accepted one not
        found, e.g. from an imported design, is listed too)."""
        listed = list(found) + [a for a in accepted if not any(_same_symmetry(a, f) for f in found)]
        self.symmetries = listed
        self.symmetry_list.blockSignals(True)
        self.symmetry_list.clear()
        for sym in listed:
            item = QtGui.QListWidgetItem(symmetry_text(sym))
            item.setFlags(item.flags() | QtCore.Qt.ItemIsUserCheckable)
            item.setCheckState(QtCore.Qt.Checked if any(_same_symmetry(sym, a) for a in accepted)
                               else QtCore.Qt.Unchecked)
            self.symmetry_list.addItem(item)
        if found is not None and not listed and self.symmetry_mode.currentIndex() == 1:
            self.symmetry_list.addItem("no symmetry found within 1e-3 of the diagonal")
        self.symmetry_list.blockSignals(False)
        self.symmetry_mode.blockSignals(True)
        if listed:   # an accepted symmetry (undo, an imported design) shows as Detect's
            self.symmetry_mode.setCurrentIndex(1)
        self.symmetry_mode.blockSignals(False)

    def set_accepted_symmetry(self, accepted):
        """The design's accepted symmetries changed (undo, import): tick what it holds."""
        self.show_symmetries([s for s in self.symmetries], accepted)

    def _band_changed(self, value):
        self.tool.set_options(compatibility_band=float(value) if value > 0 else None)

    def _boundary_changed(self, index):
        if 0 <= index < len(BOUNDARY_MODES):
            self.tool.set_options(boundary=BOUNDARY_MODES[index])

    def _anchor_box(self):
        """The selected strip's anchors (select a strip row above)."""
        box = QtGui.QWidget()
        box.setObjectName("StripWeaveAnchorBox")
        bl = QtGui.QVBoxLayout(box)
        self.anchor_list = QtGui.QListWidget()
        self.anchor_list.setObjectName("StripWeaveAnchorList")
        _compact(self.anchor_list, 120)
        self.anchor_list.setWordWrap(True)
        self.anchor_list.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        self.anchor_title = QtGui.QLabel("")
        self.anchor_title.setWordWrap(True)
        bl.addWidget(self.anchor_title)
        bl.addWidget(self.anchor_list)
        self.anchor_list.itemSelectionChanged.connect(self._enable_anchor_buttons)
        row = QtGui.QVBoxLayout()
        self.delete_anchor = QtGui.QPushButton("Delete anchor")
        self.delete_anchor.setObjectName("StripWeaveDeleteAnchor")
        self.delete_anchor.setToolTip("Delete the selected anchor; the strip is derived again (undoable)")
        self.delete_anchor.clicked.connect(lambda: self._anchor_action(self.tool.delete_anchor))
        self.positional = QtGui.QPushButton("Make positional")
        self.positional.setObjectName("StripWeaveMakePositional")
        self.positional.setToolTip("Drop the selected anchor's direction (undoable)")
        self.positional.clicked.connect(lambda: self._anchor_action(self.tool.make_positional))
        row.addWidget(self.delete_anchor)
        row.addWidget(self.positional)
        bl.addLayout(row)
        return box

    def selected_strip(self):
        rows = {i.row() for i in self.table.selectedIndexes()}
        return min(rows) if rows else None

    def selected_anchor(self):
        row = self.anchor_list.currentRow()
        return row if row >= 0 and self.anchor_list.currentItem() is not None \
            and self.anchor_list.currentItem().isSelected() else None

    def _show_anchors(self):
        strip = self.selected_strip()
        anchors = self.anchors[strip] if strip is not None and strip < len(self.anchors) else []
        self.anchor_title.setText("select a strip in Strips" if strip is None else "Strip {}:".format(strip + 1))
        self.anchor_list.clear()
        for k, a in enumerate(anchors):
            where = ", ".join(_fmt(c) for c in a[:3])
            kind = "directional ({})".format(", ".join("{:.2f}".format(c) for c in a[3:])) \
                if len(a) == 6 else "positional"
            self.anchor_list.addItem("{}: ({}) {}".format(k + 1, where, kind))
        self._enable_anchor_buttons()

    def _enable_anchor_buttons(self):
        strip, anchor = self.selected_strip(), self.selected_anchor()
        anchors = self.anchors[strip] if strip is not None and strip < len(self.anchors) else []
        chosen = anchor is not None and anchor < len(anchors)
        self.delete_anchor.setEnabled(chosen and len(anchors) > 1)   # the last one: Remove the strip
        self.positional.setEnabled(chosen and len(anchors[anchor]) == 6)

    def _anchor_action(self, action):
        strip, anchor = self.selected_strip(), self.selected_anchor()
        if strip is not None and anchor is not None:
            action(strip, anchor)

    # -- filled in by the tool ------------------------------------------------------------
    def set_proposal(self, text):
        self.proposal.setText(text)

    def set_busy(self, busy):
        """No removals or anchor edits while a strip is being edited (it is
        based on the current design)."""
        for b in self.remove_buttons:
            b.setEnabled(not busy)
        if busy:
            self.delete_anchor.setEnabled(False)
            self.positional.setEnabled(False)
        else:
            self._enable_anchor_buttons()

    def refresh(self, summary, anchors=None):
        """Fill the strip table and counts from a Design ``Summary`` dict,
        and the anchor list from ``anchors`` (per strip its anchor lists);
        the selected strip stays selected."""
        selected = self.selected_strip()
        self.anchors = list(anchors or [])
        strips = summary.get("strips", [])
        self.table.blockSignals(True)
        self.table.clearSelection()
        # Emptied first: a Remove button replaced in place stayed on screen
        # over column 0 (a click on a row's number removed the strip).
        self.table.setRowCount(0)
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
        if selected is not None and selected < self.table.rowCount():
            self.table.selectRow(selected)
        self.table.blockSignals(False)
        self._show_anchors()

    def set_scale(self, diagonal):
        """The band's precision from the model's size (its bounding-box
        diagonal): 1e-4 of it, steps of 1e-2 of it (a part in metres and one
        in millimetres both get four digits)."""
        import math
        if not diagonal > 0:
            return
        self.band.blockSignals(True)
        self.band.setDecimals(max(0, -int(math.floor(math.log10(diagonal * 1e-4)))))
        self.band.setSingleStep(10.0 ** math.floor(math.log10(diagonal * 1e-2)))
        self.band.blockSignals(False)

    def set_options(self, options):
        """Show the design's options (without applying them again)."""
        band = options.get("compatibility_band")
        boundary = options.get("boundary", "aligned")
        for w in (self.band, self.boundary):
            w.blockSignals(True)
        self.band.setValue(float(band) if band else 0.0)
        if boundary in BOUNDARY_MODES:
            self.boundary.setCurrentIndex(BOUNDARY_MODES.index(boundary))
        for w in (self.band, self.boundary):
            w.blockSignals(False)

    def set_regions(self, regions, error=None):
        """Fill the Layout tab from region_list.compute's dict (None: stale
        or failed, with ``error``)."""
        self.region_list.clear()
        if regions is None:
            self.region_counts.setText("regions: {}".format(error or "being computed ..."))
            return
        counts = regions["counts"]
        self.region_counts.setText("Regions  red {}   crease {}   orange {}   yellow {}   ok {}\n{}".format(
            counts.get("red", 0), counts.get("crease", 0), counts.get("orange", 0), counts.get("yellow", 0),
            counts.get("none", 0), "layout: " + ("clean" if regions["clean"] else "valid, {} defect{}".format(
                len(regions["defects"]), "" if len(regions["defects"]) == 1 else "s")
                if regions["valid"] else "invalid (red regions)")))
        tints = {"red": "#c92a2a", "crease": "#862e9c", "orange": "#d9480f", "yellow": "#e0a800"}
        for r in regions["regions"]:
            item = QtGui.QListWidgetItem(r["text"])
            item.setForeground(QtGui.QBrush(QtGui.QColor(tints.get(r["colour"], "#000000"))))
            self.region_list.addItem(item)
        for line in regions["defects"]:
            self.region_list.addItem("defect: " + line)

    def row_count(self):
        return self.table.rowCount()
