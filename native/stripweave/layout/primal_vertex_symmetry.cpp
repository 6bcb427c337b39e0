// Symmetric primal vertices (paper §5.8, issue 21): a layout invariant under
// the design's accepted symmetries puts the vertices of regions that are
// images of each other at points that are images of each other.
//
// symmetrize_primal_vertices(ctx, symmetries, vertices, vertex_wedge)
//   Input   the primalization context; the symmetries (normalized units) the
//           design accepted; the vertices placed by the rules and the pins
//           (place_primal_vertices, pin_primal_vertices) with their wedges.
//   Output  per orbit of regions under the group the symmetries generate,
//           the vertices of all members but the representative moved to the
//           representative's vertex mapped (image_of set to it, position,
//           refined vertex, boundary flag and clearance updated) and
//           vertex_wedge with them. Nothing moves when the group does not
//           act on the regions (the loops are not mapped onto loops).
//   Rules   The group: the closure of the symmetries' maps (a rotation with a
//           mirror through its axis gives the dihedral group). A map takes
//           region r to the region of the refined vertex nearest the image
//           of r's deepest point (farthest from the loops); it acts on the
//           regions when that is a permutation keeping valences.
//           Representative: a pinned region if the orbit has one (a pin wins
//           over the symmetry, and its images get the pin mapped, placement
//           Pinned), else the member placed by the highest rule (the order
//           of VertexPlacement), then the most centred (clearance over
//           inradius), then the least position (x, y, z): a choice that does
//           not depend on how regions are numbered.
//           Target of member m: the mean of the images g(p) of the
//           representative's vertex p over the maps g taking the
//           representative to m. For the representative itself that mean is
//           invariant under its stabilizer (a region that is its own mirror
//           image gets p projected onto the plane, one around a rotation
//           axis the point of the axis); for the others it is that point
//           mapped, so the targets are exact images of each other.
//           Snap: the member's point nearest its target among those its rule
//           allows (as a pin's: a corner of the part stays a corner, i.e.
//           the corner point nearest the target, a crease-star node stays;
//           a boundary vertex stays on the boundary, a crease vertex on the
//           crease; else any point off the loops), preferring, for a member
//           with a non-trivial stabilizer, the points the stabilizer fixes
//           (on the plane, on the axis) when the rule allows any.
// Cost    O(|group| x regions x refined vertices) for the region maps and
//         O(regions x refined vertices) for the snaps, one clearance search.
#include "stripweave/layout/primalization.h"

#include "stripweave/surface/corner_strength.h"

#include <algorithm>
#include <numeric>

