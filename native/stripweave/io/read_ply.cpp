// PLY (ascii, binary_little_endian, binary_big_endian; version 1.0):
//   ply / format F 1.0 / comment, obj_info / element NAME COUNT /
//   property TYPE NAME / property list COUNT_TYPE INDEX_TYPE NAME / end_header
// then the elements in header order. The surface is element "vertex" with
// numeric properties x, y, z and element "face" with a list property
// "vertex_indices" (or "vertex_index"); every other property and element
// (colours, normals, edges, materials) is read past by its declared type.
//
// Strict (issue 23): every element count is checked against the bytes after
// the header before anything is allocated (binary: its fixed bytes per element;
// ascii: two characters per number at least); errors name the byte offset
// (binary) or the line (ascii, and the header). Faces go through
// triangulate_polygon in file order, like OBJ and OFF.
#include "stripweave/io/mesh_readers.h"

#include "stripweave/io/mesh_text.h"
#include "stripweave/io/polygon_triangulation.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>

namespace stripweave {

namespace {

enum class Scalar : std::uint8_t { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64, kNone };

Scalar scalar_of(std::string_view t) {
  if (t == "char" || t == "int8") return Scalar::kI8;
  if (t == "uchar" || t == "uint8") return Scalar::kU8;
  if (t == "short" || t == "int16") return Scalar::kI16;
  if (t == "ushort" || t == "uint16") return Scalar::kU16;
  if (t == "int" || t == "int32") return Scalar::kI32;
  if (t == "uint" || t == "uint32") return Scalar::kU32;
  if (t == "float" || t == "float32") return Scalar::kF32;
  if (t == "double" || t == "float64") return Scalar::kF64;
  return Scalar::kNone;
}

std::size_t size_of(Scalar s) {
  switch (s) {
    case Scalar::kI8: case Scalar::kU8: return 1;
    case Scalar::kI16: case Scalar::kU16: return 2;
    case Scalar::kI32: case Scalar::kU32: case Scalar::kF32: return 4;
    case Scalar::kF64: return 8;
    default: return 0;
  }
}

std::string number_text(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

bool is_integer(Scalar s) { return s != Scalar::kF32 && s != Scalar::kF64; }

struct Property {
  std::string name;
  Scalar type = Scalar::kNone;        // the value's (a list's items')
  Scalar count_type = Scalar::kNone;  // kNone: a scalar property
  bool is_list() const { return count_type != Scalar::kNone; }
};

struct Element {
  std::string name;
  long long count = 0;
  long long header_line = 0;
  std::vector<Property> properties;
  // Least bytes one element takes after the header: binary, its scalars and
  // list counts; ascii, one digit and a separator per number.
  std::size_t min_bytes(bool binary) const {
    std::size_t n = 0;
    for (const Property& p : properties) n += binary ? size_of(p.is_list() ? p.count_type : p.type) : 2;
    return n;
  }
};

enum class Encoding { kAscii, kLittle, kBig };

struct Header {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
  std::size_t data_begin = 0;  // byte offset of the first element
  long long data_line = 0;     // lines of the header (ascii errors count on from here)
};

Header read_header(const std::string& path, std::string_view bytes) {
  Header h;
  std::size_t pos = 0;
  long long line = 0;
  auto fail = [&](const std::string& what) { throw_mesh_read(path, "line " + std::to_string(line) + ": " + what); };
  bool ended = false, has_format = false;
  while (!ended) {
    if (pos >= bytes.size()) fail("the header ends without 'end_header'");
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view text = bytes.substr(pos, end - pos);
    pos = std::min(end + 1, bytes.size() + 1);
    ++line;
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    std::vector<std::string_view> tokens;
    for (std::size_t i = 0; i < text.size();) {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
      if (i > start) tokens.push_back(text.substr(start, i - start));
    }
    if (line == 1) {
      if (tokens.size() != 1 || tokens[0] != "ply") fail("a PLY file starts with the line 'ply'");
      continue;
    }
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "format") {
      if (tokens.size() != 3) fail("'format ascii|binary_little_endian|binary_big_endian 1.0' expected");
      if (tokens[1] == "ascii") h.encoding = Encoding::kAscii;
      else if (tokens[1] == "binary_little_endian") h.encoding = Encoding::kLittle;
      else if (tokens[1] == "binary_big_endian") h.encoding = Encoding::kBig;
      else fail("unknown PLY format '" + std::string(tokens[1]) + "'");
      if (tokens[2] != "1.0") fail("PLY version '" + std::string(tokens[2]) + "' (only 1.0 is defined)");
      has_format = true;
    } else if (tokens[0] == "element") {
      if (tokens.size() != 3) fail("'element NAME COUNT' expected");
      Element e;
      e.name = std::string(tokens[1]);
      e.header_line = line;
      const auto [p, ec] = std::from_chars(tokens[2].data(), tokens[2].data() + tokens[2].size(), e.count);
      if (ec != std::errc() || p != tokens[2].data() + tokens[2].size() || e.count < 0)
        fail("the element count '" + std::string(tokens[2]) + "' is not a whole number");
      h.elements.push_back(std::move(e));
    } else if (tokens[0] == "property") {
      if (h.elements.empty()) fail("a property before any element");
      Property p;
      if (tokens.size() == 5 && tokens[1] == "list") {
        p.count_type = scalar_of(tokens[2]);
        p.type = scalar_of(tokens[3]);
        p.name = std::string(tokens[4]);
        if (p.count_type == Scalar::kNone || !is_integer(p.count_type))
          fail("a list's count type must be an integer type, got '" + std::string(tokens[2]) + "'");
        if (p.type == Scalar::kNone) fail("unknown property type '" + std::string(tokens[3]) + "'");
      } else if (tokens.size() == 3) {
        p.type = scalar_of(tokens[1]);
        p.name = std::string(tokens[2]);
        if (p.type == Scalar::kNone) fail("unknown property type '" + std::string(tokens[1]) + "'");
      } else {
        fail("'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME' expected");
      }
      h.elements.back().properties.push_back(std::move(p));
    } else if (tokens[0] == "end_header") {
      ended = true;
    } else {
      fail("unknown header keyword '" + std::string(tokens[0]) + "'");
    }
  }
  if (!has_format) fail("the header has no 'format' line");
  h.data_begin = std::min(pos, bytes.size());
  h.data_line = line;
  // Every count against what the rest of the file can hold, before allocating.
  const bool binary = h.encoding != Encoding::kAscii;
  const std::size_t data = bytes.size() - h.data_begin;
  long double needed = 0;
  for (const Element& e : h.elements) {
    const std::size_t each = std::max<std::size_t>(1, e.min_bytes(binary));
    needed += static_cast<long double>(e.count) * each;
    if (static_cast<unsigned long long>(e.count) > data || needed > data) {
      line = e.header_line;
      fail("the header announces " + std::to_string(e.count) + " " + e.name + " elements, more than a file of " +
           std::to_string(bytes.size()) + " bytes can hold");
    }
  }
  return h;
}

// The roles of an element's properties for the surface.
struct Roles {
  int x = -1, y = -1, z = -1, corners = -1;
};

Roles roles_of(const Element& e) {
  Roles r;
  for (int i = 0; i < static_cast<int>(e.properties.size()); ++i) {
    const Property& p = e.properties[i];
    if (e.name == "vertex" && !p.is_list()) {
      if (p.name == "x") r.x = i;
      if (p.name == "y") r.y = i;
      if (p.name == "z") r.z = i;
    }
    if (e.name == "face" && p.is_list() && (p.name == "vertex_indices" || p.name == "vertex_index")) r.corners = i;
  }
  return r;
}

// Values one at a time from the data: binary at a byte offset, ascii as
// tokens with their line. `at()` names where the last value began.
class Values {
 public:
  Values(const std::string& path, std::string_view bytes, const Header& h)
      : path_(path), bytes_(bytes), pos_(h.data_begin), line_(h.data_line + 1), encoding_(h.encoding) {}

