"""Models generated with FreeCAD/OCCT for the tests, and geometric checks on surfaces."""
import math

import numpy as np

import FreeCAD  # noqa: F401  (loads Part's dependencies)
import Part
from FreeCAD import Vector


# --- generated models (FreeCAD Part shapes) ---------------------------------

def mirrored_box(shift=0.0):
    """A 40 x 20 x 8 slab centred at x = 0 with a 6 x 4 x 4 boss at x in [7, 13], y in [1, 5]
    and its mirror image at x in [-13, -7] (moved by `shift` along y: no longer symmetric)."""
    slab = Part.makeBox(40, 20, 8, Vector(-20, -10, 0))
    right = Part.makeBox(6, 4, 4, Vector(7, 1, 8))
    left = Part.makeBox(6, 4, 4, Vector(-13, 1 + shift, 8))
    return slab.fuse([right, left]).removeSplitter()


def turned_box():
    """The slab of mirrored_box with its bosses a half turn about z apart (no mirror plane)."""
    slab = Part.makeBox(40, 20, 8, Vector(-20, -10, 0))
    bosses = [Part.makeBox(6, 4, 4, Vector(7, 1, 8)), Part.makeBox(6, 4, 4, Vector(-13, -5, 8))]
    return slab.fuse(bosses).removeSplitter()


def box(size=10.0):
    return Part.makeBox(size, size, size)


def cylinder(r=5.0, h=20.0):
    return Part.makeCylinder(r, h)


def torus(R=10.0, r=3.0):
    return Part.makeTorus(R, r)


def sphere(R=5.0):
    return Part.makeSphere(R)


def filleted_box(size=10.0, radius=2.0):
    b = Part.makeBox(size, size, size)
    return b.makeFillet(radius, b.Edges)


def open_cylinder_shell(r=5.0, h=20.0):
    """The lateral face of a cylinder alone: an open shell with two boundary circles."""
    return Part.Shell([Part.makeCylinder(r, h).Faces[0]])


def lofted_face():
    """A freeform B-spline face lofted through three wavy curves (an open surface)."""
    def wavy(y, amp, phase):
        pts = [Vector(x, y, amp * math.sin(0.5 * x + phase)) for x in np.linspace(0, 20, 9)]
        c = Part.BSplineCurve()
        c.interpolate(pts)
        return Part.Wire(c.toShape())
    return Part.makeLoft([wavy(0, 2.0, 0.0), wavy(8, 3.0, 1.0), wavy(16, 1.5, 2.0)], False, False)


# --- helpers ------------------------------------------------------------------

def square_u_tube(w=8.0, R=20.0, L=20.0, skew_deg=30.0):
    """An open shell like the shared ubend2.stp: a square tube of side w swept along a U
    (a leg of length L, a half circle of radius R, a leg back), creased along its 4 edges,
    the first end square, the second cut by a plane turned skew_deg about z (its corners
    are no right angles). 12 faces; the ends are the open boundary, where each crease
    ends in a corner of the part."""
    path = Part.Wire([Part.LineSegment(Vector(0, 0, 0), Vector(0, L, 0)).toShape(),
                      Part.ArcOfCircle(Vector(0, L, 0), Vector(R, L + R, 0), Vector(2 * R, L, 0)).toShape(),
                      Part.LineSegment(Vector(2 * R, L, 0), Vector(2 * R, 0, 0)).toShape()])
    h = w / 2
    profile = Part.makePolygon([Vector(-h, 0, -h), Vector(h, 0, -h), Vector(h, 0, h), Vector(-h, 0, h),
                                Vector(-h, 0, -h)])
    shell = path.makePipeShell([profile], False, True)
    if not skew_deg:
        return shell
    cutter = Part.makeBox(100, 100, 100, Vector(-50, -100, -50))
    cutter.rotate(Vector(2 * R, 5, 0), Vector(0, 0, 1), skew_deg)
    cutter.translate(Vector(0, 5, 0))
    return Part.Shell(shell.cut(cutter).Faces)


def edge_use_counts(triangles):
    """How many triangles use each undirected edge."""
    t = np.asarray(triangles)
    e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return counts


def is_watertight_manifold(surface):
    """Every edge has exactly two triangles, and every vertex's triangles form one fan."""
    t = surface.triangles
    if not np.all(edge_use_counts(t) == 2):
        return False
    # One fan per vertex: on a closed manifold, the link of a vertex is a single cycle,
    # so its triangle count equals its neighbour count.
    n = len(surface.vertices)
    tri_count = np.bincount(t.ravel(), minlength=n)
    edges = np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)
    nbr_count = np.bincount(edges.ravel(), minlength=n)
    return bool(np.all(tri_count == nbr_count))


def capped_cylinder(r=5.0, h=20.0):
    return Part.makeCylinder(r, h)


