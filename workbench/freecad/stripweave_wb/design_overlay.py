"""Coin nodes of a design: stripes on the surface, loops, singularities, and
the design tool's preview loop.  Pure pivy + numpy: no document, no Qt.

Arrays go to Coin in bulk (``setValues`` on whole fields), never node by
node, and nodes are built once and refilled, so a redraw is cheap.

Scene graph (node names are a contract used by tests and macros)::

    SoSeparator "StripWeaveDesign"
        SoSwitch "StripWeaveStripes"          shaded solver-mesh triangles of all strips,
            SoShapeHints, SoPolygonOffset,    per-vertex colours (stripe_pattern.py),
            SoMaterialBinding, SoMaterial,    lifted off the surface along the normals
            SoNormalBinding, SoNormal,
            SoCoordinate3, SoIndexedFaceSet
        SoSwitch "StripWeaveLoops"            one polyline per strip, its hue, thick
            ... SoMaterial (per part), SoCoordinate3, SoLineSet
        SoSwitch "StripWeaveSingularities"    markers coloured by index
            ... SoMaterial (per vertex), SoCoordinate3, SoMarkerSet

    SoSeparator "StripWeavePreview"           (design tool, in the view's scene graph)
        ... SoBaseColor, SoDrawStyle, SoCoordinate3, SoLineSet, anchor SoMarkerSet
"""

import numpy as np
from pivy import coin

from . import stripe_pattern as pattern

DESIGN_NODE = "StripWeaveDesign"
STRIPES_NODE = "StripWeaveStripes"
LOOPS_NODE = "StripWeaveLoops"
SINGULARITIES_NODE = "StripWeaveSingularities"
PREVIEW_NODE = "StripWeavePreview"

LOOP_WIDTH = 5.0
PREVIEW_WIDTH = 6.0
MARKER_SIZE = 13
# Lines and markers lie on the surface: draw them a little nearer the viewer
# so the shaded part and the stripes do not hide them (see overlay.py).
DEPTH_RANGE_FAR = 0.9990


def _marker_index(size):
    try:
        import FreeCADGui as Gui
        return Gui.getMarkerIndex("CIRCLE_FILLED", int(size))
    except Exception:
        return coin.SoMarkerSet.CIRCLE_FILLED_9_9


def _on_top_prelude(sep):
    """Unpickable, unlit, depth-biased towards the viewer."""
    pick = coin.SoPickStyle()
    pick.style = coin.SoPickStyle.UNPICKABLE
    light = coin.SoLightModel()
    light.model = coin.SoLightModel.BASE_COLOR
    depth = coin.SoDepthBuffer()
    depth.function = coin.SoDepthBuffer.LEQUAL
    depth.range.setValue(0.0, DEPTH_RANGE_FAR)
    for node in (pick, light, depth):
        sep.addChild(node)


def _switch(name):
    sw = coin.SoSwitch()
    sw.setName(name)
    sw.whichChild = coin.SO_SWITCH_ALL
    return sw


def _set_vec3(field, array):
    array = np.asarray(array, dtype=float).reshape(-1, 3)
    n = len(array)
    if n:
        field.setValues(0, n, array.tolist())
    field.setNum(n)


def _set_ints(field, values):
    values = [int(v) for v in values]
    if values:
        field.setValues(0, len(values), values)
    field.setNum(len(values))


