// Local geodesic polar coordinates: a discrete exponential map around one
// vertex (paper §5.3: g-edges are surface geodesics, so their lengths and end
// tangents are measured on the surface, not along the chord).
//
// map(v, k) gives every vertex w within graph distance k of the centre v a
// point U(w) of v's tangent plane:
//   |U(w)|       the geodesic distance from v to w
//   atan2 U(w)   the polar angle of the geodesic's departure direction at v,
//                counter-clockwise about the normal from the frame vector e1.
// Polar angles are intrinsic: around an interior vertex the triangle corner
// angles are scaled by 2 pi / (their sum), so a cone (a cube corner, angle sum
// 3 pi / 2) is opened flat and a straight curve through v always leaves at its
// arrival angle plus pi. Around an open-boundary vertex the half fan keeps its
// true angles: there is no full turn to normalize, and a curve running along
// the boundary then turns by the boundary's own geodesic curvature.
//
// Method (after the unfolding schemes of fast marching and of Melvaer and
// Reimers' geodesic polar coordinates):
//  1. Ring: breadth-first search over mesh edges up to k hops from v. It does
//     not continue from a vertex on a sharp feature curve or an open boundary
//     (other than v itself): such vertices are reached, and so can end a
//     geodesic, but no geodesic passes through them. (Ring membership is
//     symmetric: w is in v's ring iff v is in w's.)
//  2. The 1-ring is laid out exactly from v's triangle fan: U(a) = |va| at the
//     scaled cumulative corner angle. At a crease the fan spans both sides, so
//     they are unfolded into one plane and a curve crossing the crease
//     orthogonally is straight.
//  3. Further vertices are settled in order of distance (Dijkstra). When two
//     corners a, b of a triangle (a, b, c) are settled, c gets a candidate:
//     the triangle is laid flat with its true edge lengths, the "virtual
//     source" S is placed on the far side of ab at distances |U(a)|, |U(b)|
//     from a and b, the geodesic S -> c is straight there, and it is rotated
//     into the map by the rotation carrying a onto U(a) (resp. b onto U(b)),
//     interpolated where the ray crosses ab. Flat regions are mapped exactly,
//     developable ones (cylinders) up to the mesh's chords, and curved ones to
//     second order in the ring's size. No unfolding crosses a sharp-feature
//     or boundary edge.
//     Choosing among a vertex's candidates (see choose()): the shortest
//     "straight" one (its ray really crosses ab) wins, unless a path bent at
//     a corner the ray passes is shorter still (the straight one then comes
//     round a saddle's shadow the long way); with no straight candidate the
//     shortest unfolding whose ray misses ab is taken, as the surface goes on
//     smoothly there; last, an unfolding whose ray passes beside a feature or
//     boundary vertex on its far side. Settling a vertex that has no straight
//     candidate is put off once until its pending neighbours have settled
//     (fast marching's obtuse-triangle case: the triangle its geodesic does
//     cross waits for a corner farther from v than the vertex itself).
//  4. Vertices reached only past a feature / boundary vertex's far side, or
//     from such vertices, are flagged (touches_blocked): their geodesic would
//     touch the feature, so they are no g-neighbours of v.
// Cost: O(m log m) for m ring vertices; a mapper reuses its workspace, so
// mapping every vertex of a 30K-triangle mesh at k = 4 takes about 0.3 s.
// A mapper is not thread-safe; use one per thread (the domain is shared and
// read-only).
#pragma once

#include "stripweave/surface/surface.h"

namespace stripweave {

// Per-surface data every map reads: which vertices geodesics may pass
// through, and the normal of each vertex's tangent plane.
struct GeodesicMapDomain {
  explicit GeodesicMapDomain(const Surface& surface);

  enum : std::uint8_t { kOnFeature = 1, kOnBoundary = 2 };

  const Surface* surface;
  std::vector<std::uint8_t> flags;  // per vertex: kOnFeature | kOnBoundary (an incident edge of that class)
  // The normal of the tangent plane of the polar angles: Surface::normal, but
  // on a sharp feature the angle-weighted mean of the incident triangles'
  // normals (a B-rep vertex on a crease carries one side's normal; the polar
  // angles unfold both sides into the mean plane).
  std::vector<Vec3> plane_normal;

  // A geodesic may pass through v (v is neither on a feature nor on the boundary).
  bool expands(Index v) const { return flags[v] == 0; }
};

struct LocalGeodesicMap {
  Index centre = kInvalid;
  Vec3 normal = Vec3::UnitZ();  // tangent plane normal at the centre
  Vec3 e1 = Vec3::UnitX();      // polar angle 0 (the first fan edge, projected; along a crease on a feature)
  Vec3 e2 = Vec3::UnitY();      // normal x e1
  double angle_scale = 1.0;     // 2 pi / corner angle sum (1 on the boundary)
  // The mapped vertices, centre first (vertex[0] == centre, u[0] == 0), then
  // in breadth-first order; ring[i] is the hop count. Ring vertices the
  // unfolding could not reach (a pathological fan) are left out.
  std::vector<Index> vertex;
  std::vector<Vec2> u;
  std::vector<std::uint8_t> ring;
  // 1 where the geodesic could only be continued past a feature or boundary
  // vertex on its far side (it touches the vertex, or comes from one that
  // does): such vertices are mapped, but are no g-neighbours, and no
  // straight segment to them stays on the near side.
  std::vector<std::uint8_t> touches_blocked;

  Index size() const { return static_cast<Index>(vertex.size()); }
};

class LocalGeodesicMapper {
 public:
  explicit LocalGeodesicMapper(const GeodesicMapDomain& domain);

  // Map the `rings`-ring (1..254) of `centre`. The result stays valid until
  // the next call.
  const LocalGeodesicMap& compute(Index centre, int rings);
  const LocalGeodesicMap& map() const { return map_; }
  // The index of vertex v in the last map, or kInvalid.
  Index local(Index v) const { return stamp_[v] == current_ ? local_[v] : kInvalid; }

 private:
  // The best candidate of each kind a vertex has received (dist = inf if none).
  enum Kind { kStraight, kBent, kUnfolded, kBlocked, kKinds };
  struct Candidates {
    Vec2 u[kKinds];
    double dist[kKinds];
    Index from[kKinds][2];  // the settled corners each came from
    int chosen;             // the kind in effect, see choose()
  };
  void choose(Candidates& c) const;
  void push(Index i, double key);
  void add(Index v, int ring);
  void layout_fan();
  void unfold(Index a, Index b, Index c, bool c_left);

  const GeodesicMapDomain& domain_;
  const Surface& s_;
  LocalGeodesicMap map_;
  std::vector<std::uint32_t> stamp_;
  std::vector<Index> local_;
  std::uint32_t current_ = 0;
  // per local vertex, during compute()
  std::vector<std::uint8_t> state_;  // 0 unreached, 1 candidate, 2 settled
  std::vector<Candidates> cand_;
  std::vector<double> key_;                  // the latest heap key of each vertex
  std::vector<std::uint8_t> deferred_;       // settling was put off once already
  std::vector<std::pair<double, Index>> heap_;
};

}  // namespace stripweave
