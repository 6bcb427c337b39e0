"""Stage 1, the surface model: load a CAD part or a mesh.

    surf = load("part.step")                    # STEP/IGES/BREP, STL/OBJ/OFF/PLY, FCStd
    surf = from_shape(part_shape)               # a FreeCAD Part.Shape or a BREP string
    surf = from_mesh(vertices, triangles)       # numpy (N,3) float and (M,3) int arrays
    surf = from_object(doc_object)              # a Part::Feature or Mesh::Feature

Options (keyword arguments, all optional):
    target_triangles=30000     size of the solver mesh; 0 keeps the tessellation
    feature_angle_deg=30       dihedral angle above which an edge is a sharp feature
    deflection=0               B-rep chordal deflection in model units (0: relative)
    relative_deflection=1e-3   ... as a fraction of the bounding-box diagonal
    angular_deflection_deg=20
    min_feature_length=0.02    meshes: drop isolated crease chains shorter than this (of the diagonal)
    curvature_radius=0         meshes: jet-fit radius (of the diagonal; 0 = automatic)
    remesh_iterations=3

Every function takes `progress=` (a `Progress`, polled from another thread;
its cancel() stops the computation with `Cancelled`) and releases the GIL
while the native code runs. Bad input raises `InputError` with a message that
names the problem.
"""
import os

import numpy as np

from ._native import native

SurfaceOptions = native.SurfaceOptions
InputError = native.InputError


def make_options(**options):
    """A native SurfaceOptions from keyword arguments; unknown names are an error."""
    opts = native.SurfaceOptions()
    for name, value in options.items():
        if name.startswith("_") or not hasattr(opts, name):
            valid = sorted(n for n in dir(opts) if not n.startswith("_"))
            raise TypeError(f"unknown surface option '{name}' (valid: {', '.join(valid)})")
        try:
            setattr(opts, name, value)
        except TypeError:
            raise InputError(f"surface option {name} must be a {type(getattr(opts, name)).__name__}, "
                             f"got {value!r}") from None
    return opts


def load(path, progress=None, **options):
    """Build the surface model from a model file (see the module docstring)."""
    path = os.fspath(path)
    if path.lower().endswith(".fcstd"):
        return from_object(_single_object_of_fcstd(path), progress=progress, **options)
    return native.load_file(path, make_options(**options), progress)


def from_shape(shape, progress=None, **options):
    """Build the surface model from a FreeCAD Part.Shape or a BREP string."""
    text = shape if isinstance(shape, str) else shape.exportBrepToString()
    return native.from_brep_string(text, make_options(**options), progress)


def from_mesh(vertices, triangles, progress=None, **options):
    """Build the surface model from (N,3) vertex and (M,3) triangle arrays."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    return native.from_arrays(v, index_array(triangles), make_options(**options), progress)


def index_array(triangles):
    """Triangle corners as int64 (the native side checks their range): a float array
    whose values are not whole numbers is refused, not truncated (1.5 is not vertex 1)."""
    t = np.asarray(triangles)
    if t.dtype.kind == "f":
        whole = np.isfinite(t) & (t == np.round(t))
        if not whole.all():
            i = np.argwhere(~whole)[0]
            raise InputError(f"triangle {i[0]} has the corner {t[tuple(i)]!r}: vertex indices are whole numbers")
    elif t.dtype.kind not in "iub":
        raise InputError(f"triangles must be an (M, 3) array of vertex indices, got {t.dtype} values")
    if t.dtype.kind == "u" and t.size and t.max() > np.iinfo(np.int64).max:
        raise InputError(f"a triangle refers to vertex {t.max()}, beyond any mesh")
    return np.ascontiguousarray(t, dtype=np.int64)


def mesh_arrays_of(mesh):
    """(vertices, triangles) numpy arrays of a FreeCAD Mesh.Mesh."""
    points, facets = mesh.Topology
    v = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
    t = np.array(facets, dtype=np.int32).reshape(-1, 3)
    return v, t


def from_object(obj, progress=None, **options):
    """Build the surface model from a FreeCAD document object (Part or Mesh)."""
    mesh = getattr(obj, "Mesh", None)
    if mesh is not None and hasattr(mesh, "Topology"):
        return from_mesh(*mesh_arrays_of(mesh), progress=progress, **options)
    shape = getattr(obj, "Shape", None)
    if shape is None:
        raise InputError(f"'{getattr(obj, 'Label', obj)}' is neither a Part (it has no Shape) nor a Mesh")
    if shape.isNull() or not shape.Faces:
        raise InputError(f"the shape of '{getattr(obj, 'Label', obj)}' has no faces")
    return from_shape(shape, progress=progress, **options)


def _single_object_of_fcstd(path):
    """The one shape or mesh of a FreeCAD document (its top-level object)."""
    if not os.path.isfile(path):
        raise InputError(f"cannot read '{path}': the file does not exist")
    import FreeCAD  # only FCStd needs FreeCAD itself
    try:
        doc = FreeCAD.openDocument(path)
    except Exception as exc:  # FreeCAD raises plain Exceptions for broken files
        raise InputError(f"cannot read '{path}': {exc}") from None
    try:
        candidates = []
        for obj in doc.Objects:
            if any(parent.TypeId != "App::Part" for parent in obj.InList):
                continue  # consumed by another feature: not a result
            mesh = getattr(obj, "Mesh", None)
            shape = getattr(obj, "Shape", None)
            if (mesh is not None and hasattr(mesh, "Topology") and mesh.CountFacets) or \
               (shape is not None and not shape.isNull() and shape.Faces):
                candidates.append(obj)
        if len(candidates) != 1:
            names = ", ".join(o.Label for o in candidates) or "none"
            raise InputError(f"'{path}' must hold exactly one top-level shape or mesh, it holds "
                             f"{len(candidates)} ({names})")
        return _Detached(candidates[0])
    finally:
        FreeCAD.closeDocument(doc.Name)


class _Detached:
    """A copy of an object's Shape or Mesh that outlives its document."""

    def __init__(self, obj):
        self.Label = obj.Label
        mesh = getattr(obj, "Mesh", None)
        if mesh is not None and hasattr(mesh, "Topology"):
            self.Mesh = mesh.copy()
        else:
            self.Shape = obj.Shape.copy()
