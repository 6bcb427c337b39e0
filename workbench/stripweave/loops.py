"""Stage 2, elastica loops (paper §5): the loop engine of one surface.

    session = LoopSession(surface, boundary="aligned")        # builds g and g'
    best = session.best_loop((x, y, z))                       # hover: all directions
    loops = session.loops([(x, y, z, dx, dy, dz), (x, y, z)], alternatives=5)
    for loop in loops: loop["points"], loop["length"], loop["cost"], ...

Anchors are (x, y, z) points or (x, y, z, dx, dy, dz) points with a tangent
direction, in model units; a direction's sign does not matter. Each loop is a
dict with the keys of `stripweave loop --json` (design.md) plus the cost
terms, the g' node chain and, per polyline point, the mesh vertex or mesh
edge it lies on.

Options: k=4, max_turn_deg=30, alpha=1.0, beta=0.25, boundary="aligned" |
"trimmed", feature_weight=100; algorithm="bidirectional" | "astar" |
"dijkstra" (equal costs, different speed); threads=2 (search directions
are shared between both cores). Queries release the GIL, and a newer query
cancels an older one still running (it raises Cancelled).
"""
import math
import time

from ._native import native

BOUNDARY_MODES = {"aligned": native.BoundaryMode.aligned, "trimmed": native.BoundaryMode.trimmed}
ALGORITHMS = {"dijkstra": native.SearchAlgorithm.dijkstra, "astar": native.SearchAlgorithm.astar,
              "bidirectional": native.SearchAlgorithm.bidirectional}


def make_params(**options):
    params = native.ElasticaParams()
    for name, value in options.items():
        if name == "boundary":
            if value not in BOUNDARY_MODES:
                raise native.InputError(f"unknown boundary mode '{value}' (expected aligned or trimmed)")
            value = BOUNDARY_MODES[value]
        elif name.startswith("_") or not hasattr(params, name):
            raise TypeError(f"unknown loop option '{name}'")
        setattr(params, name, value)
    return params


class LoopSession:
    """The elastica graph of a surface and the loop queries on it."""

    def __init__(self, surface, progress=None, algorithm="bidirectional", threads=2, **options):
        self.surface = surface
        self.native = native.LoopSession(surface, make_params(**options), progress)
        self.native.set_threads(threads)
        self.algorithm = algorithm

    @property
    def algorithm(self):
        return self.native.algorithm.name

    @algorithm.setter
    def algorithm(self, name):
        if name not in ALGORITHMS:
            raise ValueError(f"unknown search algorithm '{name}' (expected {', '.join(ALGORITHMS)})")
        self.native.algorithm = ALGORITHMS[name]

    def stats(self):
        return self.native.graph_stats()

    def loops(self, anchors, alternatives=1, open_curves=True):
        """Up to `alternatives` distinct loops through the anchors, cheapest first, as dicts."""
        if isinstance(alternatives, bool) or not isinstance(alternatives, int) or alternatives < 1:
            raise native.InputError(f"the number of alternatives must be a whole number, 1 or more, "
                                    f"got {alternatives!r}")
        return [self.describe(loop) for loop in self.native.loops([list(a) for a in anchors], alternatives,
                                                                   open_curves)]

    def best_loop(self, point, open_curves=True):
        """The best loop through a point over all directions (the hover query), as a dict."""
        return self.describe(self.native.best_loop(list(point), open_curves))

    def describe(self, loop):
        path = self.native.embed(loop)
        return {
            "cost": loop.cost,
            "length": path["length"],
            "closed": loop.closed,
            "points": path["points"].tolist(),
            "max_turn_deg": loop.max_turn_deg,
            "length_term": loop.length_term,
            "alignment_term": loop.alignment_term,
            "curvature_term": loop.curvature_term,
            "nodes": list(loop.nodes),
            "mesh_vertex": path["vertex"],
            "mesh_edge": path["edge"],
            "edge_t": path["t"],
        }


def parse_anchor(text):
    """'X,Y,Z' or 'X,Y,Z,DX,DY,DZ' -> tuple of floats."""
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise native.InputError(f"cannot read anchor '{text}': expected X,Y,Z or X,Y,Z,DX,DY,DZ") from None
    if len(values) not in (3, 6):
        raise native.InputError(f"cannot read anchor '{text}': expected X,Y,Z or X,Y,Z,DX,DY,DZ")
    if not all(math.isfinite(x) for x in values):   # the native side also bounds its distance
        raise native.InputError(f"cannot read anchor '{text}': a coordinate is NaN or infinite")
    return values


def timed(fn, *args, **kwargs):
    start = time.perf_counter()
    result = fn(*args, **kwargs)
    return result, (time.perf_counter() - start) * 1000.0
