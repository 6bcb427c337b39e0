#include "stripweave/symmetry/detect_symmetries.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/core/error.h"
#include "stripweave/symmetry/area_moments.h"
#include "stripweave/symmetry/refine_symmetry.h"
#include "stripweave/symmetry/symmetry_error.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

// Two principal moments this close (relative to the largest) leave their axes
// undetermined: the mesh's noise picks them.
constexpr double kEqualMoments = 0.02;
// Directions closer than this (radians, either sign) are one candidate.
constexpr double kSameDirection = 1e-3;
constexpr std::size_t kScreenSamples = 256;
constexpr std::size_t kRefineSamples = 1000, kQuickSamples = 250;
// A candidate this close in direction (radians) to an accepted symmetry of the
// same kind and order is that symmetry seen from another pair of points.
constexpr double kNearDirection = 0.035;

// At most `count` of the points, spread over the index range and visited in a
// scrambled order (a multiplicative stride): a wrong candidate fails at one
// of the first few, where mesh order would keep them all in one corner.
std::vector<Vec3> scrambled_sample(const std::vector<Vec3>& points, std::size_t count) {
  const std::size_t n = std::min(count, points.size());
  std::vector<Vec3> out;
  out.reserve(n);
  const double step = static_cast<double>(points.size()) / static_cast<double>(std::max<std::size_t>(n, 1));
  constexpr std::size_t kStride = 7919;  // a prime: i * kStride mod n visits every i once unless n divides by it
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = n % kStride == 0 ? i : (i * kStride) % n;
    out.push_back(points[static_cast<std::size_t>(static_cast<double>(j) * step)]);
  }
  return out;
}

bool same_direction(const Vec3& a, const Vec3& b) { return std::abs(a.dot(b)) > std::cos(kSameDirection); }

void add_direction(std::vector<Vec3>& dirs, const Vec3& d) {
  const double n = d.norm();
  if (!(n > 1e-9)) return;
  const Vec3 u = d / n;
  for (const Vec3& e : dirs)
    if (same_direction(e, u)) return;
  dirs.push_back(u);
}

// Feature-curve ends and junctions, then the vertices farthest from the
// centroid, spread by farthest-point sampling: at most `count`.
std::vector<Vec3> salient_points(const Surface& s, const Vec3& centroid, int count) {
  std::vector<Index> pool;
  for (const FeatureCurve& c : s.feature_curves)
    if (!c.closed && !c.vertices.empty()) {
      pool.push_back(c.vertices.front());
      pool.push_back(c.vertices.back());
    }
  std::vector<std::pair<double, Index>> far;
  for (Index v = 0; v < s.mesh.num_vertices(); ++v) far.emplace_back((s.mesh.positions[v] - centroid).norm(), v);
  std::sort(far.begin(), far.end(), std::greater<>());
  const double reach = far.empty() ? 0.0 : far.front().first;
  for (const auto& [d, v] : far) {
    if (d < 0.97 * reach) break;
    pool.push_back(v);
  }
  std::sort(pool.begin(), pool.end());
  pool.erase(std::unique(pool.begin(), pool.end()), pool.end());
  // Farthest-point sampling from the point farthest from the centroid.
  std::vector<Vec3> out;
  if (pool.empty()) return out;
  std::vector<double> gap(pool.size(), 1e300);
  std::size_t next = 0;
  for (std::size_t i = 0; i < pool.size(); ++i)
    if ((s.mesh.positions[pool[i]] - centroid).norm() > (s.mesh.positions[pool[next]] - centroid).norm()) next = i;
  while (static_cast<int>(out.size()) < count) {
    const Vec3 p = s.mesh.positions[pool[next]];
    out.push_back(p);
    std::size_t best = 0;
    for (std::size_t i = 0; i < pool.size(); ++i) {
      gap[i] = std::min(gap[i], (s.mesh.positions[pool[i]] - p).norm());
      if (gap[i] > gap[best]) best = i;
    }
    if (gap[best] < 1e-6) break;
    next = best;
  }
  return out;
}

std::vector<Vec3> candidate_directions(const Surface& s, const AreaMoments& m, const SymmetryOptions& options) {
  std::vector<Vec3> dirs;
  for (int i = 0; i < 3; ++i) add_direction(dirs, m.axes.col(i));
  const double largest = std::max(m.moments.maxCoeff(), 1e-300);
  const bool degenerate = std::abs(m.moments(1) - m.moments(0)) < kEqualMoments * largest ||
                          std::abs(m.moments(2) - m.moments(1)) < kEqualMoments * largest;
  if (!degenerate) return dirs;
  const std::vector<Vec3> points = salient_points(s, m.centroid, options.salient_points);
  for (const Vec3& p : points) add_direction(dirs, p - m.centroid);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j) {
      add_direction(dirs, points[i] - points[j]);
      // The axis through the midpoint of a pair (a cube's edge midpoints, a
      // blade gap's centre).
      add_direction(dirs, 0.5 * (points[i] + points[j]) - m.centroid);
    }
  return dirs;
}

bool same_symmetry(const Symmetry& a, const Symmetry& b) {
  if (a.kind != b.kind || std::abs(a.direction.dot(b.direction)) < std::cos(kNearDirection)) return false;
  const Vec3 d = b.point - a.point;
  // Planes: the offset along the normal; axes: the distance between the lines.
  const double apart = a.kind == SymmetryKind::Reflection ? std::abs(d.dot(a.direction))
                                                          : (d - a.direction * d.dot(a.direction)).norm();
  return apart < 1e-3;
}

