#include "stripweave/surfacing/symmetric_fit.h"

#include "stripweave/core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace stripweave {

namespace {

// The point at half the polyline's arc length: it tells apart two edges
// between the same two vertices.
Vec3 polyline_midpoint(const std::vector<Vec3>& points) {
  double length = 0;
  for (size_t k = 1; k < points.size(); ++k) length += (points[k] - points[k - 1]).norm();
  double left = length / 2;
  for (size_t k = 1; k < points.size(); ++k) {
    const double step = (points[k] - points[k - 1]).norm();
    if (step >= left && step > 0) return points[k - 1] + (left / step) * (points[k] - points[k - 1]);
    left -= step;
  }
  return points.back();
}

// Side s of a patch runs counter-clockwise from this vertex.
Index side_start(const PatchNetwork& net, const NetworkPatch& P, int s) {
  const NetworkEdge& E = net.edges[P.edges[s]];
  return P.reversed[s] ? E.v1 : E.v0;
}

// The candidate whose position lies nearest x, and its distance (kInvalid,
// infinity without candidates).
std::pair<Index, double> nearest(const std::vector<Index>& candidates, const std::vector<Vec3>& positions,
                                 const Vec3& x) {
  std::pair<Index, double> best{kInvalid, std::numeric_limits<double>::infinity()};
  for (Index c : candidates) {
    const double d = (positions[c] - x).norm();
    if (d < best.second) best = {c, d};
  }
  return best;
}

// How far an edge's mapped midpoint may lie from its image's. The layout
// places vertices symmetrically (to the symmetry tolerance) but routes edges
// over the mesh, whose triangles the symmetry does not map onto each other:
// an edge and its image both join the same two image vertices and agree to
// the mesh's resolution, a few solver edges, far more than the symmetry's
// tolerance on a coarse mesh (a half-turn box at 8,000 triangles:
// "edge 0 has no image"). Two different edges between the same two vertices
// (around a handle) lie at least about their length apart, so a quarter of
// the edge's length still tells them apart; the nearest wins, one to one.
constexpr double kEdgeMatchShare = 0.25;  // of the edge's length

double edge_match_tolerance(const std::vector<Vec3>& points, double tolerance) {
  double length = 0;
  for (size_t k = 1; k < points.size(); ++k) length += (points[k] - points[k - 1]).norm();
  return std::max(tolerance, kEdgeMatchShare * length);
}

NetworkPairing failed(NetworkPairing p, const std::string& why) {
  p.paired = false;
  p.problem = why;
  return p;
}

// The corners of the unit square, corner c at the start of side c.
const Vec2 kCorner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

int mod4(int a) { return ((a % 4) + 4) % 4; }

// Where control (i, j) of a patch goes in its image: the square's symmetry
// taking corner c to corner kappa(c) (rotation: c + shift; reflection: side
// s runs backwards along side shift - s, so corner c goes to shift + 1 - c).
std::array<int, 2> image_index(const BSplinePatch& from, const BSplinePatch& to, int i, int j, int shift,
                               bool reflection) {
  auto kappa = [&](int c) { return reflection ? mod4(shift + 1 - c) : mod4(shift + c); };
  const Vec2 o = kCorner[kappa(0)], du = kCorner[kappa(1)] - o, dv = kCorner[kappa(3)] - o;
  const double u = double(i) / (from.rows() - 1), v = double(j) / (from.cols() - 1);
  const Vec2 w = o + u * du + v * dv;
  return {int(std::lround(w.x() * (to.rows() - 1))), int(std::lround(w.y() * (to.cols() - 1)))};
}

// Whether the patch's u direction goes to the image's v direction.
bool swaps_directions(int shift, bool reflection) {
  auto kappa = [&](int c) { return reflection ? mod4(shift + 1 - c) : mod4(shift + c); };
  const Vec2 du = kCorner[kappa(1)] - kCorner[kappa(0)];
  return std::abs(du.x()) < 0.5;
}

}  // namespace