def bumpy_sphere_mesh(R=5.0, subdivisions=4):
    """An organic closed triangle mesh (vertices, triangles): an icosphere of radius R whose
    radius is modulated by smooth bumps (+-15%), like a scanned blob. Genus 0."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        midpoint, faces = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                midpoint[key] = len(verts) - 1
            return midpoint[key]
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = faces
    u = np.array(verts)
    bumps = 1 + 0.15 * np.sin(3 * u[:, 0] + 1) * np.sin(2 * u[:, 1]) * np.cos(4 * u[:, 2] - 0.5)
    return R * u * bumps[:, None], np.array(f, dtype=np.int64)


def torus_knot_tube(radius=1.2, samples=360, around=24):
    """A closed tube (vertices, triangles) of the given radius around the (2, 3) torus knot
    r = 10 + 4 cos 3t, (r cos 2t, r sin 2t, 4 sin 3t): genus 1, knotted, no crease. Its
    circles follow a parallel-transport frame, the frame's holonomy spread evenly along the
    knot so that the tube closes without a seam twist."""
    t = np.linspace(0, 2 * np.pi, samples, endpoint=False)
    r = 10 + 4 * np.cos(3 * t)
    centre = np.stack([r * np.cos(2 * t), r * np.sin(2 * t), 4 * np.sin(3 * t)], 1)
    tangent = np.gradient(centre, axis=0)
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    normal = np.zeros_like(tangent)
    n = np.cross(tangent[0], [0.0, 0.0, 1.0])
    for i in range(samples):
        n = n - tangent[i] * np.dot(n, tangent[i])
        n /= np.linalg.norm(n)
        normal[i] = n
    binormal = np.cross(tangent, normal)
    back = normal[-1] - tangent[0] * np.dot(normal[-1], tangent[0])
    twist = np.arctan2(np.dot(np.cross(normal[0], back), tangent[0]), np.dot(normal[0], back))
    phi = -twist * np.arange(samples)[:, None] / samples + 2 * np.pi * np.arange(around)[None, :] / around
    vertices = (centre[:, None, :] + radius * (np.cos(phi)[..., None] * normal[:, None, :]
                                               + np.sin(phi)[..., None] * binormal[:, None, :])).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(samples), np.arange(around), indexing="ij")
    a0, a1 = i * around + j, i * around + (j + 1) % around
    b0, b1 = ((i + 1) % samples) * around + j, ((i + 1) % samples) * around + (j + 1) % around
    triangles = np.concatenate([np.stack([a0, b0, b1], -1).reshape(-1, 3), np.stack([a0, b1, a1], -1).reshape(-1, 3)])
    return vertices, triangles.astype(np.int64)


def winding_numbers(points, R=10.0):
    """(around the torus axis, around the tube) of a closed polyline on a torus centred at the origin."""
    p = np.asarray(points)
    theta = np.unwrap(np.arctan2(p[:, 1], p[:, 0]))
    phi = np.unwrap(np.arctan2(p[:, 2], np.hypot(p[:, 0], p[:, 1]) - R))
    return round((theta[-1] - theta[0]) / (2 * np.pi)), round((phi[-1] - phi[0]) / (2 * np.pi))


def key(R=10.0, r=2.0, shaft=30.0, shaft_r=1.5):
    """A key: a ring (torus in the xy plane) with a round shaft along +x fused to it, one solid
    of genus 1 whose handle is only the ring."""
    ring = Part.makeTorus(R, r)
    rod = Part.makeCylinder(shaft_r, shaft, Vector(R, 0, 0), Vector(1, 0, 0))
    return ring.fuse(rod).removeSplitter()


def bitted_key(R=10.0, r=2.0, shaft=30.0, shaft_r=1.5):
    """The key (key()) with what makes a real one sharp: a box bit at the shaft's end with
    three slots cut across it, and a collar ringing the shaft halfway, so creases ring the
    shaft and run along the bit."""
    bit = Part.makeBox(4, 2, 5, Vector(R + shaft - 6, -1, 0))
    for i in range(3):
        bit = bit.cut(Part.makeBox(0.8, 3, 2.5, Vector(R + shaft - 5.5 + 1.3 * i, -1.5, 2.6)))
    shape = key(R, r, shaft, shaft_r).fuse(bit).removeSplitter()
    collar = Part.makeCylinder(shaft_r + 0.7, 1.5, Vector(R + shaft / 3, 0, 0), Vector(1, 0, 0))
    return shape.fuse(collar).removeSplitter()


def bored_plate(bores=4, pitch=12.0, radius=3.0, thickness=4.0, width=12.0):
    """A plate `bores` pitches long with one through bore per pitch, in a row: genus `bores`."""
    plate = Part.makeBox(bores * pitch, width, thickness)
    holes = [Part.makeCylinder(radius, thickness, Vector((i + 0.5) * pitch, width / 2, 0)) for i in range(bores)]
    return plate.cut(holes[0].fuse(holes[1:]) if bores > 1 else holes[0]).removeSplitter()


def helical_tube(radius=5.0, pitch=2.5, turns=6, tube=0.9):
    """A tube swept along a helix (a thread's shape): one B-spline face winding `turns`
    times, its neighbouring turns 2 * (pitch / 2 - tube) apart, closed by two plane caps."""
    helix = Part.makeHelix(pitch, pitch * turns, radius)
    edge = helix.Edges[0]
    start, tangent = edge.valueAt(edge.FirstParameter), edge.tangentAt(edge.FirstParameter)
    profile = Part.Wire(Part.makeCircle(tube, start, tangent))
    return Part.Wire(helix.Edges).makePipeShell([profile], True, True)
