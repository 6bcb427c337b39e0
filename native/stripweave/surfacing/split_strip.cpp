#include "stripweave/surfacing/split_strip.h"

#include "stripweave/core/error.h"
#include "stripweave/surfacing/patch_parameterization.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace stripweave {

namespace {

// A vertex this close to the isoline (square-map units) lies on it: the cut
// runs through it instead of leaving a sliver beside it.
constexpr double kSnap = 1e-3;

struct SideUse {
  Index patch = kInvalid;
  int side = 0;
};

// The cut through one patch of the strip: the isoline w = c of its square
// map, w being u (direction 0) or v (direction 1).
struct Crossing {
  Index patch = kInvalid;
  int direction = 0;
  double c = 0;
};

// Where an edge is cut: at arc-length fraction t from v0, through polyline
// point `through` (snapped), or else inside the segment ending at point
// `after`, at `point`.
struct EdgeCut {
  double t = 0;
  Index through = kInvalid;
  Index after = kInvalid;
  Vec3 point = Vec3::Zero();
  Index vertex = kInvalid;  // the new network vertex
  Index second = kInvalid;  // the edge's second half (appended)
  // -1 before the cut (towards v0), 0 on it, +1 after.
  int sign(Index i) const {
    if (through != kInvalid) return i < through ? -1 : (i == through ? 0 : 1);
    return i < after ? -1 : 1;
  }
};

// The isoline w = c meets side s at this fraction of its edge's arc length
// from v0 (sides 0 and 1 run with w, sides 2 and 3 against it), and back.
double edge_fraction(const NetworkPatch& P, int s, double c) {
  const double along = s < 2 ? c : 1 - c;
  return P.reversed[s] ? 1 - along : along;
}

double iso_value(const NetworkPatch& P, int s, double t) {
  const double along = P.reversed[s] ? 1 - t : t;
  return s < 2 ? along : 1 - along;
}

// The strip through the start crossing: walk out through the side opposite
// the one entered, to a boundary edge or back to the start. Fills the
// crossings (in order along the strip) and each crossed edge's fraction.
std::string walk_strip(const PatchNetwork& net, const std::vector<std::vector<SideUse>>& uses,
                       const Crossing& start, std::vector<Crossing>& chain, std::map<Index, double>& edge_t,
                       bool& closed) {
  std::vector<bool> visited(net.patches.size(), false);
  visited[start.patch] = true;
  chain.assign(1, start);
  closed = false;
  auto walk = [&](int first_side, std::vector<Crossing>& out) -> std::string {
    Crossing at = start;
    int side = first_side;
    for (;;) {
      const NetworkPatch& P = net.patches[at.patch];
      const Index e = P.edges[side];
      const double t = edge_fraction(P, side, at.c);
      const auto known = edge_t.find(e);
      if (known != edge_t.end() && std::abs(known->second - t) > 1e-9)
        return "the strip comes back to edge " + std::to_string(e) + " at another fraction (a twisted strip)";
      edge_t[e] = t;
      const SideUse* next = nullptr;
      for (const SideUse& u : uses[e])
        if (u.patch != at.patch || u.side != side) next = &u;
      if (!next) return "";  // a boundary edge: the strip ends here
      const NetworkPatch& Q = net.patches[next->patch];
      const Crossing q{next->patch, next->side % 2, iso_value(Q, next->side, t)};
      if (visited[q.patch]) {
        if (q.patch == start.patch && q.direction == start.direction && std::abs(q.c - start.c) <= 1e-9) {
          closed = true;
          return "";
        }
        return "the strip crosses itself at patch " + std::to_string(q.patch);
      }
      visited[q.patch] = true;
      out.push_back(q);
      at = q;
      side = (next->side + 2) % 4;
    }
  };
  std::vector<Crossing> forward, backward;
  std::string error = walk(start.direction + 2, forward);
  if (error.empty() && !closed) error = walk(start.direction, backward);
  if (!error.empty()) return error;
  chain.assign(backward.rbegin(), backward.rend());
  chain.push_back(start);
  chain.insert(chain.end(), forward.begin(), forward.end());
  return "";
}

EdgeCut cut_edge(const NetworkEdge& E, double t) {
  const size_t n = E.points.size();
  std::vector<double> T(n, 0.0);
  for (size_t k = 1; k < n; ++k) T[k] = T[k - 1] + (E.points[k] - E.points[k - 1]).norm();
  for (double& x : T) x /= T.back();
  EdgeCut cut;
  cut.t = t;
  for (size_t k = 1; k + 1 < n; ++k)
    if (std::abs(T[k] - t) <= kSnap) {
      cut.through = static_cast<Index>(k);
      cut.point = E.points[k];
      return cut;
    }
  size_t k = 1;
  while (k + 1 < n && T[k] < t) ++k;
  cut.after = static_cast<Index>(k);
  const double s = (t - T[k - 1]) / std::max(T[k] - T[k - 1], 1e-300);
  cut.point = E.points[k - 1] + std::clamp(s, 0.0, 1.0) * (E.points[k] - E.points[k - 1]);
  return cut;
}

// A patch cut along its isoline: the piece where w < c and the one where
// w > c, with their corners (the network's edges are set later), and the
// cut polyline from side d to side d + 2.
struct Pieces {
  NetworkPatch lower, upper;
  std::vector<Vec3> cut;
};

struct PieceBuilder {
  const NetworkPatch& P;
  std::vector<Vec3>& positions;
  NetworkPatch piece;
  std::map<Index, Index> local;
  Index id(Index v) {
    const auto [it, fresh] = local.emplace(v, piece.mesh.num_vertices());
    if (fresh) piece.mesh.positions.push_back(positions[v]);
    return it->second;
  }
  void add(const Tri& t, Index source_triangle) {
    piece.mesh.triangles.push_back({id(t[0]), id(t[1]), id(t[2])});
    if (P.source_face.size() == P.mesh.triangles.size()) piece.source_face.push_back(P.source_face[source_triangle]);
  }
  void set_corners(const std::array<Index, 4>& c) {
    for (int k = 0; k < 4; ++k) piece.corners[k] = id(c[k]);
  }
};

// The isoline w = c on a patch mesh: per vertex its side of it (-1, 0 on
// it, +1), and the mesh vertices added where it crosses mesh edges.
struct Isoline {
  double c = 0;
  std::vector<Vec3> positions;  // the patch mesh's, then the crossings
  std::vector<double> w;
  std::vector<int> sign;
  std::map<EdgeKey, Index> crossing;
  std::array<Index, 2> ends{};  // where it leaves through side d and side d + 2
  Index cross(Index a, Index b) {
    const auto [it, fresh] = crossing.emplace(edge_key(a, b), static_cast<Index>(positions.size()));
    if (fresh) {
      const double s = std::clamp((c - w[a]) / (w[b] - w[a]), 0.0, 1.0);
      positions.push_back(positions[a] + s * (positions[b] - positions[a]));
    }
    return it->second;
  }
};

Isoline isoline(const NetworkPatch& P, const PatchParameterization& map, const Crossing& x,
                const std::map<Index, EdgeCut>& cuts) {
  const int d = x.direction;
  Isoline iso;
  iso.c = x.c;
  iso.positions = P.mesh.positions;
  const Index nv = P.mesh.num_vertices();
  iso.w.resize(nv), iso.sign.resize(nv);
  for (Index v = 0; v < nv; ++v) {
    iso.w[v] = map.uv[v][d];
    iso.sign[v] = iso.w[v] < x.c - kSnap ? -1 : (iso.w[v] > x.c + kSnap ? 1 : 0);
  }
  // The cut sides take their signs and their crossing from their edge's
  // cut, so that both patches on an edge cut it at the same point.
  for (int k = 0; k < 2; ++k) {
    const int s = d + 2 * k;
    const EdgeCut& ec = cuts.at(P.edges[s]);
    const auto& sv = map.side_vertices[s];
    const Index n = static_cast<Index>(sv.size());
    const bool rev = P.reversed[s];
    auto at = [&](Index i) { return sv[rev ? n - 1 - i : i]; };  // the side vertex at edge point i
    const int flip = (s < 2 ? 1 : -1) * (rev ? -1 : 1);
    for (Index i = 0; i < n; ++i) iso.sign[at(i)] = flip * ec.sign(i);
    if (ec.through != kInvalid) {
      iso.ends[k] = at(ec.through);
    } else {
      iso.positions.push_back(ec.point);
      iso.ends[k] = static_cast<Index>(iso.positions.size()) - 1;
      iso.crossing[edge_key(at(ec.after - 1), at(ec.after))] = iso.ends[k];
    }
  }
  return iso;
}

// Each triangle to the piece on its side of the isoline; a triangle it
// crosses is cut linearly, into one triangle on one side and a quad (two
// triangles) on the other, or two triangles when it runs through a vertex.
void cut_triangles(const NetworkPatch& P, Isoline& iso, PieceBuilder& lower, PieceBuilder& upper) {
  const auto& sign = iso.sign;
  auto to = [&](int s) -> PieceBuilder& { return s < 0 ? lower : upper; };
  for (Index t = 0; t < P.mesh.num_triangles(); ++t) {
    const Tri& f = P.mesh.triangles[t];
    const bool any_lower = sign[f[0]] < 0 || sign[f[1]] < 0 || sign[f[2]] < 0;
    const bool any_upper = sign[f[0]] > 0 || sign[f[1]] > 0 || sign[f[2]] > 0;
    if (!any_lower || !any_upper) {
      to(any_lower ? -1 : 1).add(f, t);
      continue;
    }
    // Rotate (keeping the orientation) so the vertex alone on its side, or
    // on the isoline, comes first.
    for (int r = 0; r < 3; ++r) {
      const Index a = f[r], b = f[(r + 1) % 3], e = f[(r + 2) % 3];
      if (sign[a] == 0) {
        const Index X = iso.cross(b, e);
        to(sign[b]).add({a, b, X}, t);
        to(sign[e]).add({a, X, e}, t);
        break;
      }
      if (sign[b] != 0 && sign[e] != 0 && sign[b] == sign[e] && sign[a] == -sign[b]) {
        const Index X = iso.cross(a, b), Y = iso.cross(a, e);
        to(sign[a]).add({a, X, Y}, t);
        to(sign[b]).add({X, b, e}, t);
        to(sign[b]).add({X, e, Y}, t);
        break;
      }
    }
  }
}

Pieces cut_patch(const NetworkPatch& P, const Crossing& x, const std::map<Index, EdgeCut>& cuts) {
  const int d = x.direction;
  Isoline iso = isoline(P, square_map(P), x, cuts);
  PieceBuilder lower{P, iso.positions, {}, {}}, upper{P, iso.positions, {}, {}};
  cut_triangles(P, iso, lower, upper);
  const auto& C = P.corners;
  const Index A = iso.ends[0], B = iso.ends[1];
  if (d == 0) {
    lower.set_corners({C[0], A, B, C[3]});
    upper.set_corners({A, C[1], C[2], B});
  } else {
    lower.set_corners({C[0], C[1], A, B});
    upper.set_corners({B, A, C[2], C[3]});
  }
  lower.piece.even_stretch = upper.piece.even_stretch = P.even_stretch;
  Pieces out;
  // The cut is side 1 (direction 0) or side 2 (direction 1) of the lower
  // piece, from A to B.
  const PatchParameterization lower_map = square_sides(lower.piece);
  for (Index v : lower_map.side_vertices[d == 0 ? 1 : 2]) out.cut.push_back(lower.piece.mesh.positions[v]);
  out.lower = std::move(lower.piece);
  out.upper = std::move(upper.piece);
  return out;
}

// Edge e cut in two: its first half keeps the index, the second is appended.
void split_edge(PatchNetwork& net, Index e, EdgeCut& cut) {
  NetworkEdge first = net.edges[e];
  NetworkEdge second = first;
  net.vertices.push_back(cut.point);
  cut.vertex = static_cast<Index>(net.vertices.size()) - 1;
  const auto& pts = net.edges[e].points;
  const Index end = cut.through != kInvalid ? cut.through : cut.after - 1;  // last point kept in the first half
  first.points.assign(pts.begin(), pts.begin() + end + 1);
  second.points.assign(pts.begin() + (cut.through != kInvalid ? cut.through : cut.after), pts.end());
  if (cut.through == kInvalid) {
    first.points.push_back(cut.point);
    second.points.insert(second.points.begin(), cut.point);
  }
  first.v1 = cut.vertex;
  second.v0 = cut.vertex;
  net.edges[e] = std::move(first);
  net.edges.push_back(std::move(second));
  cut.second = static_cast<Index>(net.edges.size()) - 1;
}

// Side s of the patch cut in two at its edge's cut: the part from corner s
// to the cut (first) or from the cut to corner s + 1, as (edge, reversed).
std::pair<Index, bool> side_part(const NetworkPatch& P, int s, const EdgeCut& cut, bool first) {
  const Index e = P.edges[s];
  const bool rev = P.reversed[s];
  return {first != rev ? e : cut.second, rev};
}

void set_side(NetworkPatch& piece, int s, std::pair<Index, bool> edge) {
  piece.edges[s] = edge.first;
  piece.reversed[s] = edge.second;
}

// A piece is a quad disc whose sides carry their edges' points.
void check_piece(const PatchNetwork& net, const NetworkPatch& piece) {
  const PatchParameterization map = square_sides(piece);
  for (int s = 0; s < 4; ++s)
    if (map.side_vertices[s].size() != net.edges[piece.edges[s]].points.size())
      throw InputError("a piece's side does not carry its edge's points");
}

}  // namespace