namespace stripweave {

namespace {

// An element of the group: x -> linear * x + shift.
struct GroupMap {
  Eigen::Matrix3d linear;
  Vec3 shift;
  Vec3 apply(const Vec3& p) const { return linear * p + shift; }
  bool same(const GroupMap& o) const {
    return (linear - o.linear).cwiseAbs().maxCoeff() < 1e-9 && (shift - o.shift).cwiseAbs().maxCoeff() < 1e-9;
  }
};

GroupMap map_of(const Symmetry& s, int k) {
  const Eigen::Matrix3d L = s.linear(k);
  return {L, s.map_point(Vec3::Zero(), k)};
}

// The closure of the symmetries' maps under composition, identity first.
std::vector<GroupMap> group_of(const std::vector<Symmetry>& symmetries) {
  constexpr size_t kMaxElements = 4 * kMaxRotationOrder;
  std::vector<GroupMap> group{{Eigen::Matrix3d::Identity(), Vec3::Zero()}};
  std::vector<GroupMap> generators;
  for (const Symmetry& s : symmetries) generators.push_back(map_of(s, 1));
  for (size_t i = 0; i < group.size() && group.size() < kMaxElements; ++i) {
    for (const GroupMap& g : generators) {
      const GroupMap h{g.linear * group[i].linear, g.linear * group[i].shift + g.shift};
      if (std::none_of(group.begin(), group.end(), [&](const GroupMap& x) { return x.same(h); })) group.push_back(h);
    }
  }
  return group;
}

// Per region, its wedge farthest from the loops (kInvalid if none is off them).
std::vector<Index> deepest_wedges(const PrimalContext& ctx, const std::vector<double>& clearance) {
  std::vector<Index> deepest(ctx.regions.regions.size(), kInvalid);
  for (Index w = 0; w < ctx.wedges.count(); ++w) {
    const Index v = ctx.wedges.vertex[w], r = ctx.wedge_region[w];
    if (ctx.vertex_on_loop[v] || ctx.vertex_crossing[v]) continue;
    if (deepest[r] == kInvalid || clearance[w] > clearance[deepest[r]]) deepest[r] = w;
  }
  return deepest;
}

// Per group element, the permutation of the regions it induces; empty if
// some element does not act on them (not a bijection, or valences differ).
std::vector<std::vector<Index>> region_maps(const PrimalContext& ctx, const std::vector<GroupMap>& group,
                                            const std::vector<Index>& deepest) {
  const auto& positions = ctx.arrangement.mesh.positions;
  const Index nr = static_cast<Index>(ctx.regions.regions.size());
  std::vector<std::vector<Index>> maps;
  for (const GroupMap& g : group) {
    std::vector<Index> perm(nr, kInvalid);
    std::vector<std::uint8_t> hit(nr, 0);
    for (Index r = 0; r < nr; ++r) {
      if (deepest[r] == kInvalid) return {};
      const Index w = nearest_wedge(ctx, g.apply(positions[ctx.wedges.vertex[deepest[r]]]), [](Index) { return true; });
      if (w == kInvalid) return {};
      const Index m = ctx.wedge_region[w];
      if (hit[m] || ctx.regions.regions[m].valence != ctx.regions.regions[r].valence) return {};
      hit[m] = 1, perm[r] = m;
    }
    maps.push_back(std::move(perm));
  }
  return maps;
}

// Whether vertex a is the better representative of its orbit than b.
bool better_representative(const PrimalVertex& a, const PrimalVertex& b) {
  const bool pa = a.placement == VertexPlacement::Pinned, pb = b.placement == VertexPlacement::Pinned;
  if (pa != pb) return pa;
  if (a.placement != b.placement) return a.placement < b.placement;
  const double ca = a.inradius > 0 ? a.clearance / a.inradius : 0, cb = b.inradius > 0 ? b.clearance / b.inradius : 0;
  if (ca != cb) return ca > cb;
  return std::lexicographical_compare(a.position.data(), a.position.data() + 3, b.position.data(),
                                      b.position.data() + 3);
}

}  // namespace

void symmetrize_primal_vertices(const PrimalContext& ctx, const std::vector<Symmetry>& symmetries,
                                std::vector<PrimalVertex>& vertices, std::vector<Index>& vertex_wedge) {
  if (symmetries.empty() || vertices.empty()) return;
  const LoopArrangement& A = ctx.arrangement;
  const Index nr = static_cast<Index>(vertices.size());
  const std::vector<GroupMap> group = group_of(symmetries);
  std::vector<double> clearance = loop_clearance(ctx);
  const std::vector<std::vector<Index>> maps = region_maps(ctx, group, deepest_wedges(ctx, clearance));
  if (maps.empty()) return;  // the loops are not mapped onto loops: no orbits to respect

  // Orbits: the regions a region is mapped to (the group is closed, so one
  // pass over the elements from any member reaches them all).
  std::vector<Index> orbit_of(nr, kInvalid);
  std::vector<std::vector<Index>> orbits;
  for (Index r = 0; r < nr; ++r) {
    if (orbit_of[r] != kInvalid) continue;
    orbits.emplace_back();
    for (const auto& perm : maps)
      if (orbit_of[perm[r]] == kInvalid) orbit_of[perm[r]] = static_cast<Index>(orbits.size() - 1), orbits.back().push_back(perm[r]);
  }

  const std::vector<std::uint8_t> on_crease = crease_vertices(ctx);
  const std::vector<double> strength = corner_strength(ctx.surface, ctx.surface_crease);
  const Index surface_vertices = ctx.surface.mesh.num_vertices();
  // A point counts as fixed by a map within a millionth of the part's size.
  Vec3 lo = A.mesh.positions[0], hi = lo;
  for (const Vec3& p : A.mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double fixed_tolerance = 1e-6 * (hi - lo).norm();

  bool moved = false;
  for (const std::vector<Index>& orbit : orbits) {
    Index rep = kInvalid;
    for (Index m : orbit)
      if (vertex_wedge[m] != kInvalid && (rep == kInvalid || better_representative(vertices[m], vertices[rep]))) rep = m;
    if (rep == kInvalid) continue;
    const Vec3 p = vertices[rep].position;
    const bool pinned = vertices[rep].placement == VertexPlacement::Pinned;
    for (Index m : orbit) {
      if (vertex_wedge[m] == kInvalid) continue;
      if (m != rep && vertices[m].placement == VertexPlacement::Pinned) continue;  // its own pin wins
      // The target and the maps fixing m (its stabilizer, the identity left out).
      Vec3 target = Vec3::Zero();
      int count = 0;
      std::vector<const GroupMap*> stabilizer;
      for (size_t g = 0; g < group.size(); ++g) {
        if (maps[g][rep] == m) target += group[g].apply(p), ++count;
        if (g > 0 && maps[g][m] == m) stabilizer.push_back(&group[g]);
      }
      target /= count;
      const VertexPlacement rule = vertices[m].placement;
      const RegionCreases& rc = ctx.regions.creases.regions[m];
      if (rule == VertexPlacement::Corner && rc.has_crease && rc.problem == CreaseProblem::None && rc.node != kInvalid) {
        if (m != rep) vertices[m].image_of = rep;  // the crease star's node: the nodes are each other's images
        continue;
      }
      auto allowed = [&](Index x) {
        const Index v = ctx.wedges.vertex[x];
        if (ctx.wedge_region[x] != m) return false;
        if (rule == VertexPlacement::Corner) {
          const Index sv = A.original_vertex[v];
          return sv != kInvalid && sv < surface_vertices && strength[sv] > 0;
        }
        if (rule == VertexPlacement::Boundary) return ctx.vertex_on_boundary[v] != 0;
        if (rule == VertexPlacement::Feature) return on_crease[v] != 0;
        return true;  // pinned (its images), singularity, centre: anywhere off the loops
      };
      auto fixed = [&](Index x) {
        const Vec3& q = A.mesh.positions[ctx.wedges.vertex[x]];
        for (const GroupMap* h : stabilizer)
          if ((h->apply(q) - q).norm() > fixed_tolerance) return false;
        return allowed(x);
      };
      Index w = stabilizer.empty() ? kInvalid : nearest_wedge(ctx, target, fixed);
      if (w == kInvalid) w = nearest_wedge(ctx, target, allowed);
      if (w == kInvalid) continue;
      PrimalVertex& pv = vertices[m];
      if (m != rep) pv.image_of = rep;
      if (m != rep && pinned) pv.placement = VertexPlacement::Pinned;
      if (w == vertex_wedge[m]) continue;
      vertex_wedge[m] = w;
      pv.refined_vertex = ctx.wedges.vertex[w];
      pv.position = A.mesh.positions[pv.refined_vertex];
      pv.boundary = ctx.vertex_on_boundary[pv.refined_vertex];
      moved = true;
    }
  }
  if (!moved) return;
  for (Index r = 0; r < nr; ++r)
    if (vertex_wedge[r] != kInvalid) vertices[r].clearance = clearance[vertex_wedge[r]];
}

}  // namespace stripweave
