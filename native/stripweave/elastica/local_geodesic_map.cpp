#include "stripweave/elastica/local_geodesic_map.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace stripweave {

namespace {

double corner_angle(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ea = a - p, eb = b - p;
  return std::atan2(ea.cross(eb).norm(), ea.dot(eb));
}


// Complex multiplication: rotate b by the unit complex number a.
inline Vec2 rotate(const Vec2& a, const Vec2& b) {
  return {a.x() * b.x() - a.y() * b.y(), a.x() * b.y() + a.y() * b.x()};
}

// The unit complex number r with r * from/|from| = to/|to|.
inline Vec2 rotation_between(const Vec2& from, const Vec2& to) {
  const Vec2 r(from.x() * to.x() + from.y() * to.y(), from.x() * to.y() - from.y() * to.x());
  const double n = r.norm();
  return n > 0 ? Vec2(r / n) : Vec2(1, 0);
}

}  // namespace

GeodesicMapDomain::GeodesicMapDomain(const Surface& s) : surface(&s) {
  const Index nv = s.mesh.num_vertices();
  flags.assign(nv, 0);
  for (Index e = 0; e < s.topology.num_edges(); ++e) {
    std::uint8_t f = 0;
    if (s.edge_class[e] == EdgeClass::Feature) f = kOnFeature;
    if (s.edge_class[e] == EdgeClass::Boundary) f = kOnBoundary;
    flags[s.topology.edges[e][0]] |= f;
    flags[s.topology.edges[e][1]] |= f;
  }
  plane_normal.resize(nv);
  for (Index v = 0; v < nv; ++v) {
    const bool given = static_cast<Index>(s.normal.size()) == nv && s.normal[v].squaredNorm() > 0;
    if (given && !(flags[v] & kOnFeature)) {
      plane_normal[v] = s.normal[v].normalized();
      continue;
    }
    // Angle-weighted mean of the fan's triangle normals: at a crease with
    // two flat sides this is the bisector of the two face normals.
    Vec3 n = Vec3::Zero();
    for (const Index* t = s.topology.vertex_triangles.begin(v); t != s.topology.vertex_triangles.end(v); ++t) {
      const Tri& f = s.mesh.triangles[*t];
      const int i = f[0] == v ? 0 : f[1] == v ? 1 : 2;
      const Vec3& p = s.mesh.positions[v];
      const Vec3& a = s.mesh.positions[f[(i + 1) % 3]];
      const Vec3& b = s.mesh.positions[f[(i + 2) % 3]];
      const Vec3 fn = (a - p).cross(b - p);
      if (fn.squaredNorm() > 0) n += corner_angle(p, a, b) * fn.normalized();
    }
    if (n.squaredNorm() == 0) n = given ? s.normal[v] : Vec3::UnitZ();
    plane_normal[v] = n.normalized();
  }
}

LocalGeodesicMapper::LocalGeodesicMapper(const GeodesicMapDomain& domain)
    : domain_(domain),
      s_(*domain.surface),
      stamp_(domain.surface->mesh.num_vertices(), 0),
      local_(domain.surface->mesh.num_vertices(), kInvalid) {}

void LocalGeodesicMapper::add(Index v, int ring) {
  stamp_[v] = current_;
  local_[v] = map_.size();
  map_.vertex.push_back(v);
  map_.ring.push_back(static_cast<std::uint8_t>(ring));
}