// Screen, refine and verify one candidate; true with `out` filled when accepted.
bool verify(const Symmetry& candidate, const std::vector<Vec3>& screen, const std::vector<Vec3>& refine,
            const std::vector<Vec3>& all, const SurfaceLocator& locator, double tolerance, Symmetry& out,
            std::vector<Symmetry>& refined) {
  // The candidate is approximate (moments of a mesh, feature points): screen
  // loosely, then refine and judge strictly.
  const double loose = std::max(20.0 * tolerance, 0.02);
  if (!symmetry_error(candidate, screen, locator, loose).complete) return false;
  refined.push_back(candidate);
  // A few cheap steps first: most candidates that pass the loose screen are
  // near-symmetries that stay well off (a scan almost mirror-symmetric), and
  // each refinement step costs a query per sample.
  const std::vector<Vec3> few(refine.begin(), refine.begin() + std::min<std::size_t>(refine.size(), kQuickSamples));
  Symmetry s = refine_symmetry(candidate, few, locator, 3);
  if (!symmetry_error(s, screen, locator, 5.0 * tolerance).complete) return false;
  s = refine_symmetry(s, refine, locator);
  if (!symmetry_error(s, screen, locator, 2.0 * tolerance).complete) return false;
  const SymmetryError e = symmetry_error(s, all, locator);
  if (e.max > tolerance) return false;
  s.rms_error = e.rms;
  s.max_error = e.max;
  out = s;
  return true;
}

void keep(std::vector<Symmetry>& found, const Symmetry& s) {
  for (Symmetry& f : found)
    if (same_symmetry(f, s)) {
      if (s.order > f.order || (s.order == f.order && s.max_error < f.max_error)) f = s;
      return;
    }
  found.push_back(s);
}

}  // namespace

std::vector<Symmetry> detect_symmetries(const Surface& surface, const SymmetryOptions& options) {
  if (!(options.tolerance > 0) || !std::isfinite(options.tolerance))
    throw InputError("the symmetry tolerance must be a positive fraction of the diagonal");
  if (options.max_order < 2 || options.max_order > kMaxRotationOrder)
    throw InputError("the largest rotation order tried must be within 2.." + std::to_string(kMaxRotationOrder));
  std::vector<Symmetry> found;
  if (surface.mesh.num_triangles() == 0) return found;
  const AreaMoments m = area_moments(surface.mesh);
  const SurfaceLocator locator(surface.mesh);
  const std::vector<Vec3>& all = surface.mesh.positions;
  const std::vector<Vec3> refine = scrambled_sample(all, kRefineSamples);
  // Screened farthest from the centroid first: a wrong map moves far points
  // most, and a part's extremities (blade tips, corners) are what its
  // symmetric core (a hub, a slab) cannot vouch for.
  std::vector<Vec3> screen = scrambled_sample(all, kScreenSamples);
  std::stable_sort(screen.begin(), screen.end(), [&](const Vec3& a, const Vec3& b) {
    return (a - m.centroid).squaredNorm() > (b - m.centroid).squaredNorm();
  });
  // Refined candidates, accepted or not: a nearby candidate (another pair of
  // salient points on the same near-symmetry) refines to the same map.
  std::vector<Symmetry> refined;
  const auto known = [&](const Symmetry& candidate) {
    return std::any_of(found.begin(), found.end(), [&](const Symmetry& f) {
             return f.order % candidate.order == 0 && same_symmetry(f, candidate);
           }) ||
           std::any_of(refined.begin(), refined.end(), [&](const Symmetry& f) {
             return f.order == candidate.order && same_symmetry(f, candidate);
           });
  };
  for (const Vec3& d : candidate_directions(surface, m, options)) {
    Symmetry s;
    const Symmetry mirror = Symmetry::reflection(m.centroid, d);
    if (!known(mirror) && verify(mirror, screen, refine, all, locator, options.tolerance, s, refined)) keep(found, s);
    // The maximal order first: a lower order that divides it adds nothing.
    std::vector<int> accepted;
    for (int n = options.max_order; n >= 2; --n) {
      if (std::any_of(accepted.begin(), accepted.end(), [&](int k) { return k % n == 0; })) continue;
      const Symmetry rotation = Symmetry::rotation(m.centroid, d, n);
      if (known(rotation)) continue;
      if (verify(rotation, screen, refine, all, locator, options.tolerance, s, refined)) {
        accepted.push_back(n);
        keep(found, s);
      }
    }
  }
  // Keep the maximal order per axis: two orders a, b accepted about one axis
  // mean lcm(a, b) is a symmetry too, found above when within max_order.
  std::vector<Symmetry> out;
  for (const Symmetry& s : found) {
    bool dominated = false;
    for (const Symmetry& t : found)
      if (&t != &s && t.kind == SymmetryKind::Rotation && s.kind == SymmetryKind::Rotation &&
          same_direction(t.direction, s.direction) && t.order > s.order && t.order % s.order == 0) {
        const Vec3 d = t.point - s.point;
        if ((d - s.direction * d.dot(s.direction)).norm() < 1e-3) dominated = true;
      }
    if (!dominated) out.push_back(s);
  }
  std::stable_sort(out.begin(), out.end(), [](const Symmetry& a, const Symmetry& b) {
    if (a.kind != b.kind) return a.kind == SymmetryKind::Reflection;
    if (a.order != b.order) return a.order > b.order;
    return a.max_error < b.max_error;
  });
  return out;
}

}  // namespace stripweave
