// OBJ: "v x y z [w | r g b]" and "f a b c ..." with corners "i", "i/t",
// "i//n" or "i/t/n" (1-based; negative: relative to the last vertex); every
// other statement (vt, vn, o, g, s, usemtl, mtllib, l, p) carries no surface.
#include "stripweave/io/mesh_readers.h"

#include "stripweave/io/mesh_text.h"
#include "stripweave/io/polygon_triangulation.h"

#include <charconv>

namespace stripweave {

namespace {

// The vertex index of a corner token, 0-based and checked: only the part
// before the first '/' names the vertex, and it must be a whole number.
Index corner_index(const MeshText& text, std::size_t token, long long vertices) {
  const std::string_view t = text.tokens()[token];
  const std::string_view head = t.substr(0, t.find('/'));
  long long i = 0;
  const auto [end, ec] = std::from_chars(head.data(), head.data() + head.size(), i);
  if (head.empty() || ec != std::errc() || end != head.data() + head.size())
    text.fail("the corner '" + std::string(t) + "' does not start with a whole vertex number");
  const long long zero_based = i > 0 ? i - 1 : vertices + i;
  if (i == 0 || zero_based < 0 || zero_based >= vertices)
    text.fail("the corner '" + std::string(t) + "' refers to no vertex (the file has " + std::to_string(vertices) +
              " so far; OBJ counts from 1)");
  return static_cast<Index>(zero_based);
}

}  // namespace

TriangleMesh read_obj(const std::string& path, const std::string& bytes) {
  MeshText text(path, bytes);
  TriangleMesh mesh;
  std::vector<Index> corners;
  while (text.next_line()) {
    const std::string_view kind = text.tokens()[0];
    if (kind == "v") {
      mesh.positions.emplace_back(text.number(1, "x"), text.number(2, "y"), text.number(3, "z"));
    } else if (kind == "f") {
      const std::size_t n = text.tokens().size() - 1;
      if (n > kMaxPolygonCorners)
        text.fail("a face of " + std::to_string(n) + " corners (at most " + std::to_string(kMaxPolygonCorners) + ")");
      corners.clear();
      for (std::size_t k = 1; k <= n; ++k) corners.push_back(corner_index(text, k, mesh.num_vertices()));
      if (!triangulate_polygon(mesh.positions, corners, mesh.triangles))
        text.fail("the face of " + std::to_string(n) + " corners crosses itself");
    }
  }
  return mesh;
}

}  // namespace stripweave