const LocalGeodesicMap& LocalGeodesicMapper::compute(Index centre, int rings) {
  rings = std::clamp(rings, 1, 254);
  if (++current_ == 0) {  // the stamp wrapped: forget every earlier map
    std::fill(stamp_.begin(), stamp_.end(), 0);
    current_ = 1;
  }
  map_.centre = centre;
  map_.vertex.clear();
  map_.ring.clear();
  map_.u.clear();
  map_.touches_blocked.clear();

  // 1. The ring: breadth-first, not continuing from feature / boundary
  //    vertices other than the centre (they end geodesics, never carry them).
  const Csr& nb = s_.topology.vertex_neighbours;
  add(centre, 0);
  for (Index i = 0; i < map_.size(); ++i) {
    const Index x = map_.vertex[i];
    const int h = map_.ring[i];
    if (h == rings || (i > 0 && !domain_.expands(x))) continue;
    for (const Index* w = nb.begin(x); w != nb.end(x); ++w)
      if (stamp_[*w] != current_) add(*w, h + 1);
  }
  const Index n = map_.size();
  map_.u.assign(n, Vec2::Zero());
  map_.touches_blocked.assign(n, 0);
  state_.assign(n, 0);
  Candidates none;
  for (int k = 0; k < kKinds; ++k) {
    none.u[k] = Vec2::Zero();
    none.dist[k] = std::numeric_limits<double>::infinity();
    none.from[k][0] = none.from[k][1] = kInvalid;
  }
  none.chosen = kStraight;
  cand_.assign(n, none);
  heap_.clear();
  key_.assign(n, 0.0);
  deferred_.assign(n, 0);
  state_[0] = 2;

  // 2. The 1-ring from the fan (fixed: state 3 until settled).
  layout_fan();

  // 3. Dijkstra order, unfolding each triangle when its second corner settles.
  const auto& tris = s_.mesh.triangles;
  const Csr& vt = s_.topology.vertex_triangles;
  auto later = std::greater<std::pair<double, Index>>();
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const auto [d, i] = heap_.back();
    heap_.pop_back();
    if (state_[i] == 2 || d != key_[i]) continue;  // settled, or a stale entry
    const Candidates& ci = cand_[i];
    const Index a = map_.vertex[i];
    if (ci.chosen != kStraight && !deferred_[i]) {
      // Fast marching's obtuse-triangle case: the triangle (x, j, i) that
      // i's geodesic really crosses may still wait for its corner j, which
      // is farther from the centre than i. Settle i after such corners (once),
      // so it can still get its straight candidate.
      double wait = -1;
      for (const Index* t = vt.begin(a); t != vt.end(a); ++t) {
        const Tri& f = tris[*t];
        const int k = f[0] == a ? 0 : f[1] == a ? 1 : 2;
        const Index l1 = local(f[(k + 1) % 3]), l2 = local(f[(k + 2) % 3]);
        if (l1 == kInvalid || l2 == kInvalid) continue;
        const auto& te = s_.topology.triangle_edges[*t];
        if (state_[l1] == 2 && (state_[l2] == 1 || state_[l2] == 3) &&
            s_.edge_class[te[(k + 1) % 3]] == EdgeClass::Regular)
          wait = std::max(wait, key_[l2]);
        if (state_[l2] == 2 && (state_[l1] == 1 || state_[l1] == 3) &&
            s_.edge_class[te[(k + 1) % 3]] == EdgeClass::Regular)
          wait = std::max(wait, key_[l1]);
      }
      deferred_[i] = 1;
      if (wait >= d) {
        push(i, std::nextafter(wait, std::numeric_limits<double>::infinity()));
        continue;
      }
    }
    state_[i] = 2;
    map_.u[i] = ci.u[ci.chosen];
    const Index* from = ci.from[ci.chosen];
    map_.touches_blocked[i] = ci.chosen == kBlocked || (from[0] != kInvalid && map_.touches_blocked[from[0]]) ||
                              (from[1] != kInvalid && map_.touches_blocked[from[1]]);
    for (const Index* t = vt.begin(a); t != vt.end(a); ++t) {
      const Tri& f = tris[*t];
      const int j = f[0] == a ? 0 : f[1] == a ? 1 : 2;
      const Index b1 = f[(j + 1) % 3], b2 = f[(j + 2) % 3];
      const Index l1 = local(b1), l2 = local(b2);
      if (l1 == kInvalid || l2 == kInvalid) continue;
      const auto& te = s_.topology.triangle_edges[*t];
      // (a, b1, b2) is counter-clockwise: b2 lies left of a -> b1.
      if (state_[l1] == 2 && state_[l2] < 2) {
        if (s_.edge_class[te[j]] == EdgeClass::Regular) unfold(i, l1, l2, true);
      } else if (state_[l2] == 2 && state_[l1] < 2) {
        if (s_.edge_class[te[(j + 2) % 3]] == EdgeClass::Regular) unfold(i, l2, l1, false);
      }
    }
  }

  // Drop ring vertices no unfolding reached, keeping the order.
  Index kept = 0;
  for (Index i = 0; i < n; ++i) {
    const Index v = map_.vertex[i];
    if (state_[i] != 2) {
      stamp_[v] = current_ - 1;
      continue;
    }
    map_.vertex[kept] = v;
    map_.u[kept] = map_.u[i];
    map_.ring[kept] = map_.ring[i];
    map_.touches_blocked[kept] = map_.touches_blocked[i];
    local_[v] = kept++;
  }
  map_.vertex.resize(kept);
  map_.u.resize(kept);
  map_.ring.resize(kept);
  map_.touches_blocked.resize(kept);
  return map_;
}