class StripesNode:
    """The stripe pattern on the covered solver-mesh triangles."""

    def __init__(self):
        self.root = _switch(STRIPES_NODE)
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.shapeType = coin.SoShapeHints.UNKNOWN_SHAPE_TYPE  # two-sided lighting
        offset = coin.SoPolygonOffset()  # in front of the part's own faces
        offset.factor = -1.0
        offset.units = -2.0
        mbind = coin.SoMaterialBinding()
        mbind.value = coin.SoMaterialBinding.PER_VERTEX_INDEXED
        self.material = coin.SoMaterial()
        self.material.specularColor.setValue(0.15, 0.15, 0.15)
        nbind = coin.SoNormalBinding()
        nbind.value = coin.SoNormalBinding.PER_VERTEX_INDEXED
        self.normals = coin.SoNormal()
        self.coords = coin.SoCoordinate3()
        self.faces = coin.SoIndexedFaceSet()
        for node in (hints, offset, mbind, self.material, nbind, self.normals, self.coords, self.faces):
            self.root.addChild(node)

    def set_mesh(self, vertices, normals, colors, triangles):
        """``triangles``: (m,3) indices into vertices; colours and normals per
        vertex.  Corners at sharp features get their face's normal (a welded
        vertex on a box edge has one normal for two faces)."""
        tris = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
        corner_normals, normal_index = corner_shading(np.asarray(vertices, dtype=float).reshape(-1, 3),
                                                      np.asarray(normals, dtype=float).reshape(-1, 3), tris)
        _set_vec3(self.coords.point, vertices)
        _set_vec3(self.normals.vector, corner_normals)
        _set_vec3(self.material.diffuseColor, colors)
        end = -np.ones((len(tris), 1), dtype=np.int64)
        _set_ints(self.faces.coordIndex, np.hstack([tris, end]).ravel().tolist())
        _set_ints(self.faces.normalIndex, np.hstack([normal_index, end]).ravel().tolist())

    def triangle_count(self):
        return self.faces.coordIndex.getNum() // 4


def corner_shading(vertices, normals, tris, crease_cos=0.866):
    """Normals for shading and their per-corner index: the vertex normal,
    or the face normal where they differ by more than 30 degrees."""
    if len(tris) == 0:
        return normals, np.zeros((0, 3), dtype=np.int64)
    v = vertices[tris]
    fn = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    fn /= np.maximum(np.linalg.norm(fn, axis=1, keepdims=True), 1e-300)
    dots = np.einsum("tcj,tj->tc", normals[tris], fn)
    flip = np.where(dots.sum(axis=1) < 0, -1.0, 1.0)  # face normals on the vertex normals' side
    fn *= flip[:, None]
    dots *= flip[:, None]
    face_index = len(normals) + np.arange(len(tris))[:, None].repeat(3, axis=1)
    return np.vstack([normals, fn]), np.where(dots >= crease_cos, tris, face_index)


class PolylinesNode:
    """Polylines with one colour each (loops), unlit, thick."""

    def __init__(self, name, width):
        self.root = _switch(name)
        sep = coin.SoSeparator()
        _on_top_prelude(sep)
        self.style = coin.SoDrawStyle()
        self.style.lineWidth = float(width)
        mbind = coin.SoMaterialBinding()
        mbind.value = coin.SoMaterialBinding.PER_FACE  # a SoLineSet's "face" is a polyline (a part is a segment)
        self.material = coin.SoMaterial()
        self.coords = coin.SoCoordinate3()
        self.lines = coin.SoLineSet()
        for node in (self.style, mbind, self.material, self.coords, self.lines):
            sep.addChild(node)
        self.root.addChild(sep)

    def set_polylines(self, polylines, colors):
        polylines = [np.asarray(p, dtype=float).reshape(-1, 3) for p in polylines]
        keep = [i for i, p in enumerate(polylines) if len(p) >= 2]
        pts = np.vstack([polylines[i] for i in keep]) if keep else np.zeros((0, 3))
        _set_vec3(self.coords.point, pts)
        _set_ints(self.lines.numVertices, [len(polylines[i]) for i in keep])
        _set_vec3(self.material.diffuseColor, [colors[i] for i in keep] or np.zeros((0, 3)))

    def set_width(self, width):
        self.style.lineWidth = float(width)

    def polyline_count(self):
        return self.lines.numVertices.getNum()


