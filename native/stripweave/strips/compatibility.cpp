// Strip compatibility (see compatibility.h).
#include "stripweave/strips/compatibility.h"

#include "stripweave/strips/cut_graph.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

// The g-edges that cross the loop between their two ends at an angle within
// the limit (see the header). A g-edge joins vertices at most k rings apart,
// so one that crosses the loop has both ends within k rings of the
// triangles the loop runs through: a breadth-first search over those rings
// gives every such vertex the loop segment it was reached from, and its side
// of the loop there (the sign of its offset along normal x direction). An
// edge whose ends lie on opposite sides crosses the loop; its direction
// there is taken as the mean of its two end tangents, the loop's as that of
// the two segments.
void disable_shallow_crossings(const Surface& surface, const ElasticaGraph& g, const LoopPath& loop,
                               double cos_limit, std::vector<Index>& nodes) {
  const TriangleMesh& mesh = surface.mesh;
  const MeshTopology& topo = surface.topology;
  const Index nv = mesh.num_vertices();
  std::vector<Index> origin(nv, kInvalid);  // the loop segment a vertex was reached from
  std::vector<Index> frontier, next;
  for (Index k = 0; k < static_cast<Index>(loop.segments.size()); ++k)
    for (Index v : mesh.triangles[loop.segments[k].triangle])
      if (origin[v] == kInvalid) origin[v] = k, frontier.push_back(v);
  std::vector<Index> reached = frontier;
  for (int ring = 0; ring < g.params.k && !frontier.empty(); ++ring) {
    next.clear();
    for (Index v : frontier)
      for (auto it = topo.vertex_triangles.begin(v); it != topo.vertex_triangles.end(v); ++it)
        for (Index w : mesh.triangles[*it])
          if (origin[w] == kInvalid) origin[w] = origin[v], next.push_back(w);
    reached.insert(reached.end(), next.begin(), next.end());
    frontier.swap(next);
  }
  auto side = [&](Index v) {
    const PathSegment& sg = loop.segments[origin[v]];
    const Vec3 mid = 0.5 * (loop.path.points[sg.from] + loop.path.points[sg.to]);
    const Vec3 left = unit_normal(mesh, sg.triangle).cross(sg.direction);
    const double d = (mesh.positions[v] - mid).dot(left);
    return d > 0 ? 1 : d < 0 ? -1 : 0;
  };
  for (Index a : reached) {
    const int sa = side(a);
    if (sa == 0) continue;
    for (Index n = g.node_offsets[a]; n < g.node_offsets[a + 1]; ++n) {
      const Index b = g.head[n];
      if (b < a || origin[b] == kInvalid || side(b) != -sa) continue;  // each edge once, from its lower end
      const Vec3& ta = loop.segments[origin[a]].direction;
      const Vec3& tb = loop.segments[origin[b]].direction;
      const Vec3 along = ta.dot(tb) >= 0 ? Vec3(ta + tb) : Vec3(ta - tb);
      const Vec3 dir = g.tangent(surface, n) - g.tangent(surface, g.reverse[n]);
      if (along.squaredNorm() == 0 || dir.squaredNorm() == 0) continue;
      if (std::abs(dir.normalized().dot(along.normalized())) > cos_limit) {
        nodes.push_back(n);
        nodes.push_back(g.reverse[n]);
      }
    }
  }
}

// The nodes at vertex v that run within the limit of `direction`, either way
// along it, with their reverses (the mask stays closed under reversal).
void disable_along(const Surface& surface, const ElasticaGraph& g, Index v, const Vec3& direction, double cos_limit,
                   std::vector<Index>& nodes) {
  for (Index n = g.node_offsets[v]; n < g.node_offsets[v + 1]; ++n)
    if (std::abs(g.tangent(surface, n).dot(direction)) > cos_limit) {
      nodes.push_back(n);
      nodes.push_back(g.reverse[n]);
    }
}

// The loop's own neighbourhood where the strip does not cover it (a strip
// stopped at once by a fold-over or a singularity beside its loop, or held
// within a band narrower than a triangle): at the corners of the triangles
// the loop runs through, the nodes within the limit of its direction there.
// The parameterization refuses any later loop that meets this one running
// the same way (contradicting_meetings, parameterization.h), and a strip of
// no width disables nothing of its own: later loops then ran along such
// loops and through their vertices, and every one was refused (a plate with
// 23 bores: 20 of 86 strips without width, and each proposal of its last
// red region's cut refused so).
void disable_along_uncovered_loop(const Surface& surface, const ElasticaGraph& g, const LoopPath& loop,
                                  const std::vector<bool>& covered, double cos_limit, std::vector<Index>& nodes) {
  for (const PathSegment& segment : loop.segments)
    for (Index v : surface.mesh.triangles[segment.triangle])
      if (!covered[v]) disable_along(surface, g, v, segment.direction, cos_limit, nodes);
}

}  // namespace

std::vector<Index> incompatible_nodes(const Surface& surface, const ElasticaGraph& g, const Strip& strip,
                                      const LoopPath& loop, double max_angle_deg, double band) {
  // |cos| of the angle to the isocurve, either way along it.
  const double cos_limit = std::cos(max_angle_deg * M_PI / 180.0);
  // Per vertex, the least |across| of the strip there.
  std::vector<double> across(surface.mesh.num_vertices(), std::numeric_limits<double>::infinity());
  if (std::isfinite(band)) {
    for (size_t k = 0; k < strip.triangles.size(); ++k)
      for (int i = 0; i < 3; ++i) {
        double& a = across[surface.mesh.triangles[strip.triangles[k]][i]];
        a = std::min(a, std::abs(strip.coords[k][i].y()));
      }
  }
  std::vector<Index> nodes;
  disable_shallow_crossings(surface, g, loop, cos_limit, nodes);
  std::vector<bool> covered(surface.mesh.num_vertices(), false);  // the isocurve rule applies
  for (Index v = 0; v < surface.mesh.num_vertices(); ++v) {
    const Vec3& iso = strip.isocurve[v];
    if (iso.squaredNorm() == 0) continue;
    if (std::isfinite(band) && across[v] > band) continue;
    covered[v] = true;
    disable_along(surface, g, v, iso, cos_limit, nodes);
  }
  disable_along_uncovered_loop(surface, g, loop, covered, cos_limit, nodes);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

}  // namespace stripweave
