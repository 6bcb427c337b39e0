"""Coin nodes of a design's accepted symmetries (paper §5.8): a reflection drawn as a
translucent plane quad through its point, a rotation as its axis line.  Pure pivy + numpy:
no document, no Qt.

    overlay = SymmetryOverlay()
    overlay.set(symmetries, (xmin, ymin, zmin, xmax, ymax, zmax))   # design.md's dicts, model units
    overlay.set([], None)                                            # nothing drawn

Inputs: the symmetries (kind, point, normal | axis) and the part's bounding box, which sizes
the drawing: the plane is the box's section by it (its corners clipped to the box, a quad
spanning it), the axis runs across the box.  Output: ``root``, which the design tool puts in
the view's scene graph while it runs.

Scene graph (node names are a contract used by tests and macros)::

    SoSeparator "StripWeaveSymmetry"
        SoPickStyle UNPICKABLE, SoLightModel BASE_COLOR
        SoSeparator "StripWeaveSymmetryPlanes"
            SoShapeHints, SoMaterial (translucent), SoCoordinate3, SoFaceSet (4 per plane)
        SoSeparator "StripWeaveSymmetryAxes"
            SoBaseColor, SoDrawStyle, SoCoordinate3, SoLineSet (2 per axis)
"""

import numpy as np
from pivy import coin

SYMMETRY_NODE = "StripWeaveSymmetry"
PLANES_NODE = "StripWeaveSymmetryPlanes"
AXES_NODE = "StripWeaveSymmetryAxes"
PLANE_COLOR = (0.15, 0.55, 0.95)
PLANE_TRANSPARENCY = 0.6    # the part stays visible through the plane
AXIS_COLOR = (0.85, 0.1, 0.55)
AXIS_WIDTH = 3.0
# The drawing reaches past the part (a quarter of its size), so it shows beside an opaque part.
MARGIN = 0.25


def _unit(v):
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v)
    return v / n if n > 0 else v


def plane_quad(point, normal, box):
    """Four corners of a square in the plane (point, normal) centred at the box centre's
    projection on it, half-side the box's half-diagonal plus MARGIN: it covers the part's
    section by the plane, whatever the plane's tilt."""
    lo, hi = np.asarray(box[:3], dtype=float), np.asarray(box[3:], dtype=float)
    n = _unit(normal)
    centre = (lo + hi) / 2.0
    centre = centre - np.dot(centre - np.asarray(point, dtype=float), n) * n
    half = np.linalg.norm(hi - lo) / 2.0
    # Half-extent of the box along each in-plane direction: the quad fits the section.
    u = _unit(np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]))
    v = np.cross(n, u)
    extent = (hi - lo) / 2.0
    hu = min(half, float(np.dot(np.abs(u), extent))) * (1 + MARGIN)
    hv = min(half, float(np.dot(np.abs(v), extent))) * (1 + MARGIN)
    return [centre - hu * u - hv * v, centre + hu * u - hv * v, centre + hu * u + hv * v, centre - hu * u + hv * v]


def axis_segment(point, axis, box):
    """The axis line's two ends: through the point, as long as the box's diagonal plus MARGIN,
    centred at the box centre's projection on the axis."""
    lo, hi = np.asarray(box[:3], dtype=float), np.asarray(box[3:], dtype=float)
    a, p = _unit(axis), np.asarray(point, dtype=float)
    centre = p + np.dot((lo + hi) / 2.0 - p, a) * a
    half = np.linalg.norm(hi - lo) / 2.0 * (1 + MARGIN)
    return [centre - half * a, centre + half * a]


class SymmetryOverlay:
    def __init__(self):
        self.root = coin.SoSeparator()
        self.root.setName(SYMMETRY_NODE)
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE   # a click goes through the plane to the part
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        self.root.addChild(pick)
        self.root.addChild(light)

        self.planes = coin.SoSeparator()
        self.planes.setName(PLANES_NODE)
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.UNKNOWN_ORDERING   # both sides lit alike
        material = coin.SoMaterial()
        material.diffuseColor.setValue(*PLANE_COLOR)
        material.emissiveColor.setValue(*PLANE_COLOR)
        material.transparency.setValue(PLANE_TRANSPARENCY)
        self.plane_coords = coin.SoCoordinate3()
        self.plane_faces = coin.SoFaceSet()
        for node in (hints, material, self.plane_coords, self.plane_faces):
            self.planes.addChild(node)

        self.axes = coin.SoSeparator()
        self.axes.setName(AXES_NODE)
        color = coin.SoBaseColor()
        color.rgb.setValue(*AXIS_COLOR)
        style = coin.SoDrawStyle()
        style.lineWidth = AXIS_WIDTH
        self.axis_coords = coin.SoCoordinate3()
        self.axis_lines = coin.SoLineSet()
        for node in (color, style, self.axis_coords, self.axis_lines):
            self.axes.addChild(node)
        self.root.addChild(self.planes)
        self.root.addChild(self.axes)
        self.set([], None)

    def set(self, symmetries, box):
        """Draw ``symmetries`` sized to ``box`` (xmin, ymin, zmin, xmax, ymax, zmax); none
        (or no box) clears the drawing."""
        quads, segments = [], []
        for sym in (symmetries or []) if box is not None else []:
            if sym.get("kind") == "reflection":
                quads.append(plane_quad(sym["point"], sym["normal"], box))
            elif sym.get("kind") == "rotation":
                segments.append(axis_segment(sym["point"], sym["axis"], box))
        _fill(self.plane_coords, self.plane_faces, quads)
        _fill(self.axis_coords, self.axis_lines, segments)

    def plane_count(self):
        return self.plane_faces.numVertices.getNum()

    def axis_count(self):
        return self.axis_lines.numVertices.getNum()


def _fill(coords, shape, polygons):
    points = [tuple(float(c) for c in p) for poly in polygons for p in poly]
    if points:
        coords.point.setValues(0, len(points), points)
    coords.point.setNum(len(points))
    if polygons:
        shape.numVertices.setValues(0, len(polygons), [len(p) for p in polygons])
    shape.numVertices.setNum(len(polygons))
