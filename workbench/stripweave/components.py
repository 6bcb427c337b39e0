"""Per-component figures of a layout (issue 18: assemblies and multi-component files are
reported per component), for report.json's "components".

    component_report(surface, layout, red_regions) -> [ {...} per component ] or []

Input : the Surface (its solver mesh in model units: vertices, triangles), layout.json's
        dict (patches with corners, vertices with positions, defect_locations) and the
        red regions the weave left (weave.red_regions: position).
Output: per connected component of the solver mesh, largest first:
        {"component", "triangles", "area", "patches", "red_regions", "defects": {kind: n},
         "clean"}; clean when the component has patches, no red region and no defect
        located on it. An empty list for a one-component surface (report.json's own
        figures are that component's).
A patch belongs to the component of its first corner, a defect and a red region to the
component of the solver vertex nearest their position (they lie on the surface).
"""
import numpy as np


def component_labels(triangles, vertex_count):
    """Per vertex, the id of its connected component (union-find over the triangles' edges)."""
    parent = np.arange(vertex_count)

    def find(v):
        root = v
        while parent[root] != root:
            root = parent[root]
        while parent[v] != root:
            parent[v], v = root, parent[v]
        return root

    for a, b, c in np.asarray(triangles, dtype=np.int64):
        ra, rb, rc = find(a), find(b), find(c)
        parent[rb] = ra
        parent[rc] = ra
    roots = np.array([find(v) for v in range(vertex_count)])
    _, labels = np.unique(roots, return_inverse=True)
    return labels


def report_labels(triangles, vertex_count):
    """Per vertex, the id component_report gives its component: components numbered largest
    first (by triangles), ties in the order of component_labels. The one numbering of the
    report, the job's set-aside components and triangle_components."""
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    labels = component_labels(triangles, vertex_count)
    count = int(labels.max()) + 1 if len(labels) else 0
    sizes = np.bincount(labels[triangles[:, 0]], minlength=count)
    order = sorted(range(count), key=lambda c: (-sizes[c], c))
    rank = np.empty(count, dtype=np.int64)
    rank[order] = np.arange(count)
    return rank[labels]


def triangle_components(triangles, vertex_count):
    """Per triangle, the id component_report gives its component (report_labels)."""
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    return report_labels(triangles, vertex_count)[triangles[:, 0]]


def _nearest_vertices(vertices, points, chunk=256):
    out = []
    for k in range(0, len(points), chunk):
        p = np.asarray(points[k:k + chunk], float)
        d = ((p[:, None, :] - vertices[None, :, :]) ** 2).sum(axis=2)
        out.extend(np.argmin(d, axis=1).tolist())
    return out


def component_report(surface, layout, red_regions=()):
    vertices = np.asarray(surface.vertices, float)
    triangles = np.asarray(surface.triangles, dtype=np.int64)
    labels = report_labels(triangles, len(vertices))
    count = int(labels.max()) + 1 if len(labels) else 0
    if count <= 1:
        return []
    tri_label = labels[triangles[:, 0]]
    e1 = vertices[triangles[:, 1]] - vertices[triangles[:, 0]]
    e2 = vertices[triangles[:, 2]] - vertices[triangles[:, 0]]
    tri_area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
    entries = [{"component": c, "triangles": int((tri_label == c).sum()),
                "area": float(tri_area[tri_label == c].sum()), "patches": 0, "red_regions": 0,
                "defects": {}} for c in range(count)]

    def of(points):
        return [int(labels[v]) for v in _nearest_vertices(vertices, points)] if len(points) else []

    lv = layout.get("vertices", [])
    corners = [lv[p["corners"][0]]["position"] for p in layout.get("patches", []) if p.get("corners")]
    for c in of(corners):
        entries[c]["patches"] += 1
    located = [d for d in layout.get("defect_locations", []) if d.get("position") is not None]
    for d, c in zip(located, of([d["position"] for d in located])):
        entries[c]["defects"][d["kind"]] = entries[c]["defects"].get(d["kind"], 0) + 1
    red = [r for r in red_regions if r.get("position") is not None]
    for c in of([r["position"] for r in red]):
        entries[c]["red_regions"] += 1
    for e in entries:
        e["clean"] = bool(layout.get("valid")) and e["patches"] > 0 and not e["red_regions"] and not e["defects"]
    return entries