NetworkPairing pair_network(const PatchNetwork& net, const Symmetry& psi, double tolerance) {
  NetworkPairing out;
  out.reflection = psi.kind == SymmetryKind::Reflection;
  const Index nV = Index(net.vertices.size()), nE = Index(net.edges.size()), nP = Index(net.patches.size());
  // Vertices: the nearest to the mapped position, one-to-one.
  out.vertex_image.assign(nV, kInvalid);
  std::vector<bool> taken(nV, false);
  std::vector<Index> all_vertices(nV);
  std::iota(all_vertices.begin(), all_vertices.end(), 0);
  for (Index v = 0; v < nV; ++v) {
    const Vec3 x = psi.map_point(net.vertices[v]);
    const auto [best, d] = nearest(all_vertices, net.vertices, x);
    if (best == kInvalid || d > tolerance)
      return failed(out, "layout vertex " + std::to_string(v) + " has no image within the symmetry tolerance");
    if (taken[best]) return failed(out, "two layout vertices map onto vertex " + std::to_string(best));
    taken[best] = true;
    out.vertex_image[v] = best;
  }
  // Edges: between the ends' images, the nearest by the mapped midpoint.
  std::map<std::pair<Index, Index>, std::vector<Index>> between;
  for (Index e = 0; e < nE; ++e)
    between[std::minmax(net.edges[e].v0, net.edges[e].v1)].push_back(e);
  std::vector<Vec3> midpoints(nE);
  for (Index e = 0; e < nE; ++e) midpoints[e] = polyline_midpoint(net.edges[e].points);
  out.edge_image.assign(nE, kInvalid);
  out.edge_reversed.assign(nE, false);
  std::vector<bool> edge_taken(nE, false);
  for (Index e = 0; e < nE; ++e) {
    const NetworkEdge& E = net.edges[e];
    const Index a = out.vertex_image[E.v0], b = out.vertex_image[E.v1];
    const auto it = between.find(std::minmax(a, b));
    const Vec3 mid = psi.map_point(polyline_midpoint(E.points));
    const auto [best, d] = nearest(it != between.end() ? it->second : std::vector<Index>{}, midpoints, mid);
    if (best == kInvalid || d > edge_match_tolerance(E.points, tolerance))
      return failed(out, "layout edge " + std::to_string(e) + " has no image within the symmetry tolerance");
    if (edge_taken[best]) return failed(out, "two layout edges map onto edge " + std::to_string(best));
    edge_taken[best] = true;
    out.edge_image[e] = best;
    // An edge from a vertex to itself (a closed loop) keeps its direction.
    out.edge_reversed[e] = a != b && net.edges[best].v0 == b;
  }
  // Patches: the one with the four image edges, sides matched by a symmetry
  // of the square that also carries each side's start vertex.
  std::vector<std::vector<Index>> edge_patches(nE);
  for (Index p = 0; p < nP; ++p)
    for (Index e : net.patches[p].edges) edge_patches[e].push_back(p);
  out.patch_image.assign(nP, kInvalid);
  out.side_shift.assign(nP, 0);
  std::vector<bool> patch_taken(nP, false);
  for (Index p = 0; p < nP; ++p) {
    const NetworkPatch& P = net.patches[p];
    for (Index q : edge_patches[out.edge_image[P.edges[0]]]) {
      const NetworkPatch& Q = net.patches[q];
      for (int r = 0; r < 4 && out.patch_image[p] == kInvalid; ++r) {
        bool fits = true;
        for (int s = 0; s < 4 && fits; ++s) {
          const int t = out.reflection ? mod4(r - s) : mod4(r + s);
          // Reflection: the image side runs backwards, from its end.
          const Index start = out.reflection ? side_start(net, Q, mod4(t + 1)) : side_start(net, Q, t);
          fits = Q.edges[t] == out.edge_image[P.edges[s]] && start == out.vertex_image[side_start(net, P, s)];
        }
        if (fits) out.patch_image[p] = q, out.side_shift[p] = r;
      }
      if (out.patch_image[p] != kInvalid) break;
    }
    if (out.patch_image[p] == kInvalid)
      return failed(out, "layout patch " + std::to_string(p) + " has no image");
    if (patch_taken[out.patch_image[p]])
      return failed(out, "two layout patches map onto patch " + std::to_string(out.patch_image[p]));
    patch_taken[out.patch_image[p]] = true;
  }
  out.paired = true;
  return out;
}

FitNets map_nets(const FitNets& nets, const Symmetry& psi, const NetworkPairing& pairing) {
  FitNets out = nets;
  for (size_t e = 0; e < nets.edges.size(); ++e) {
    const BSplineCurve3& c = nets.edges[e];
    BSplineCurve3& to = out.edges[pairing.edge_image[e]];
    const size_t N = c.control.size();
    if (to.control.size() != N)
      throw InputError("symmetric fit: edge " + std::to_string(e) + " and its image have different spans");
    for (size_t m = 0; m < N; ++m) to.control[pairing.edge_reversed[e] ? N - 1 - m : m] = psi.map_point(c.control[m]);
  }
  for (size_t p = 0; p < nets.patches.size(); ++p) {
    const BSplinePatch& from = nets.patches[p];
    BSplinePatch& to = out.patches[pairing.patch_image[p]];
    const int shift = pairing.side_shift[p];
    const bool swap = swaps_directions(shift, pairing.reflection);
    if ((swap ? to.cols() : to.rows()) != from.rows() || (swap ? to.rows() : to.cols()) != from.cols())
      throw InputError("symmetric fit: patch " + std::to_string(p) + " and its image have different spans");
    for (int i = 0; i < from.rows(); ++i)
      for (int j = 0; j < from.cols(); ++j) {
        const auto ij = image_index(from, to, i, j, shift, pairing.reflection);
        to.P(ij[0], ij[1]) = psi.map_point(from.P(i, j));
      }
  }
  return out;
}

