"""Coin scene-graph overlay for feature curves and boundary loops.

Pure pivy: no document, no Qt.  The view provider owns one :class:`Overlay`
and feeds it polylines as (points, counts): ``points`` is a flat list of
(x, y, z) and ``counts[i]`` the number of points of polyline i.

Scene graph (node names are a contract used by tests and macros)::

    SoSeparator "StripWeaveOverlay"
        SoPickStyle UNPICKABLE          overlay never steals picks
        SoLightModel BASE_COLOR         flat, unlit colour
        SoDepthBuffer LEQUAL, range [0, 0.9995]: drawn over the source's edges
        SoSeparator "StripWeaveFeatures"
            SoBaseColor, SoDrawStyle, SoCoordinate3, SoLineSet
        SoSeparator "StripWeaveBoundaries"
            SoBaseColor, SoDrawStyle, SoCoordinate3, SoLineSet
"""

from pivy import coin

OVERLAY_NODE = "StripWeaveOverlay"
FEATURES_NODE = "StripWeaveFeatures"
BOUNDARIES_NODE = "StripWeaveBoundaries"

FEATURE_COLOR = (0.95, 0.35, 0.05)    # orange
BOUNDARY_COLOR = (0.05, 0.45, 0.95)   # blue
LINE_WIDTH = 5.0
DEPTH_RANGE_FAR = 0.9995


class PolylineSet:
    """A named SoSeparator holding many polylines of one colour."""

    def __init__(self, name, color, line_width):
        self.root = coin.SoSeparator()
        self.root.setName(name)
        self.color = coin.SoBaseColor()
        self.style = coin.SoDrawStyle()
        self.style.style = coin.SoDrawStyle.LINES
        self.coords = coin.SoCoordinate3()
        self.lines = coin.SoLineSet()
        self.lines.numVertices.setNum(0)
        for node in (self.color, self.style, self.coords, self.lines):
            self.root.addChild(node)
        self.set_color(color)
        self.set_line_width(line_width)

    def set_color(self, rgb):
        self.color.rgb.setValue(*[float(c) for c in rgb[:3]])

    def set_line_width(self, width):
        self.style.lineWidth = float(width)

    def set_polylines(self, points, counts):
        """Replace all polylines. ``points``: sequence of (x,y,z) or an (n,3)
        array; ``counts``: points per polyline (each >= 2)."""
        counts = [int(c) for c in counts]
        n = len(points)
        if sum(counts) != n or any(c < 2 for c in counts):
            raise ValueError("polyline counts do not match the points")
        if n:
            pts = points.tolist() if hasattr(points, "tolist") else [tuple(p) for p in points]
            self.coords.point.setValues(0, n, pts)
        self.coords.point.setNum(n)
        if counts:
            self.lines.numVertices.setValues(0, len(counts), counts)
        self.lines.numVertices.setNum(len(counts))

    def polyline_count(self):
        return self.lines.numVertices.getNum()

    def point_count(self):
        return self.coords.point.getNum()


class Overlay:
    def __init__(self, feature_color=FEATURE_COLOR, boundary_color=BOUNDARY_COLOR,
                 line_width=LINE_WIDTH):
        self.root = coin.SoSeparator()
        self.root.setName(OVERLAY_NODE)
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        depth = coin.SoDepthBuffer()
        depth.function = coin.SoDepthBuffer.LEQUAL
        # Pull the curves slightly towards the viewer: they lie exactly on the
        # source's faces and edges and would z-fight with them (glPolygonOffset
        # does not apply to lines).  Small enough not to show hidden curves.
        depth.range.setValue(0.0, DEPTH_RANGE_FAR)
        for node in (pick, light, depth):
            self.root.addChild(node)
        self.features = PolylineSet(FEATURES_NODE, feature_color, line_width)
        self.boundaries = PolylineSet(BOUNDARIES_NODE, boundary_color, line_width)
        self.root.addChild(self.features.root)
        self.root.addChild(self.boundaries.root)


def find_nodes(root, name):
    """All nodes called ``name`` below ``root`` (also inside inactive switches)."""
    search = coin.SoSearchAction()
    search.setName(coin.SbName(name))
    search.setInterest(coin.SoSearchAction.ALL)
    search.setSearchingAll(True)
    search.apply(root)
    paths = search.getPaths()
    return [paths[i].getTail() for i in range(paths.getLength())]


def line_set_of(separator):
    """The SoLineSet child of a :class:`PolylineSet` separator found by name."""
    for i in range(separator.getNumChildren()):
        child = separator.getChild(i)
        if child.isOfType(coin.SoLineSet.getClassTypeId()):
            return child
    return None
