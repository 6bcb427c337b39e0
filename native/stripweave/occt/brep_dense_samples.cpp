// BrepSource::dense_samples and BrepSource::foot_on_face: the source B-rep
// as exact samples for measuring a fit (surfacing/fit_deviation.h).
//
// dense_samples(spacing, chord)
//   BRepMesh (edges at a linear deflection of 2 * chord, the interior at 16
//   * chord) gives each face triangles with (u, v) nodes. Each triangle is
//   subdivided n x n in its (u, v) (n from 1), every sub-triangle vertex
//   evaluated on the face's surface; where a sub-triangle's centroid (the
//   exact point at its centroid's (u, v) against the flat centroid) lies
//   more than `chord` off, n grows by the square-root law of the chordal
//   error (error ~ h^2) and the triangle is done again. That fine mesh
//   gives the triangle's area; the samples, about `spacing` apart, are exact
//   points at the centroids of its longest-edge bisection (add_samples),
//   their weights summing to that area. Faces are sampled side by side (one adaptor per
//   face, made in the thread that samples it) and concatenated in face
//   order, so the result does not depend on the thread count.
//   A face BRepMesh leaves empty is meshed again on its own at other
//   deflections; if none works it has no samples, and its area is reported
//   (unmeshed_area) so that a coverage figure can count it as unmeasured.
// foot_on_face(f, p, uv)
//   Gauss-Newton on the face's surface from uv (a point within the trim),
//   each step halved until it brings the point closer, (u, v) kept within
//   the face's (u, v) box (BRepTools::UVBounds): a local search stays on
//   the face rather than jumping to the untrimmed surface's far side. Where
//   the foot lands past the trim (a sample beyond a face border), the
//   nearest point of the face within it lies on its border: the nearest of
//   the start and the points of the face's edges nearest to p. Not
//   thread-safe (per-face caches): a thread uses its own thread_copy().
#include "stripweave/core/parallel.h"
#include "stripweave/occt/brep_source.h"
#include "stripweave/occt/brep_source_impl.h"

#include <BRepGProp.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <IMeshTools_Parameters.hxx>
#include <Poly_Triangulation.hxx>
#include <Standard_Failure.hxx>

#include <cmath>

