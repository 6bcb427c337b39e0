"""View provider of the Layout object: the patches tinted on the refined
mesh (a pastel per patch; red, crease, orange and yellow regions in their colours,
§4.2), the layout's edges as dark lines, its vertices as dots (irregular
ones larger, pinned ones, placed by hand (§7, layout_pins.py), as larger
green squares with a diamond, as are the points edges were routed through
by hand) and its defects as red crosses.

Display mode "Layout" (this overlay); the Shape (edges and vertices) is what
selection and other workbenches see.  The tinted mesh needs the result kept
in memory (LayoutModel.mesh); after a reopen the edges, vertices and defects
come from the stored LayoutJson until the next recompute.
"""

from . import messages
from .proxy_state import StatelessViewProvider

REGION_TINTS = {"red": (0.95, 0.25, 0.2), "orange": (1.0, 0.6, 0.15), "yellow": (0.98, 0.9, 0.25),
                "crease": (0.2, 0.7, 0.85)}   # as in preview.png
# Pastel patch tints, chosen so neighbours usually differ.
PATCH_TINTS = ((0.72, 0.83, 0.95), (0.78, 0.92, 0.78), (0.93, 0.85, 0.72), (0.86, 0.78, 0.93),
               (0.75, 0.9, 0.9), (0.92, 0.8, 0.85))
OUTSIDE_TINT = (0.8, 0.8, 0.8)
EDGE_COLOR = (0.1, 0.15, 0.35)
VERTEX_COLOR = (0.1, 0.15, 0.35)
IRREGULAR_COLOR = (0.85, 0.1, 0.6)
PINNED_COLOR = (0.0, 0.7, 0.15)   # no patch tint or region colour is this green
PINNED_SIZE = 12.0                 # pixels: larger than every other dot (markers are 9 px at most)
# A pinned dot is drawn this fraction of the diagonal out along the surface
# normal (lift.py): a square that large would cut into the tinted mesh.
PINNED_LIFT = 0.004
DEFECT_COLOR = (0.9, 0.0, 0.0)
ROOT_NODE = "StripWeaveLayout"


def triangle_tints(mesh):
    """Per refined triangle its colour: the region's when red, crease, orange
    or yellow, else its patch's pastel (grey outside every patch)."""
    out = []
    patches = mesh["patch"]
    for t, colour in enumerate(mesh["colour"]):
        if colour in REGION_TINTS:
            out.append(REGION_TINTS[colour])
        else:
            p = int(patches[t]) if t < len(patches) else -1
            out.append(PATCH_TINTS[p % len(PATCH_TINTS)] if p >= 0 else OUTSIDE_TINT)
    return out