  double next(Scalar type, const char* what) {
    return encoding_ == Encoding::kAscii ? next_text(type, what) : next_binary(type, what);
  }
  // Ascii: every element stands on its own line; called after each one.
  void end_element() {
    if (encoding_ != Encoding::kAscii) return;
    skip_blanks();
    if (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r')
      fail("more numbers on the line than its element's properties");
    line_start_ = true;
  }
  // After the last element: nothing but blanks may follow.
  void finish() {
    if (encoding_ == Encoding::kAscii) {
      while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) advance_char();
    }
    if (pos_ < bytes_.size())
      fail(std::to_string(bytes_.size() - pos_) + " bytes after the last element the header announces");
  }
  [[noreturn]] void fail(const std::string& what) const {
    if (encoding_ == Encoding::kAscii) throw_mesh_read(path_, "line " + std::to_string(line_) + ": " + what);
    throw_mesh_read(path_, "byte " + std::to_string(value_begin_) + ": " + what);
  }

 private:
  void advance_char() {
    if (bytes_[pos_] == '\n') ++line_;
    ++pos_;
  }
  void skip_blanks() {
    while (pos_ < bytes_.size() && (bytes_[pos_] == ' ' || bytes_[pos_] == '\t')) ++pos_;
  }

  double next_binary(Scalar type, const char* what) {
    value_begin_ = pos_;
    const std::size_t n = size_of(type);
    if (bytes_.size() - pos_ < n) fail(std::string("the file ends where ") + what + " is due");
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    if (encoding_ == Encoding::kBig) std::reverse(b, b + n);
    switch (type) {
      case Scalar::kI8: return static_cast<std::int8_t>(b[0]);
      case Scalar::kU8: return b[0];
      case Scalar::kI16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case Scalar::kU16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Scalar::kI32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case Scalar::kU32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Scalar::kF32: { float v; std::memcpy(&v, b, 4); return v; }
      default: { double v; std::memcpy(&v, b, 8); return v; }
    }
  }

