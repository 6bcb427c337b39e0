"""The workbench's defaults, kept in FreeCAD's parameter tree, and the
preferences page that edits them (Edit > Preferences > StripWeave).

Parameters (``User parameter:BaseApp/Preferences/Mod/StripWeave``)::

    TargetTriangles  int     solver-mesh size Prepare surface builds (30000)
    FeatureAngle     float   dihedral angle, degrees, above which an edge is a feature (30)
    Tolerance        float   fitting tolerance of NURBS patches, model units; 0: the
                             library's own (a fraction of the part's size)
    BoundaryMode     string  how a New design's dual curves meet open boundaries:
                             "aligned" or "trimmed"
    AutoWeaveMaxStrips int   strips at most after Auto weave (the user's included); 0:
                             automatic, 40 beyond the cuts the part's handles and holes
                             ask for (stripweave.weave.WeaveOptions.max_strips)
    AutoWeaveCreasePairs bool  Auto weave tries pairs of crossing loops where no single
                             loop parts a crease region (WeaveOptions.crease_pairs; off:
                             README, "Pairs of loops")

Readers take these at the moment a command runs (no caching), so a change on
the page applies to the next command.  No Qt at import: the page class is
built on demand (:func:`register_page`, GUI only).
"""

import FreeCAD as App

PARAM_PATH = "User parameter:BaseApp/Preferences/Mod/StripWeave"
DEFAULT_TARGET_TRIANGLES = 30000
DEFAULT_FEATURE_ANGLE_DEG = 30.0
DEFAULT_TOLERANCE = 0.0
BOUNDARY_MODES = ("aligned", "trimmed")
DEFAULT_AUTO_WEAVE_MAX_STRIPS = 0
DEFAULT_AUTO_WEAVE_CREASE_PAIRS = False


def group():
    return App.ParamGet(PARAM_PATH)


def target_triangles():
    return max(100, int(group().GetInt("TargetTriangles", DEFAULT_TARGET_TRIANGLES)))


def feature_angle():
    return float(group().GetFloat("FeatureAngle", DEFAULT_FEATURE_ANGLE_DEG))


def tolerance():
    """The fitting tolerance, or None for the library's default."""
    value = float(group().GetFloat("Tolerance", DEFAULT_TOLERANCE))
    return value if value > 0 else None


def boundary_mode():
    mode = group().GetString("BoundaryMode", BOUNDARY_MODES[0])
    return mode if mode in BOUNDARY_MODES else BOUNDARY_MODES[0]


def auto_weave_max_strips():
    """The strip cap of Auto weave, or None for the automatic one (by the part's topology)."""
    value = int(group().GetInt("AutoWeaveMaxStrips", DEFAULT_AUTO_WEAVE_MAX_STRIPS))
    return value if value > 0 else None


def auto_weave_crease_pairs():
    """Whether Auto weave tries pairs of crossing loops on crease regions."""
    return bool(group().GetBool("AutoWeaveCreasePairs", DEFAULT_AUTO_WEAVE_CREASE_PAIRS))


def save(target_triangles=None, feature_angle=None, tolerance=None, boundary_mode=None, max_strips=None,
         crease_pairs=None):
    """Write the given defaults (None: leave as is)."""
    g = group()
    if crease_pairs is not None:
        g.SetBool("AutoWeaveCreasePairs", bool(crease_pairs))
    if max_strips is not None:
        g.SetInt("AutoWeaveMaxStrips", int(max_strips))
    if target_triangles is not None:
        g.SetInt("TargetTriangles", int(target_triangles))
    if feature_angle is not None:
        g.SetFloat("FeatureAngle", float(feature_angle))
    if tolerance is not None:
        g.SetFloat("Tolerance", float(tolerance))
    if boundary_mode is not None:
        if boundary_mode not in BOUNDARY_MODES:
            raise ValueError("StripWeave: boundary mode must be one of {}, got {!r}".format(
                ", ".join(BOUNDARY_MODES), boundary_mode))
        g.SetString("BoundaryMode", boundary_mode)


def _page_class():
    from PySide import QtGui

    class PreferencesPage:
        """Edit > Preferences > StripWeave: FreeCAD calls loadSettings when
        the dialog opens and saveSettings on OK / Apply."""

        def __init__(self, parent=None):
            self.form = QtGui.QWidget(parent)
            self.form.setObjectName("StripWeavePreferences")
            self.form.setWindowTitle("StripWeave")
            layout = QtGui.QFormLayout(self.form)
            self.triangles = QtGui.QSpinBox()
            self.triangles.setObjectName("TargetTriangles")
            self.triangles.setRange(100, 10000000)
            self.triangles.setSingleStep(1000)
            self.angle = QtGui.QDoubleSpinBox()
            self.angle.setObjectName("FeatureAngle")
            self.angle.setRange(0.0, 180.0)
            self.angle.setSuffix(" deg")
            self.tolerance = QtGui.QDoubleSpinBox()
            self.tolerance.setObjectName("Tolerance")
            self.tolerance.setDecimals(4)
            self.tolerance.setRange(0.0, 1e6)
            self.tolerance.setSpecialValueText("automatic")
            self.boundary = QtGui.QComboBox()
            self.boundary.setObjectName("BoundaryMode")
            self.boundary.addItems(list(BOUNDARY_MODES))
            self.max_strips = QtGui.QSpinBox()
            self.max_strips.setObjectName("AutoWeaveMaxStrips")
            self.max_strips.setRange(0, 1000)
            self.max_strips.setSpecialValueText("automatic")
            layout.addRow("Target triangles (Prepare surface)", self.triangles)
            layout.addRow("Feature angle", self.angle)
            layout.addRow("Patch fitting tolerance", self.tolerance)
            layout.addRow("Boundary mode (New design)", self.boundary)
            self.crease_pairs = QtGui.QCheckBox("Pairs of crossing loops on crease regions (slower)")
            self.crease_pairs.setObjectName("AutoWeaveCreasePairs")
            layout.addRow("Strips at most (Auto weave)", self.max_strips)
            layout.addRow("Auto weave", self.crease_pairs)

        def loadSettings(self):
            self.triangles.setValue(target_triangles())
            self.angle.setValue(feature_angle())
            self.tolerance.setValue(tolerance() or 0.0)
            self.boundary.setCurrentIndex(BOUNDARY_MODES.index(boundary_mode()))
            self.max_strips.setValue(auto_weave_max_strips() or 0)
            self.crease_pairs.setChecked(auto_weave_crease_pairs())

        def saveSettings(self):
            save(self.triangles.value(), self.angle.value(), self.tolerance.value(),
                 self.boundary.currentText(), self.max_strips.value(), self.crease_pairs.isChecked())

    return PreferencesPage


def register_page():
    """Add the page to Edit > Preferences (GUI); returns the page class."""
    import FreeCADGui as Gui
    cls = _page_class()
    Gui.addPreferencePage(cls, "StripWeave")
    return cls
