// Strip extraction (see strip_extraction.h).
#include "stripweave/strips/strip_extraction.h"

#include "stripweave/core/error.h"

#include <cmath>
#include <limits>
#include <queue>

namespace stripweave {

namespace {

// Strip coordinates of a chart point: (along, across) = Q p + c, Q a rotation
// by a multiple of 90 degrees (charts and strip frames are both
// counter-clockwise, so no reflection is ever needed).
struct StripMap {
  Eigen::Matrix2d q = Eigen::Matrix2d::Identity();
  Vec2 c = Vec2::Zero();
  Vec2 operator()(const Vec2& p) const { return q * p + c; }
};

Eigen::Matrix2d quarter_turns(int r) {
  r = ((r % 4) + 4) % 4;
  Eigen::Matrix2d m = Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d quarter = (Eigen::Matrix2d() << 0, -1, 1, 0).finished();
  for (int i = 0; i < r; ++i) m = quarter * m;
  return m;
}

// The map of the triangle across edge e, given the map of the triangle `from`.
StripMap carry(const StripMap& m, const Transition& tr, bool from_is_first) {
  StripMap out;
  if (from_is_first) {
    // chart_1 = R^r chart_0 + tr  =>  chart_0 = R^-r (chart_1 - tr)
    out.q = m.q * quarter_turns(-tr.r);
    out.c = m.c - out.q * tr.tr;
  } else {
    // chart_0 is the far side: chart_1 = R^r chart_0 + tr
    out.q = m.q * quarter_turns(tr.r);
    out.c = m.c + m.q * tr.tr;
  }
  return out;
}

// The map of a seed triangle: the loop runs along chart axis 1-axis, with
// constant coordinate `value` on axis `axis`; travel direction d (chart).
StripMap seed_map(int axis, double value, const Vec2& travel) {
  Vec2 along = Vec2::Zero();
  along[1 - axis] = travel[1 - axis] >= 0 ? 1.0 : -1.0;
  const Vec2 across(-along.y(), along.x());  // 90 degrees to the left
  StripMap m;
  m.q.row(0) = along.transpose();
  m.q.row(1) = across.transpose();
  Vec2 on_loop = Vec2::Zero();
  on_loop[axis] = value;
  m.c = -m.q * on_loop;
  return m;
}

// The 3D gradient of a linear function on a triangle from its corner values.
Vec3 gradient(const Vec3& p0, const Vec3& p1, const Vec3& p2, double f0, double f1, double f2) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2);
  const double det = a * c - b * b;
  if (!(det > 0)) return Vec3::Zero();
  // g = x e1 + y e2 with g.e1 = f1 - f0 and g.e2 = f2 - f0.
  const double d1 = f1 - f0, d2 = f2 - f0;
  const double x = (c * d1 - b * d2) / det, y = (a * d2 - b * d1) / det;
  return x * e1 + y * e2;
}

}  // namespace