  double next_text(Scalar type, const char* what) {
    if (line_start_) {
      // An element's first value: its line may follow blank lines.
      while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) advance_char();
      line_start_ = false;
    } else {
      skip_blanks();
    }
    if (pos_ >= bytes_.size() || bytes_[pos_] == '\n' || bytes_[pos_] == '\r')
      fail(std::string("the line ends where ") + what + " is due");
    const std::size_t start = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    const std::string_view t = bytes_.substr(start, pos_ - start);
    if (is_integer(type)) {
      long long v = 0;
      const char* begin = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
      const auto [end, ec] = std::from_chars(begin, t.data() + t.size(), v);
      if (ec != std::errc() || end != t.data() + t.size())
        fail(std::string(what) + " '" + std::string(t) + "' is not a whole number");
      return static_cast<double>(v);
    }
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
      fail(std::string(what) + " '" + std::string(t) + "' is not a finite number");
    return v;
  }

  const std::string& path_;
  std::string_view bytes_;
  std::size_t pos_;
  std::size_t value_begin_ = 0;
  long long line_;
  bool line_start_ = true;
  Encoding encoding_;
};

}  // namespace

TriangleMesh read_ply(const std::string& path, const std::string& bytes) {
  const Header h = read_header(path, bytes);
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  for (const Element& e : h.elements) {
    if (e.name == "vertex" && !vertex) vertex = &e;
    if (e.name == "face" && !face) face = &e;
  }
  if (!vertex) throw_mesh_read(path, "the header declares no 'vertex' element");
  if (!face) throw_mesh_read(path, "the header declares no 'face' element");
  const Roles vr = roles_of(*vertex), fr = roles_of(*face);
  if (vr.x < 0 || vr.y < 0 || vr.z < 0)
    throw_mesh_read(path, "line " + std::to_string(vertex->header_line) +
                              ": the vertex element has no scalar properties x, y and z");
  if (fr.corners < 0)
    throw_mesh_read(path, "line " + std::to_string(face->header_line) +
                              ": the face element has no list property 'vertex_indices' (or 'vertex_index')");
  if (vertex->count > std::numeric_limits<Index>::max())
    throw_mesh_read(path, "line " + std::to_string(vertex->header_line) + ": more vertices than a mesh can index");

  TriangleMesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(vertex->count));
  mesh.triangles.reserve(static_cast<std::size_t>(face->count));
  // Faces met before the vertices (legal, rare) wait for them: corners are
  // checked at once, triangulated once the positions are known.
  std::vector<Index> waiting_corners;
  std::vector<std::pair<std::size_t, std::size_t>> waiting;  // (first corner, count)
  bool vertices_read = false;
  std::vector<Index> corners;
  Values values(path, bytes, h);
  for (const Element& e : h.elements) {
    const bool is_vertex = &e == vertex, is_face = &e == face;
    const Roles r = is_vertex ? vr : is_face ? fr : Roles{};
    for (long long i = 0; i < e.count; ++i) {
      double xyz[3] = {0, 0, 0};
      for (int k = 0; k < static_cast<int>(e.properties.size()); ++k) {
        const Property& p = e.properties[k];
        if (!p.is_list()) {
          const double v = values.next(p.type, p.name.c_str());
          if (is_vertex && (k == r.x || k == r.y || k == r.z)) {
            if (!std::isfinite(v)) values.fail("vertex " + std::to_string(i) + " has a non-finite " + p.name);
            xyz[k == r.x ? 0 : k == r.y ? 1 : 2] = v;
          }
          continue;
        }
        const double n = values.next(p.count_type, "a list's length");
        if (n < 0) values.fail("a list of " + std::to_string(static_cast<long long>(n)) + " items");
        if (is_face && k == r.corners && n > static_cast<double>(kMaxPolygonCorners))
          values.fail("a face of " + std::to_string(static_cast<long long>(n)) + " corners (at most " +
                      std::to_string(kMaxPolygonCorners) + ")");
        if (is_face && k == r.corners) corners.clear();
        for (long long j = 0; j < static_cast<long long>(n); ++j) {
          const double v = values.next(p.type, "a list item");
          if (!(is_face && k == r.corners)) continue;
          if (!(v >= 0 && v < static_cast<double>(vertex->count)) || v != std::floor(v))
            values.fail("face " + std::to_string(i) + " refers to vertex " + number_text(v) +
                        ", the file holds " + std::to_string(vertex->count) + " (0-based)");
          corners.push_back(static_cast<Index>(v));
        }
      }
      if (is_vertex) mesh.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
      if (is_face && vertices_read) {
        if (!triangulate_polygon(mesh.positions, corners, mesh.triangles))
          values.fail("face " + std::to_string(i) + " of " + std::to_string(corners.size()) +
                      " corners crosses itself");
      } else if (is_face) {
        waiting.emplace_back(waiting_corners.size(), corners.size());
        waiting_corners.insert(waiting_corners.end(), corners.begin(), corners.end());
      }
      values.end_element();
    }
    if (is_vertex) vertices_read = true;
  }
  values.finish();
  for (std::size_t f = 0; f < waiting.size(); ++f) {
    corners.assign(waiting_corners.begin() + waiting[f].first,
                   waiting_corners.begin() + waiting[f].first + waiting[f].second);
    if (!triangulate_polygon(mesh.positions, corners, mesh.triangles))
      throw_mesh_read(path, "face " + std::to_string(f) + " of " + std::to_string(corners.size()) +
                                " corners crosses itself");
  }
  return mesh;
}

}  // namespace stripweave