double symmetry_error(const FitNets& nets, const PatchNetwork& net, const std::vector<Symmetry>& symmetries,
                      const std::vector<NetworkPairing>& pairings) {
  double worst = 0;
  for (size_t k = 0; k < symmetries.size(); ++k) {
    if (!pairings[k].paired) continue;
    const FitNets mapped = map_nets(nets, symmetries[k], pairings[k]);
    for (size_t e = 0; e < nets.edges.size(); ++e)
      for (size_t m = 0; m < nets.edges[e].control.size(); ++m)
        worst = std::max(worst, (mapped.edges[e].control[m] - nets.edges[e].control[m]).norm());
    for (size_t p = 0; p < nets.patches.size(); ++p)
      for (size_t m = 0; m < nets.patches[p].control.size(); ++m)
        worst = std::max(worst, (mapped.patches[p].control[m] - nets.patches[p].control[m]).norm());
  }
  return worst;
}

namespace {

void add(FitNets& acc, const FitNets& x, double w) {
  for (size_t e = 0; e < acc.edges.size(); ++e)
    for (size_t m = 0; m < acc.edges[e].control.size(); ++m) acc.edges[e].control[m] += w * x.edges[e].control[m];
  for (size_t p = 0; p < acc.patches.size(); ++p)
    for (size_t m = 0; m < acc.patches[p].control.size(); ++m)
      acc.patches[p].control[m] += w * x.patches[p].control[m];
}

// The group mean under one symmetry: (1/n) sum_k psi^k(X[sigma^-k(x)]).
void group_mean(FitNets& nets, const Symmetry& psi, const NetworkPairing& pairing) {
  const int n = psi.kind == SymmetryKind::Reflection ? 2 : psi.order;
  FitNets acc = nets, image = nets;
  for (int k = 1; k < n; ++k) {
    image = map_nets(image, psi, pairing);
    add(acc, image, 1.0);
  }
  FitNets zero = nets;
  for (auto& c : zero.edges) std::fill(c.control.begin(), c.control.end(), Vec3::Zero());
  for (auto& p : zero.patches) std::fill(p.control.begin(), p.control.end(), Vec3::Zero());
  add(zero, acc, 1.0 / n);
  nets = std::move(zero);
}

// The patches' boundary rows are their edge curves' control points
// (fit_patch_network.h), so neighbours share them exactly.
void set_boundary_rows(FitNets& nets, const PatchNetwork& net) {
  for (size_t p = 0; p < nets.patches.size(); ++p) {
    BSplinePatch& B = nets.patches[p];
    const NetworkPatch& P = net.patches[p];
    for (int s = 0; s < 4; ++s) {
      const BSplineCurve3& c = nets.edges[P.edges[s]];
      const int N = side_size(B, s);
      if (int(c.control.size()) != N) continue;
      for (int k = 0; k < N; ++k) {
        const auto ij = side_control(B, s, k, 0);
        B.P(ij[0], ij[1]) = c.control[P.reversed[s] ? N - 1 - k : k];
      }
    }
  }
}

}  // namespace

double symmetrize_fit(FitNets& nets, const PatchNetwork& net, const std::vector<Symmetry>& symmetries,
                      const std::vector<NetworkPairing>& pairings, double diagonal) {
  // One symmetry: one mean is exact. Several: alternate the means (each an
  // orthogonal projection) until the net is invariant under all, to rounding.
  constexpr int kMaxPasses = 64;
  const double enough = 1e-13 * diagonal;
  double error = symmetry_error(nets, net, symmetries, pairings);
  for (int pass = 0; pass < kMaxPasses && error > enough; ++pass) {
    for (size_t k = 0; k < symmetries.size(); ++k)
      if (pairings[k].paired) group_mean(nets, symmetries[k], pairings[k]);
    error = symmetry_error(nets, net, symmetries, pairings);
  }
  set_boundary_rows(nets, net);
  return symmetry_error(nets, net, symmetries, pairings);
}

}  // namespace stripweave
