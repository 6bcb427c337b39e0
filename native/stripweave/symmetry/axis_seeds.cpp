// axis_seeds (see axis_seeds.h).
#include "stripweave/symmetry/axis_seeds.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>

namespace stripweave {

namespace {

struct Crossing {
  double along = 0;  // position on the axis line, from the rotation's point
  Vec3 normal_area2 = Vec3::Zero();
  Index triangle = kInvalid;
};

// Where the line o + s a crosses triangle t (its closed area, to within
// `slack` of barycentric coordinate: a line through a vertex or an edge
// crosses every triangle there, and the crossings merge into one point).
bool line_crosses(const TriangleMesh& m, Index t, const Vec3& o, const Vec3& a, double slack, double& s) {
  const Tri& tri = m.triangles[t];
  const Vec3 p0 = m.positions[tri[0]], e1 = m.positions[tri[1]] - p0, e2 = m.positions[tri[2]] - p0;
  const Vec3 h = a.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-14 * e1.norm() * e2.norm()) return false;  // the line runs in the triangle's plane
  const Vec3 w = o - p0;
  const double u = w.dot(h) / det;
  const Vec3 q = w.cross(e1);
  const double v = a.dot(q) / det;
  if (u < -slack || v < -slack || u + v > 1 + slack) return false;
  s = e2.dot(q) / det;
  return true;
}

// The smooth cap around a fixed point (axis_points): Dijkstra along mesh edges
// from the crossed triangles' corners, to the first vertex on a crease or the
// open boundary, or whose normal has turned more than 45 degrees.
double cap_radius(const Surface& s, const Vec3& point, const Vec3& normal, const std::vector<Index>& start,
                  const std::vector<std::uint8_t>& rim_edge_vertex) {
  const Index nv = s.mesh.num_vertices();
  std::vector<double> dist(nv, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (Index v : start) {
    const double d = (s.mesh.positions[v] - point).norm();
    if (d < dist[v]) dist[v] = d, queue.push({d, v});
  }
  const double turned = std::cos(M_PI / 4);
  double farthest = 0;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    farthest = d;
    if (rim_edge_vertex[v] || s.normal[v].dot(normal) < turned) return d;
    for (const Index* u = s.topology.vertex_neighbours.begin(v); u != s.topology.vertex_neighbours.end(v); ++u) {
      const double du = d + (s.mesh.positions[*u] - s.mesh.positions[v]).norm();
      if (du < dist[*u]) dist[*u] = du, queue.push({du, *u});
    }
  }
  return farthest;  // a closed smooth component with no rim within 45 degrees: all of it
}

}  // namespace

std::vector<AxisPoint> axis_points(const Surface& s, const Symmetry& rotation) {
  const TriangleMesh& m = s.mesh;
  const Vec3 o = rotation.point, a = rotation.direction.normalized();
  std::vector<Crossing> crossings;
  for (Index t = 0; t < m.num_triangles(); ++t) {
    double along = 0;
    if (line_crosses(m, t, o, a, 1e-9, along)) crossings.push_back({along, triangle_normal_area2(m, t), t});
  }
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) { return x.along < y.along; });

  std::vector<std::uint8_t> rim(m.num_vertices(), 0);
  for (Index e = 0; e < s.topology.num_edges(); ++e)
    if (s.edge_class[e] != EdgeClass::Regular) rim[s.topology.edges[e][0]] = rim[s.topology.edges[e][1]] = 1;

  // Crossings closer than a millionth of the model (normalized units: the
  // diagonal is about 1) are one point: the triangles around a vertex or an
  // edge the axis passes through.
  constexpr double kSamePoint = 1e-6;
  std::vector<AxisPoint> out;
  for (size_t i = 0; i < crossings.size();) {
    size_t j = i;
    Vec3 n = Vec3::Zero();
    std::vector<Index> corners;
    for (; j < crossings.size() && crossings[j].along - crossings[i].along < kSamePoint; ++j) {
      n += crossings[j].normal_area2;
      for (Index v : m.triangles[crossings[j].triangle]) corners.push_back(v);
    }
    const double along = 0.5 * (crossings[i].along + crossings[j - 1].along);
    i = j;
    if (!(n.norm() > 0)) continue;
    n.normalize();
    if (std::abs(n.dot(a)) < 0.5) continue;  // the surface runs along the axis here: no chord passes it
    AxisPoint p;
    p.point = o + along * a;
    p.normal = n;
    p.cap_radius = cap_radius(s, p.point, n, corners, rim);
    out.push_back(p);
  }
  return out;
}

std::vector<Anchor> axis_seed(const Surface& s, const Symmetry& rotation, const std::vector<AxisPoint>& points,
                              double fraction, const SurfaceLocator& locator) {
  const Vec3 a = rotation.direction.normalized();
  const Vec3 any = std::abs(a.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 radial = (any - a * a.dot(any)).normalized();
  // The n-gon of apothem c has its corners at c / cos(pi / n); a half-turn's two
  // chords are parallel and never meet, and take the factor of a third-turn.
  const double corner = std::max(std::cos(M_PI / rotation.order), 0.5);
  std::vector<Anchor> out;
  for (const AxisPoint& p : points) {
    const SurfacePoint3 at = locator.closest(p.point + fraction * corner * p.cap_radius * radial);
    const Tri& t = s.mesh.triangles[at.triangle];
    const Vec3 plane = (s.mesh.positions[t[1]] - s.mesh.positions[t[0]]).cross(s.mesh.positions[t[2]] - s.mesh.positions[t[0]]);
    Vec3 along = p.normal.cross(radial);
    if (plane.norm() > 0) along -= plane.normalized() * along.dot(plane.normalized());
    if (!(along.norm() > 1e-9)) continue;
    Anchor anchor;
    anchor.point = at.point;
    anchor.direction = along.normalized();
    out.push_back(anchor);
  }
  return out;
}

}  // namespace stripweave