class MarkersNode:
    """Point markers with per-point colours (singularities)."""

    def __init__(self, name, size):
        self.root = _switch(name)
        sep = coin.SoSeparator()
        _on_top_prelude(sep)
        mbind = coin.SoMaterialBinding()
        mbind.value = coin.SoMaterialBinding.PER_VERTEX
        self.material = coin.SoMaterial()
        self.coords = coin.SoCoordinate3()
        self.markers = coin.SoMarkerSet()
        self.markers.markerIndex = _marker_index(size)
        for node in (mbind, self.material, self.coords, self.markers):
            sep.addChild(node)
        self.root.addChild(sep)

    def set_points(self, points, colors):
        _set_vec3(self.coords.point, points)
        _set_vec3(self.material.diffuseColor, colors)
        self.markers.numPoints = len(points)

    def set_size(self, size):
        self.markers.markerIndex = _marker_index(size)

    def point_count(self):
        return self.coords.point.getNum()


class DesignOverlay:
    """All nodes of a Design's view provider (display mode "Stripes")."""

    def __init__(self, loop_width=LOOP_WIDTH, marker_size=MARKER_SIZE):
        self.root = coin.SoSeparator()
        self.root.setName(DESIGN_NODE)
        self.stripes = StripesNode()
        self.loops = PolylinesNode(LOOPS_NODE, loop_width)
        self.singularities = MarkersNode(SINGULARITIES_NODE, marker_size)
        for part in (self.stripes, self.loops, self.singularities):
            self.root.addChild(part.root)

    def show(self, stripes=True, loops=True, singularities=True):
        for part, on in ((self.stripes, stripes), (self.loops, loops), (self.singularities, singularities)):
            part.root.whichChild = coin.SO_SWITCH_ALL if on else coin.SO_SWITCH_NONE

    def set_stripes(self, vertices, normals, triangles, across_list, period, strength, lift):
        """Colour the solver mesh by the strips' stripe patterns; draw only
        the covered triangles, lifted by ``lift`` (model units) along the
        normals so the part's own coarser tessellation does not poke through."""
        colors, covered = pattern.stripe_colors(len(vertices), across_list, period, strength)
        tris = pattern.covered_triangles(triangles, covered)
        self.stripes.set_mesh(vertices + lift * normals, normals, colors, tris)

    def set_loops(self, polylines):
        self.loops.set_polylines(polylines, [pattern.loop_color(i) for i in range(len(polylines))])

    def set_singularities(self, singularities):
        self.singularities.set_points([p for p, _ in singularities],
                                      [pattern.singularity_color(i) for _, i in singularities])


class PreviewOverlay:
    """The design tool's proposal: a highlighted loop and the anchor point."""

    def __init__(self, color=pattern.PREVIEW_COLOR, width=PREVIEW_WIDTH):
        self.root = coin.SoSeparator()
        self.root.setName(PREVIEW_NODE)
        _on_top_prelude(self.root)
        self.color = coin.SoBaseColor()
        self.color.rgb.setValue(*color)
        self.style = coin.SoDrawStyle()
        self.style.lineWidth = float(width)
        self.coords = coin.SoCoordinate3()
        self.lines = coin.SoLineSet()
        self.lines.numVertices.setNum(0)
        anchor_sep = coin.SoSeparator()
        anchor_color = coin.SoBaseColor()
        anchor_color.rgb.setValue(0.0, 0.0, 0.0)
        self.anchor_coords = coin.SoCoordinate3()
        self.anchor = coin.SoMarkerSet()
        self.anchor.markerIndex = _marker_index(9)
        self.anchor.numPoints = 0
        for node in (anchor_color, self.anchor_coords, self.anchor):
            anchor_sep.addChild(node)
        for node in (self.color, self.style, self.coords, self.lines, anchor_sep):
            self.root.addChild(node)

    def set_loop(self, points, anchor=None):
        points = np.asarray(points if points is not None else np.zeros((0, 3)), dtype=float).reshape(-1, 3)
        _set_vec3(self.coords.point, points)
        _set_ints(self.lines.numVertices, [len(points)] if len(points) >= 2 else [])
        _set_vec3(self.anchor_coords.point, [anchor] if anchor is not None else np.zeros((0, 3)))
        self.anchor.numPoints = 1 if anchor is not None else 0

    def clear(self):
        self.set_loop(None)

    def point_count(self):
        return self.coords.point.getNum() if self.lines.numVertices.getNum() else 0
