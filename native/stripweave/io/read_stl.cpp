// STL, binary (80-byte header, uint32 count, 50 bytes per triangle) or ASCII
// ("solid" ... "facet normal" "outer loop" 3 x "vertex x y z" "endloop"
// "endfacet" ... "endsolid").
// A file whose size is exactly 84 + 50 n for its count n is binary, even if
// its header starts with "solid" (some exporters write that); otherwise one
// starting with "solid" is ASCII, and any other is a binary file whose count
// lies, refused: a count smaller than the data was read as its first
// triangles only, silently.
#include "stripweave/io/mesh_readers.h"

#include "stripweave/io/mesh_text.h"

#include <cstdint>
#include <cstring>

namespace stripweave {

namespace {

constexpr std::size_t kHeader = 84, kRecord = 50;

std::uint32_t le32(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
}

float le_float(const char* p) {
  const std::uint32_t bits = le32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

bool starts_with_solid(const std::string& bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  return bytes.compare(i, 5, "solid") == 0;
}

TriangleMesh read_binary(const std::string& bytes) {
  const std::size_t n = le32(bytes.data() + 80);
  TriangleMesh mesh;
  mesh.positions.reserve(3 * n);
  mesh.triangles.reserve(n);
  for (std::size_t t = 0; t < n; ++t) {
    const char* r = bytes.data() + kHeader + kRecord * t + 12;  // after the normal
    const Index base = static_cast<Index>(mesh.positions.size());
    for (int c = 0; c < 3; ++c, r += 12) mesh.positions.emplace_back(le_float(r), le_float(r + 4), le_float(r + 8));
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

void expect(MeshText& text, std::size_t token, const char* word) {
  if (token >= text.tokens().size() || text.tokens()[token] != word)
    text.fail(std::string("'") + word + "' expected" +
              (token < text.tokens().size() ? ", found '" + std::string(text.tokens()[token]) + "'" : ""));
}

TriangleMesh read_ascii(const std::string& path, const std::string& bytes) {
  MeshText text(path, bytes);
  TriangleMesh mesh;
  bool in_solid = false;
  while (text.next_line()) {
    const std::string_view kind = text.tokens()[0];
    if (kind == "solid" && !in_solid) {
      in_solid = true;
    } else if (kind == "endsolid" && in_solid) {
      in_solid = false;
    } else if (kind == "facet" && in_solid) {
      if (!text.next_line()) text.fail("the file ends inside a facet");
      expect(text, 0, "outer"), expect(text, 1, "loop");
      const Index base = mesh.num_vertices();
      for (int c = 0; c < 3; ++c) {
        if (!text.next_line()) text.fail("the file ends inside a facet");
        expect(text, 0, "vertex");
        if (text.tokens().size() != 4) text.fail("a vertex line holds 'vertex x y z'");
        mesh.positions.emplace_back(text.number(1, "x"), text.number(2, "y"), text.number(3, "z"));
      }
      if (!text.next_line()) text.fail("the file ends inside a facet");
      expect(text, 0, "endloop");
      if (!text.next_line()) text.fail("the file ends inside a facet");
      expect(text, 0, "endfacet");
      mesh.triangles.push_back({base, base + 1, base + 2});
    } else {
      text.fail("'" + std::string(kind) + "' where " + (in_solid ? "'facet' or 'endsolid'" : "'solid'") +
                " is due");
    }
  }
  if (in_solid) text.fail("the file ends without 'endsolid'");
  return mesh;
}

}  // namespace

TriangleMesh read_stl(const std::string& path, const std::string& bytes) {
  if (bytes.size() >= kHeader && bytes.size() == kHeader + kRecord * std::size_t(le32(bytes.data() + 80)))
    return read_binary(bytes);
  // ASCII holds no NUL byte; a binary header that starts with "solid" does.
  if (starts_with_solid(bytes) && bytes.find('\0') == std::string::npos) return read_ascii(path, bytes);
  if (bytes.size() < kHeader)
    throw_mesh_read(path, "a binary STL holds at least 84 bytes, this file " + std::to_string(bytes.size()));
  const std::size_t n = le32(bytes.data() + 80);
  const std::size_t data = bytes.size() - kHeader;
  throw_mesh_read(path, "byte 80: the binary STL header counts " + std::to_string(n) + " triangles (" +
                            std::to_string(kHeader + kRecord * n) + " bytes), the file has " +
                            std::to_string(bytes.size()) + " bytes (" + std::to_string(data / kRecord) +
                            " triangles" + (data % kRecord ? " and " + std::to_string(data % kRecord) + " bytes" : "") +
                            " of data)");
}

}  // namespace stripweave