void LocalGeodesicMapper::layout_fan() {
  const Index v = map_.centre;
  const auto& P = s_.mesh.positions;
  const Csr& vt = s_.topology.vertex_triangles;
  struct Corner {
    Index a, b;
    double angle;
    bool along_curve;  // the edge v-a is a feature or boundary edge
  };
  std::vector<Corner> corners;
  corners.reserve(vt.size(v));
  for (const Index* t = vt.begin(v); t != vt.end(v); ++t) {
    const Tri& f = s_.mesh.triangles[*t];
    const int i = f[0] == v ? 0 : f[1] == v ? 1 : 2;
    const Index a = f[(i + 1) % 3], b = f[(i + 2) % 3];
    const Index e = s_.topology.triangle_edges[*t][i];
    corners.push_back({a, b, corner_angle(P[v], P[a], P[b]), s_.edge_class[e] != EdgeClass::Regular});
  }
  if (corners.empty()) return;

  // The fan runs counter-clockwise a -> b. An open fan (boundary vertex)
  // starts at the corner whose a is no corner's b; a closed one at its first
  // feature edge, so that e1 runs along the crease; otherwise anywhere fixed.
  auto find_a = [&](Index a) {
    for (size_t k = 0; k < corners.size(); ++k)
      if (corners[k].a == a) return static_cast<Index>(k);
    return kInvalid;
  };
  Index start = kInvalid;
  bool open = false;
  for (size_t k = 0; k < corners.size() && !open; ++k) {
    bool is_b = false;
    for (const Corner& c : corners) is_b |= c.b == corners[k].a;
    if (!is_b) start = static_cast<Index>(k), open = true;
  }
  if (!open) {
    start = 0;
    for (size_t k = 0; k < corners.size(); ++k)
      if (corners[k].along_curve) {
        start = static_cast<Index>(k);
        break;
      }
  }
  std::vector<std::pair<Index, double>> fan;  // (vertex, cumulative angle)
  fan.reserve(corners.size() + 1);
  double sum = 0;
  Index k = start;
  for (size_t step = 0; step < corners.size(); ++step) {
    fan.emplace_back(corners[k].a, sum);
    sum += corners[k].angle;
    const Index next = find_a(corners[k].b);
    if (next == kInvalid || next == start) break;
    k = next;
  }
  if (open) fan.emplace_back(corners[k].b, sum);
  map_.angle_scale = open || !(sum > 0) ? 1.0 : 2 * M_PI / sum;

  const Vec3& nrm = domain_.plane_normal[v];
  map_.normal = nrm;
  Vec3 e1 = Vec3::Zero();
  for (const auto& [a, angle] : fan) {  // the first fan edge not along the normal
    const Vec3 d = P[a] - P[v];
    e1 = d - d.dot(nrm) * nrm;
    if (e1.norm() > 1e-9 * d.norm()) break;
  }
  if (!(e1.norm() > 0)) e1 = nrm.unitOrthogonal();
  map_.e1 = e1.normalized();
  map_.e2 = nrm.cross(map_.e1);

  for (const auto& [a, angle] : fan) {
    const Index la = local(a);
    if (la == kInvalid || state_[la] != 0) continue;
    const double len = (P[a] - P[v]).norm();
    const double th = angle * map_.angle_scale;
    cand_[la].u[kStraight] = Vec2(len * std::cos(th), len * std::sin(th));
    cand_[la].dist[kStraight] = len;
    state_[la] = 3;
    push(la, len);
  }
}

void LocalGeodesicMapper::push(Index i, double key) {
  key_[i] = key;
  heap_.emplace_back(key, i);
  std::push_heap(heap_.begin(), heap_.end(), std::greater<std::pair<double, Index>>());
}

void LocalGeodesicMapper::choose(Candidates& c) const {
  const double inf = std::numeric_limits<double>::infinity();
  if (c.dist[kStraight] < inf)
    c.chosen = c.dist[kBent] < c.dist[kStraight] ? kBent : kStraight;
  else if (c.dist[kUnfolded] < inf)
    c.chosen = kUnfolded;
  else
    c.chosen = kBlocked;
}