class LayoutOverlay:
    """The coin nodes (pure pivy)."""

    def __init__(self):
        from pivy import coin
        from .overlay import PolylineSet
        self.root = coin.SoSeparator()
        self.root.setName(ROOT_NODE)
        # the tinted patches, lit, pushed slightly back so lines and dots draw over them
        self.faces = coin.SoSeparator()
        offset = coin.SoPolygonOffset()
        offset.factor, offset.units = 1.0, 1.0
        self.binding = coin.SoMaterialBinding()
        self.binding.value = coin.SoMaterialBinding.PER_FACE
        self.material = coin.SoMaterial()
        self.coords = coin.SoCoordinate3()
        self.face_set = coin.SoIndexedFaceSet()
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        for node in (hints, offset, self.binding, self.material, self.coords, self.face_set):
            self.faces.addChild(node)
        self.root.addChild(self.faces)
        lines = coin.SoSeparator()
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        lines.addChild(light)
        self.edges = PolylineSet("StripWeaveLayoutEdges", EDGE_COLOR, 3.0)
        lines.addChild(self.edges.root)
        self.vertices, self.vertex_coords = self._markers(lines, VERTEX_COLOR, "CIRCLE_FILLED_7_7")
        self.irregular, self.irregular_coords = self._markers(lines, IRREGULAR_COLOR, "CIRCLE_FILLED_9_9")
        _, self.pinned_coords = self._markers(lines, PINNED_COLOR, None, PINNED_SIZE)
        self.pinned, self.pinned_marker_coords = self._markers(lines, PINNED_COLOR, "DIAMOND_FILLED_9_9")
        self.defects, self.defect_coords = self._markers(lines, DEFECT_COLOR, "CROSS_9_9")
        self.root.addChild(lines)

    @staticmethod
    def _markers(parent, colour, kind, size=None):
        """Markers of ``kind`` (SoMarkerSet's), or with ``size`` square
        points of that many pixels (Coin's markers stop at 9).  Returns
        (the shape node, its coordinates node)."""
        from pivy import coin
        sep = coin.SoSeparator()
        c = coin.SoBaseColor()
        c.rgb.setValue(*colour)
        coords = coin.SoCoordinate3()
        if size is None:
            shape = coin.SoMarkerSet()
            shape.markerIndex = getattr(coin.SoMarkerSet, kind)
            nodes = (c, coords, shape)
        else:
            style, shape = coin.SoDrawStyle(), coin.SoPointSet()
            style.pointSize = size
            nodes = (c, style, coords, shape)
        for node in nodes:
            sep.addChild(node)
        parent.addChild(sep)
        return shape, coords

    def set_mesh(self, mesh):
        if mesh is None or not len(mesh["triangles"]):
            self.coords.point.setNum(0)
            self.face_set.coordIndex.setNum(0)
            self.material.diffuseColor.setNum(0)
            return
        v, t = mesh["vertices"], mesh["triangles"]
        self.coords.point.setValues(0, len(v), v.tolist())
        self.coords.point.setNum(len(v))
        index = [int(i) for tri in t.tolist() for i in (tri[0], tri[1], tri[2], -1)]
        self.face_set.coordIndex.setValues(0, len(index), index)
        self.face_set.coordIndex.setNum(len(index))
        tints = triangle_tints(mesh)
        self.material.diffuseColor.setValues(0, len(tints), tints)
        self.material.diffuseColor.setNum(len(tints))

    @staticmethod
    def _points(coords, points):
        coords.point.setValues(0, len(points), [tuple(map(float, p)) for p in points]) if points else None
        coords.point.setNum(len(points))

    def set_layout(self, layout, lift=None):
        """``lift``: the design's NormalLift (lift.py) if derived, for the pinned dots."""
        edges = [e["points"] for e in layout.get("edges", []) if len(e["points"]) >= 2]
        self.edges.set_polylines([tuple(p) for e in edges for p in e], [len(e) for e in edges])
        vertices = layout.get("vertices", [])
        pinned = [v["position"] for v in vertices if v.get("placement") == "pinned"]
        # The points edges were routed through by hand (layout_pins.route_edge): pins too.
        pinned += [e["through"] for e in layout.get("edges", []) if e.get("through") is not None]
        free = [v for v in vertices if v.get("placement") != "pinned"]
        regular = [v["position"] for v in free if v.get("valence") == 4 or v.get("boundary")]
        irregular = [v["position"] for v in free if not (v.get("valence") == 4 or v.get("boundary"))]
        self._points(self.vertex_coords, regular)
        self._points(self.irregular_coords, irregular)
        if lift is not None and pinned:
            pinned = [tuple(p) for p in lift.lift(pinned, PINNED_LIFT)]
        self._points(self.pinned_coords, pinned)
        self._points(self.pinned_marker_coords, pinned)
        self._points(self.defect_coords, [loc["position"] for loc in layout.get("defect_locations", [])])


class ViewProviderLayout(StatelessViewProvider):
    ICON = "Layout.svg"

    def attach(self, vobj):
        self.Object = vobj.Object
        self.overlay = LayoutOverlay()
        vobj.addDisplayMode(self.overlay.root, "Layout")
        self.redraw()

    def getDisplayModes(self, vobj):
        return ["Layout"]

    def getDefaultDisplayMode(self):
        return "Layout"

    def setDisplayMode(self, mode):
        return mode

    def updateData(self, obj, prop):
        if prop == "LayoutJson":
            self.redraw()

    def redraw(self):
        ov = getattr(self, "overlay", None)
        obj = getattr(self, "Object", None)
        try:
            if ov is None or obj is None or obj.Proxy is None:
                return
            if "Restore" in obj.State:   # properties arrive one by one: draw once the document is loaded
                from PySide import QtCore
                QtCore.QTimer.singleShot(100, self.redraw)
                return
            design = obj.Proxy.design_of(obj)
            derived = design.Proxy.derived(design) if design is not None else None
            ov.set_layout(obj.Proxy.layout(obj), derived.lift if derived is not None else None)
            ov.set_mesh(obj.Proxy.mesh(obj))
        except Exception as exc:
            messages.log("layout not drawn: {}".format(exc))