namespace stripweave {

namespace {

constexpr int kMaxSubdivision = 64;

Vec3 value_at(const BRepAdaptor_Surface& s, const Vec2& uv) {
  const gp_Pnt p = s.Value(uv.x(), uv.y());
  return {p.X(), p.Y(), p.Z()};
}

// One BRepMesh triangle (its (u, v) nodes) subdivided n x n: vertices at
// barycentric (i, j) / n, sub-triangles "up" and "down".
struct Subdivided {
  std::vector<Vec2> uv;
  std::vector<Vec3> xyz;
  std::vector<Tri> tris;
  std::vector<Vec3> centre;
  double max_chord = 0;
};

Subdivided subdivide(const BRepAdaptor_Surface& s, const std::array<Vec2, 3>& uv, int n) {
  Subdivided out;
  auto id = [n](int i, int j) { return i * (n + 1) - i * (i - 1) / 2 + j; };  // row i holds n + 1 - i
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double a = double(i) / n, b = double(j) / n;
      const Vec2 q = (1 - a - b) * uv[0] + a * uv[1] + b * uv[2];
      out.uv.push_back(q);
      out.xyz.push_back(value_at(s, q));
    }
  auto add = [&](Index a, Index b, Index c) {
    out.tris.push_back({a, b, c});
    const Vec2 q = (out.uv[a] + out.uv[b] + out.uv[c]) / 3;
    const Vec3 x = value_at(s, q);
    out.centre.push_back(x);
    out.max_chord = std::max(out.max_chord, (x - (out.xyz[a] + out.xyz[b] + out.xyz[c]) / 3).norm());
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      add(id(i, j), id(i + 1, j), id(i, j + 1));
      if (i + j + 2 <= n) add(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return out;
}

// Samples of one BRepMesh triangle (its (u, v) and exact corners x) about
// `spacing` apart, their weights summing to `area`: the triangle bisected at
// the middle of its longest edge (in (u, v), the new corner evaluated on the
// surface) until no edge is longer than the spacing, one sample at each
// piece's centroid. Unlike an n x n subdivision this stays proportional to
// the area on long thin triangles (a planar face's few long slivers).
void add_samples(const BRepAdaptor_Surface& surface, const std::array<Vec2, 3>& uv, const std::array<Vec3, 3>& x,
                 double spacing, double area, BrepDenseSamples& s) {
  struct Piece {
    std::array<Vec2, 3> uv;
    std::array<Vec3, 3> x;
    int depth;
  };
  std::vector<Piece> stack{{uv, x, 0}};
  std::vector<Vec3> points;
  std::vector<double> weights;
  double total = 0;
  while (!stack.empty()) {
    const Piece p = stack.back();
    stack.pop_back();
    int longest = 0;
    double length = 0;
    for (int k = 0; k < 3; ++k) {
      const double l = (p.x[(k + 1) % 3] - p.x[k]).norm();
      if (l > length) length = l, longest = k;
    }
    if (length > spacing && p.depth < 24) {
      const int a = longest, b = (longest + 1) % 3, c = (longest + 2) % 3;
      const Vec2 m = 0.5 * (p.uv[a] + p.uv[b]);
      const Vec3 xm = value_at(surface, m);
      stack.push_back({{p.uv[a], m, p.uv[c]}, {p.x[a], xm, p.x[c]}, p.depth + 1});
      stack.push_back({{m, p.uv[b], p.uv[c]}, {xm, p.x[b], p.x[c]}, p.depth + 1});
      continue;
    }
    points.push_back(value_at(surface, (p.uv[0] + p.uv[1] + p.uv[2]) / 3));
    weights.push_back(0.5 * (p.x[1] - p.x[0]).cross(p.x[2] - p.x[0]).norm());
    total += weights.back();
  }
  for (size_t k = 0; k < points.size(); ++k) {
    s.points.push_back(points[k]);
    s.area.push_back(total > 0 ? area * weights[k] / total : area / points.size());
  }
}

struct FaceSamples {
  BrepDenseSamples s;
  bool meshed = true;
};

FaceSamples sample_face(const TopoDS_Face& face, Index f, double spacing, double chord) {
  FaceSamples out;
  TopLoc_Location loc;
  const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
  if (tri.IsNull() || tri->NbTriangles() == 0 || !tri->HasUVNodes()) {
    out.meshed = false;
    return out;
  }
  const BRepAdaptor_Surface surface(face, false);
  BrepDenseSamples& s = out.s;
  for (Index t = 1; t <= tri->NbTriangles(); ++t) {
    Standard_Integer a, b, c;
    tri->Triangle(t).Get(a, b, c);
    std::array<Vec2, 3> uv;
    std::array<Vec3, 3> x;
    const Standard_Integer nodes[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const gp_Pnt2d q = tri->UVNode(nodes[k]);
      uv[k] = Vec2(q.X(), q.Y());
      x[k] = value_at(surface, uv[k]);
    }
    // The tessellation: as fine as `chord` asks.
    int n = 1;
    Subdivided d = subdivide(surface, uv, n);
    while (d.max_chord > chord && n < kMaxSubdivision) {
      n = std::min(kMaxSubdivision, std::max(n + 1, static_cast<int>(std::ceil(1.1 * n * std::sqrt(d.max_chord / chord)))));
      d = subdivide(surface, uv, n);
    }
    const Index base = s.mesh.num_vertices();
    s.mesh.positions.insert(s.mesh.positions.end(), d.xyz.begin(), d.xyz.end());
    s.uv.insert(s.uv.end(), d.uv.begin(), d.uv.end());
    double fine_area = 0;
    for (const Tri& q : d.tris) {
      s.mesh.triangles.push_back({base + q[0], base + q[1], base + q[2]});
      s.face.push_back(f);
      fine_area += 0.5 * (d.xyz[q[1]] - d.xyz[q[0]]).cross(d.xyz[q[2]] - d.xyz[q[0]]).norm();
    }
    // The samples: `spacing` apart, weighted by the fine mesh's area.
    add_samples(surface, uv, x, spacing, fine_area, s);
    s.max_chord = std::max(s.max_chord, d.max_chord);
  }
  return out;
}

}  // namespace

BrepDenseSamples BrepSource::dense_samples(double spacing, double chord) const {
  const Impl& s = *impl_;
  BRepTools::Clean(s.shape);
  try {
    // Edges fine (their polygons bound the samples' reach), the interior
    // coarse: the subdivision below refines it at a fraction of the cost.
    IMeshTools_Parameters parameters;
    parameters.Deflection = 2 * chord;
    parameters.Angle = 0.35;
    parameters.DeflectionInterior = 16 * chord;
    parameters.AngleInterior = 0.5;
    parameters.Relative = false;
    parameters.InParallel = false;
    BRepMesh_IncrementalMesh mesher(s.shape, parameters);
  } catch (const Standard_Failure&) {
    // Faces left without triangles are counted below.
  }
  const Index nf = num_faces();
  std::vector<FaceSamples> per_face(nf);
  parallel_for(nf, [&](Index f) {
    try {
      per_face[f] = sample_face(s.face(f), f, spacing, chord);
    } catch (const Standard_Failure&) {
      per_face[f] = FaceSamples();
      per_face[f].meshed = false;
    }
  });
  // BRepMesh leaves a face empty now and then for one set of parameters
  // and not for another: such faces are meshed again on their own.
  for (Index f = 0; f < nf; ++f)
    for (double deflection : {8 * chord, 2 * chord, 32 * chord}) {
      if (per_face[f].meshed) break;
      try {
        BRepMesh_IncrementalMesh mesher(s.face(f), deflection, false, 0.5, false);
        per_face[f] = sample_face(s.face(f), f, spacing, chord);
      } catch (const Standard_Failure&) {
      }
    }
  BRepTools::Clean(s.shape);  // leave the shape as tessellate() expects to find it
  BrepDenseSamples out;
  for (Index f = 0; f < nf; ++f) {
    FaceSamples& F = per_face[f];
    if (!F.meshed) {
      GProp_GProps props;
      BRepGProp::SurfaceProperties(s.face(f), props);
      ++out.unmeshed_faces;
      out.unmeshed_area += std::abs(props.Mass());
      continue;
    }
    const Index base = out.mesh.num_vertices();
    out.mesh.positions.insert(out.mesh.positions.end(), F.s.mesh.positions.begin(), F.s.mesh.positions.end());
    for (const Tri& t : F.s.mesh.triangles) out.mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    out.uv.insert(out.uv.end(), F.s.uv.begin(), F.s.uv.end());
    out.face.insert(out.face.end(), F.s.face.begin(), F.s.face.end());
    out.points.insert(out.points.end(), F.s.points.begin(), F.s.points.end());
    out.area.insert(out.area.end(), F.s.area.begin(), F.s.area.end());
    out.max_chord = std::max(out.max_chord, F.s.max_chord);
  }
  return out;
}

Vec3 BrepSource::foot_on_face(Index face, const Vec3& p, Vec2& uv, double* distance) const {
  const Impl& s = *impl_;
  auto& adaptor = s.adaptors[face];
  if (!adaptor) {
    adaptor = std::make_unique<BRepAdaptor_Surface>(s.face(face), false);
    double u0, u1, v0, v1;
    BRepTools::UVBounds(s.face(face), u0, u1, v0, v1);
    s.uv_box[face] = {u0, u1, v0, v1};
  }
  const auto& box = s.uv_box[face];
  auto clamp = [&](const Vec2& q) { return Vec2(std::clamp(q.x(), box[0], box[1]), std::clamp(q.y(), box[2], box[3])); };
  const Vec2 start = uv;
  const Vec3 start_x = value_at(*adaptor, uv);
  Vec3 best_x = start_x;
  double best = (best_x - p).squaredNorm();
  try {
    for (int it = 0; it < 20; ++it) {
      gp_Pnt S;
      gp_Vec Su, Sv;
      adaptor->D1(uv.x(), uv.y(), S, Su, Sv);
      const Vec3 r(p.x() - S.X(), p.y() - S.Y(), p.z() - S.Z());
      const Vec3 a(Su.X(), Su.Y(), Su.Z()), b(Sv.X(), Sv.Y(), Sv.Z());
      Eigen::Matrix2d J;
      J << a.dot(a), a.dot(b), a.dot(b), b.dot(b);
      if (std::abs(J.determinant()) < 1e-300) break;
      Vec2 step = J.ldlt().solve(Vec2(a.dot(r), b.dot(r)));
      bool better = false;
      for (int half = 0; half < 8 && !better; ++half, step *= 0.5) {
        const Vec2 next = clamp(uv + step);
        const Vec3 x = value_at(*adaptor, next);
        const double d = (x - p).squaredNorm();
        if (d < best) best = d, best_x = x, uv = next, better = true;
      }
      if (!better || step.squaredNorm() < 1e-28) break;
    }
    // A foot past the trim is no point of the part: the nearest point
    // within it is then on the face's border (or no nearer than the start).
    if (uv != start && !s.inside_trim(face, BRep_Tool::Surface(s.face(face)), gp_Pnt2d(uv.x(), uv.y()))) {
      best_x = start_x, best = (start_x - p).squaredNorm(), uv = start;
      for (Index e : face_edges(face)) {
        double d;
        const Vec3 q = project_to_edge(e, p, &d);
        if (d * d < best) best = d * d, best_x = q;
      }
    }
  } catch (const Standard_Failure&) {
    // A singular point (a pole): keep the best point found.
  }
  if (distance) *distance = std::sqrt(best);
  return best_x;
}

}  // namespace stripweave