void LocalGeodesicMapper::unfold(Index la, Index lb, Index lc, bool c_left) {
  const auto& P = s_.mesh.positions;
  const Vec3& pa = P[map_.vertex[la]];
  const Vec3& pb = P[map_.vertex[lb]];
  const Vec3& pc = P[map_.vertex[lc]];
  const Vec2& Ua = map_.u[la];
  const Vec2& Ub = map_.u[lb];
  const double lab2 = (pb - pa).squaredNorm(), lac2 = (pc - pa).squaredNorm(), lbc2 = (pc - pb).squaredNorm();
  const double lab = std::sqrt(lab2);
  if (!(lab > 0)) return;
  const double da2 = Ua.squaredNorm(), db2 = Ub.squaredNorm();
  // The triangle laid flat: A = 0, B = (lab, 0), C on its side of AB.
  const double xc = (lab2 + lac2 - lbc2) / (2 * lab);
  double yc = std::sqrt(std::max(0.0, lac2 - xc * xc));
  if (!c_left) yc = -yc;
  // The virtual source on the other side, |SA| = |U(a)|, |SB| = |U(b)|.
  const double xs = (lab2 + da2 - db2) / (2 * lab);
  double ys = std::sqrt(std::max(0.0, da2 - xs * xs));
  if (c_left) ys = -ys;
  const Vec2 SA(-xs, -ys), SB(lab - xs, -ys), SC(xc - xs, yc - ys);
  // Where the ray S -> C meets the line AB, as a fraction of AB.
  double lambda = 0.5;
  bool valid = false;
  const double dy = yc - ys;
  if (std::abs(dy) > 0) {
    const double mu = -ys / dy;
    lambda = (xs + mu * (xc - xs)) / lab;
    valid = mu >= 0 && lambda >= -1e-9 && lambda <= 1 + 1e-9;
  }
  const bool beside_a = lambda < 0.5;  // if invalid: the side the ray passes
  lambda = std::clamp(lambda, 0.0, 1.0);
  // The rotations carrying S->A onto U(a) and S->B onto U(b) agree on a flat
  // surface; on a curved one they differ slightly and are blended.
  const Vec2 ra = rotation_between(SA, Ua), rb = rotation_between(SB, Ub);
  Vec2 r = (1 - lambda) * ra + lambda * rb;
  r = r.norm() > 0 ? Vec2(r.normalized()) : ra;
  // The unfolded distance, kept within the triangle inequalities of the
  // triangle (a safeguard where |U(a)|, |U(b)| and |ab| are inconsistent and
  // S could only be placed on the line ab).
  const double la_c = std::sqrt(lac2), lb_c = std::sqrt(lbc2), da = std::sqrt(da2), db = std::sqrt(db2);
  const double lo = std::max(da - la_c, db - lb_c), hi = std::min(da + la_c, db + lb_c);
  const double dist = std::clamp(SC.norm(), std::min(lo, hi), hi);
  Vec2 u = rotate(r, SC);
  if (u.norm() > 0) u *= dist / u.norm();
  Candidates& cs = cand_[lc];
  const int before = cs.chosen;
  const double before_dist = cs.dist[before];
  auto offer = [&](int kind, const Vec2& cu, double cd, Index f0, Index f1) {
    if (cd < cs.dist[kind]) cs.u[kind] = cu, cs.dist[kind] = cd, cs.from[kind][0] = f0, cs.from[kind][1] = f1;
  };
  if (valid) {
    offer(kStraight, u, dist, la, lb);
  } else {
    const Index lx = beside_a ? la : lb;
    if (domain_.expands(map_.vertex[lx])) {
      offer(kUnfolded, u, dist, la, lb);
      // The path bent at the passed corner x: |U(x)| + |xc|, leaving x
      // in the direction the triangle gives.
      const Vec2& Ux = beside_a ? Ua : Ub;
      const Vec2 step = rotate(beside_a ? ra : rb, beside_a ? Vec2(SC - SA) : Vec2(SC - SB));
      const Vec2 p = Ux + step;
      const double bent = Ux.norm() + step.norm();
      offer(kBent, p.norm() > 0 ? Vec2(p * (bent / p.norm())) : p, bent, lx, kInvalid);
    } else {
      offer(kBlocked, u, dist, la, lb);
    }
  }
  choose(cs);
  if (state_[lc] == 0 || cs.chosen != before || cs.dist[cs.chosen] != before_dist) {
    state_[lc] = 1;
    push(lc, cs.dist[cs.chosen]);
  }
}

}  // namespace stripweave