StripSplit split_strip(PatchNetwork& network, const StripCut& cut) {
  StripSplit out;
  const Index nP = static_cast<Index>(network.patches.size());
  if (cut.patch < 0 || cut.patch >= nP || cut.direction < 0 || cut.direction > 1 || !(cut.at > 0 && cut.at < 1))
    throw InputError("split_strip: no such patch, direction or isoline");
  std::vector<std::vector<SideUse>> uses(network.edges.size());
  for (Index p = 0; p < nP; ++p)
    for (int s = 0; s < 4; ++s) uses[network.patches[p].edges[s]].push_back({p, s});

  std::vector<Crossing> chain;
  std::map<Index, double> edge_t;
  out.why_not = walk_strip(network, uses, {cut.patch, cut.direction, cut.at}, chain, edge_t, out.closed);
  if (!out.why_not.empty()) return out;

  PatchNetwork net = network;
  std::map<Index, EdgeCut> cuts;
  for (const auto& [e, t] : edge_t) cuts[e] = cut_edge(network.edges[e], t);
  try {
    std::vector<Pieces> pieces;
    for (const Crossing& x : chain) pieces.push_back(cut_patch(network.patches[x.patch], x, cuts));
    for (auto& [e, c] : cuts) split_edge(net, e, c);
    for (size_t k = 0; k < chain.size(); ++k) {
      const Crossing& x = chain[k];
      const NetworkPatch& P = network.patches[x.patch];
      const int d = x.direction;
      const EdgeCut &a = cuts.at(P.edges[d]), &b = cuts.at(P.edges[d + 2]);
      NetworkEdge across;
      across.points = std::move(pieces[k].cut);
      across.v0 = a.vertex, across.v1 = b.vertex;
      net.edges.push_back(std::move(across));
      const Index e = static_cast<Index>(net.edges.size()) - 1;
      NetworkPatch &lo = pieces[k].lower, &up = pieces[k].upper;
      // Sides in the pieces' corner order (cut_patch): the cut runs from A
      // on side d to B on side d + 2.
      if (d == 0) {
        set_side(lo, 0, side_part(P, 0, a, true)), set_side(lo, 1, {e, false});
        set_side(lo, 2, side_part(P, 2, b, false)), set_side(lo, 3, {P.edges[3], P.reversed[3]});
        set_side(up, 0, side_part(P, 0, a, false)), set_side(up, 1, {P.edges[1], P.reversed[1]});
        set_side(up, 2, side_part(P, 2, b, true)), set_side(up, 3, {e, true});
      } else {
        set_side(lo, 0, {P.edges[0], P.reversed[0]}), set_side(lo, 1, side_part(P, 1, a, true));
        set_side(lo, 2, {e, false}), set_side(lo, 3, side_part(P, 3, b, false));
        set_side(up, 0, {e, true}), set_side(up, 1, side_part(P, 1, a, false));
        set_side(up, 2, {P.edges[2], P.reversed[2]}), set_side(up, 3, side_part(P, 3, b, true));
      }
      check_piece(net, lo);
      check_piece(net, up);
      net.patches[x.patch] = std::move(lo);
      net.patches.push_back(std::move(up));
      out.patches.push_back(x.patch);
      out.new_patches.push_back(static_cast<Index>(net.patches.size()) - 1);
      out.new_edges.push_back(e);
    }
  } catch (const InputError& e) {
    out = StripSplit{};
    out.why_not = std::string("a piece is not a quad disc: ") + e.what();
    return out;
  }
  network = std::move(net);
  out.done = true;
  return out;
}

}  // namespace stripweave
