// OFF: "OFF" (or COFF, NOFF, CNOFF, STOFF...: per-vertex extras after x y z),
// then "nv nf ne", nv vertex lines, nf face lines "n i1 .. in [colour]".
#include "stripweave/io/mesh_readers.h"

#include "stripweave/io/mesh_text.h"
#include "stripweave/io/polygon_triangulation.h"

namespace stripweave {

namespace {

bool is_off_keyword(std::string_view t) {
  return t.size() >= 3 && t.substr(t.size() - 3) == "OFF" && t.find_first_not_of("STCN4") == t.size() - 3;
}

// The counts, checked against what the file can hold: a vertex line takes at
// least 6 bytes ("0 0 0\n"), a face line 8 ("3 0 1 2\n").
void read_counts(MeshText& text, std::size_t first, long long& nv, long long& nf, std::size_t file_size) {
  nv = text.integer(first, "the vertex count");
  nf = text.integer(first + 1, "the face count");
  if (nv < 0 || nf < 0) text.fail("the vertex and face counts must not be negative");
  if (nv > static_cast<long long>(file_size / 6) || nf > static_cast<long long>(file_size / 8) ||
      6 * nv + 8 * nf > static_cast<long long>(file_size))
    text.fail("the header announces " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
              " faces, more than a file of " + std::to_string(file_size) + " bytes can hold");
}

}  // namespace

TriangleMesh read_off(const std::string& path, const std::string& bytes) {
  MeshText text(path, bytes);
  if (!text.next_line() || !is_off_keyword(text.tokens()[0])) text.fail("an OFF file starts with 'OFF'");
  if (text.tokens().size() > 1 && text.tokens()[1] == "BINARY") text.fail("binary OFF is not supported");
  std::size_t first = 1;
  if (text.tokens().size() == 1) {
    if (!text.next_line()) text.fail("the file ends before the vertex and face counts");
    first = 0;
  }
  long long nv = 0, nf = 0;
  read_counts(text, first, nv, nf, bytes.size());
  TriangleMesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(nv));
  for (long long v = 0; v < nv; ++v) {
    if (!text.next_line())
      text.fail("the file ends after " + std::to_string(v) + " of its " + std::to_string(nv) + " vertices");
    mesh.positions.emplace_back(text.number(0, "x"), text.number(1, "y"), text.number(2, "z"));
  }
  std::vector<Index> corners;
  for (long long f = 0; f < nf; ++f) {
    if (!text.next_line())
      text.fail("the file ends after " + std::to_string(f) + " of its " + std::to_string(nf) + " faces");
    const long long n = text.integer(0, "the corner count");
    if (n < 0 || n > static_cast<long long>(text.tokens().size()) - 1)
      text.fail("the face claims " + std::to_string(n) + " corners, its line holds " +
                std::to_string(text.tokens().size() - 1) + " numbers");
    if (n > static_cast<long long>(kMaxPolygonCorners))
      text.fail("a face of " + std::to_string(n) + " corners (at most " + std::to_string(kMaxPolygonCorners) + ")");
    if (text.tokens().size() - 1 - n > 4) text.fail("the face has more numbers than its corners and a colour");
    corners.clear();
    for (long long k = 0; k < n; ++k) {
      const long long i = text.integer(1 + k, "a vertex index");
      if (i < 0 || i >= nv)
        text.fail("the face refers to vertex " + std::to_string(i) + ", the file holds " + std::to_string(nv) +
                  " (0-based)");
      corners.push_back(static_cast<Index>(i));
    }
    if (!triangulate_polygon(mesh.positions, corners, mesh.triangles))
      text.fail("the face of " + std::to_string(n) + " corners crosses itself");
  }
  return mesh;
}

}  // namespace stripweave