Strip extract_strip(const Surface& s, const CrossField& field, const Parameterization& param,
                    const std::vector<LoopPath>& loops, Index l) {
  const TriangleMesh& mesh = s.mesh;
  const MeshTopology& topo = s.topology;
  const Index nt = mesh.num_triangles();
  if (l < 0 || l >= static_cast<Index>(loops.size())) throw InputError("no loop " + std::to_string(l) + " in the design");
  const LoopPath& loop = loops[l];
  if (loop.segments.empty()) throw InputError("loop " + std::to_string(l + 1) + " crosses no triangle");

  std::vector<std::uint8_t> singular(mesh.num_vertices(), 0);
  for (const Singularity& sg : field.singularities) singular[sg.vertex] = 1;

  double total_area = 0;
  std::vector<double> area(nt);
  for (Index t = 0; t < nt; ++t) total_area += area[t] = 0.5 * triangle_normal_area2(mesh, t).norm();
  const double mean_area = total_area / std::max<Index>(nt, 1);

  // The seed: the first segment of the loop, in its triangle's chart.
  const PathSegment& first = loop.segments.front();
  auto chart_point = [&](Index t, Index point) {
    const Vec3 b = barycentric_in(s, loop.path, point, t);
    return Vec2(b[0] * param.uv[t][0] + b[1] * param.uv[t][1] + b[2] * param.uv[t][2]);
  };
  const Vec2 travel = chart_point(first.triangle, first.to) - chart_point(first.triangle, first.from);
  const StripMap seed = seed_map(param.loop_axis[l][0], param.loop_value[l][0], travel);

  // Conquest in order of distance from the loop. key = the smallest |across|
  // over the triangle's corners (0 where the triangle straddles an isocurve
  // of the loop); side = the sign of across at the centroid.
  Strip strip;
  strip.covered.assign(nt, 0);
  std::vector<std::uint8_t> claimed(nt, 0);
  std::vector<int> claimed_side(nt, 0);
  std::vector<double> centroid_across(nt, 0);
  std::vector<StripMap> map(nt);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double bound[2] = {kInf, kInf};  // [0] right (across < 0), [1] left
  double reach[2] = {0, 0};
  bool touched_boundary[2] = {false, false};
  std::string why[2];

  struct Entry {
    double key;
    Index triangle;
    StripMap map;
    bool operator>(const Entry& o) const { return key > o.key || (key == o.key && triangle > o.triangle); }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  auto evaluate = [&](Index t, const StripMap& m, std::array<Vec2, 3>& c) {
    double lo = kInf, hi = -kInf;
    for (int i = 0; i < 3; ++i) {
      c[i] = m(param.uv[t][i]);
      lo = std::min(lo, c[i].y());
      hi = std::max(hi, c[i].y());
    }
    return lo <= 0 && hi >= 0 ? 0.0 : std::min(std::abs(lo), std::abs(hi));
  };
  {
    std::array<Vec2, 3> c;
    queue.push({evaluate(first.triangle, seed, c), first.triangle, seed});
  }
  while (!queue.empty()) {
    const Entry top = queue.top();
    queue.pop();
    const Index t = top.triangle;
    if (claimed[t]) continue;
    std::array<Vec2, 3> c;
    evaluate(t, top.map, c);
    const double mid = (c[0].y() + c[1].y() + c[2].y()) / 3.0;
    const int side = mid >= 0 ? 1 : 0;
    if (top.key > bound[side]) continue;
    claimed[t] = 1;
    claimed_side[t] = side;
    centroid_across[t] = mid;
    map[t] = top.map;
    strip.coords.push_back(c);
    strip.triangles.push_back(t);
    reach[side] = std::max(reach[side], std::abs(mid));

    // Obstacles: the isocurve through a singularity, a fold-over or a
    // degenerate chart bounds this side of the strip.
    for (int i = 0; i < 3; ++i) {
      if (!singular[mesh.triangles[t][i]]) continue;
      const int corner_side = c[i].y() >= 0 ? 1 : 0;
      if (std::abs(c[i].y()) < bound[corner_side]) bound[corner_side] = std::abs(c[i].y()), why[corner_side] = "singularity";
    }
    const double chart_area = 0.5 * ((c[1] - c[0]).x() * (c[2] - c[0]).y() - (c[1] - c[0]).y() * (c[2] - c[0]).x());
    const bool fold = !param.flipped.empty() && param.flipped[t];
    if ((fold || !(std::abs(chart_area) > 1e-8 * mean_area)) && top.key < bound[side])
      bound[side] = top.key, why[side] = fold ? "fold-over" : "degeneracy";

    for (int k = 0; k < 3; ++k) {
      const Index e = topo.triangle_edges[t][k];
      if (topo.is_boundary_edge(e)) {
        touched_boundary[side] = true;
        continue;
      }
      const bool from_first = topo.edge_triangles[e][0] == t;
      const Index n = from_first ? topo.edge_triangles[e][1] : topo.edge_triangles[e][0];
      const StripMap m = carry(top.map, param.transition[e], from_first);
      std::array<Vec2, 3> cn;
      const double key = evaluate(n, m, cn);
      if (claimed[n]) {
        // The other side (or the same side, around the surface) came here
        // first: the strip has wrapped onto itself.
        const double across_here = (cn[0].y() + cn[1].y() + cn[2].y()) / 3.0;
        if (std::abs(across_here - centroid_across[n]) > 1e-6 && key < bound[side] && top.key > 0)
          bound[side] = std::max(key, std::abs(mid)), why[side] = "wrap";
        continue;
      }
      queue.push({key, n, m});
    }
  }

  // The strip: the conquered triangles inside both bounds.
  for (int side = 0; side < 2; ++side) {
    const double width = std::isfinite(bound[side]) ? bound[side] : reach[side];
    (side ? strip.width_left : strip.width_right) = width * s.similarity.scale;
    (side ? strip.stop_left : strip.stop_right) =
        !why[side].empty() ? why[side] : touched_boundary[side] ? "boundary" : "surface";
  }
  double covered_area = 0;
  std::vector<Index> kept;
  std::vector<std::array<Vec2, 3>> kept_coords;
  kept.reserve(strip.triangles.size());
  kept_coords.reserve(strip.triangles.size());
  for (size_t k = 0; k < strip.triangles.size(); ++k) {
    const Index t = strip.triangles[k];
    const int side = claimed_side[t];
    const double width = std::isfinite(bound[side]) ? bound[side] : kInf;
    if (std::abs(centroid_across[t]) > width) continue;
    strip.covered[t] = 1;
    kept.push_back(t);
    kept_coords.push_back(strip.coords[k]);
    covered_area += area[t];
  }
  strip.triangles = std::move(kept);
  strip.coords = std::move(kept_coords);
  strip.triangles.shrink_to_fit();  // a design keeps every strip twice (DesignState)
  strip.coords.shrink_to_fit();
  strip.area_fraction = total_area > 0 ? covered_area / total_area : 0;

  // Isocurve tangents: the along-gradient, averaged over the strip's
  // triangles around each vertex, in the vertex's tangent plane.
  strip.isocurve.assign(mesh.num_vertices(), Vec3::Zero());
  for (size_t k = 0; k < strip.triangles.size(); ++k) {
    const Index t = strip.triangles[k];
    const Tri& f = mesh.triangles[t];
    const auto& c = strip.coords[k];
    Vec3 g = gradient(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]], c[0].x(), c[1].x(), c[2].x());
    if (g.norm() == 0) continue;
    g.normalize();
    for (Index v : f) strip.isocurve[v] += area[t] * g;
  }
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    Vec3& d = strip.isocurve[v];
    if (d.squaredNorm() == 0) continue;
    d -= d.dot(s.normal[v]) * s.normal[v];
    const double n = d.norm();
    d = n > 0 ? Vec3(d / n) : Vec3::Zero();
  }
  // Strip coordinates in model units.
  for (auto& corners : strip.coords)
    for (Vec2& c : corners) c *= s.similarity.scale;
  return strip;
}

}  // namespace stripweave
