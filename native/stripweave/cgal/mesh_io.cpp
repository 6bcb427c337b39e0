// Reading and writing triangle meshes: dispatch by extension.
//
// STL, OBJ and OFF are read by our strict readers (io/mesh_readers.h: CGAL's
// read "f 1.5 2 3" as "f 1 2 3", allocated what a lying count announced and
// read a FIFO forever); PLY by CGAL, with a precise message for every way a
// file can be unusable (CGAL only says "false"), index validation and ear
// clipping of polygons added here. Writing is CGAL's for all four.
#include "stripweave/cgal/mesh_io.h"

#include "stripweave/core/error.h"
#include "stripweave/io/mesh_readers.h"
#include "stripweave/io/mesh_text.h"
#include "stripweave/io/polygon_triangulation.h"

// Same as every CGAL translation unit of the library: class templates such as
// Default_diagonalize_traits change with this flag, so it must not differ
// between them (one definition rule).
// The per-format headers, not CGAL/IO/polygon_soup_io.h: we dispatch on the
// extension ourselves, and that header also pulls in the GOCAD and VTK readers.
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>  // reading: PLY only; writing: all four
#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace stripweave {
namespace {

// Plain doubles are all the readers need; a filtered kernel buys nothing here.
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Polygon = std::vector<std::size_t>;

enum class Format { kStl, kObj, kOff, kPly, kUnknown };

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

Format format_of(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".stl") return Format::kStl;
  if (ext == ".obj") return Format::kObj;
  if (ext == ".off") return Format::kOff;
  if (ext == ".ply") return Format::kPly;
  return Format::kUnknown;
}

const char* format_name(Format f) {
  switch (f) {
    case Format::kStl: return "STL";
    case Format::kObj: return "OBJ";
    case Format::kOff: return "OFF";
    case Format::kPly: return "PLY";
    default: return "mesh";
  }
}

[[noreturn]] void throw_unknown_format(const std::string& path, const char* verb) {
  std::string ext = lowercase_extension(path);
  if (ext.empty()) ext = "(none)";
  throw InputError(std::string("cannot ") + verb + " mesh file '" + path + "': unknown mesh format '" + ext +
                   "' (expected .stl, .obj, .off or .ply)");
}

[[noreturn]] void throw_read(const std::string& path, const std::string& problem) {
  throw InputError("cannot read mesh file '" + path + "': " + problem);
}

// CGAL reports failure as a bare `false`; find out first whether the file is
// there at all, so that the user is told the real reason.
void check_readable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw_read(path, "file does not exist");
  if (fs::is_directory(st)) throw_read(path, "it is a directory");
  if (!fs::is_regular_file(st)) throw_read(path, "it is not a regular file (a device, pipe or socket)");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw_read(path, std::string("cannot open it (") + std::strerror(errno) + ")");
  const auto size = fs::file_size(path, ec);
  if (!ec && size == 0) throw_read(path, "file is empty");
}

bool read_ply_soup(const std::string& path, std::vector<Point>& points, std::vector<Polygon>& polygons) {
  std::ifstream in(path, std::ios::binary);
  CGAL::IO::set_mode(in, CGAL::IO::BINARY);
  // The stream overload of read_PLY defaults to verbose = true.
  return CGAL::IO::read_PLY(in, points, polygons, CGAL::parameters::verbose(false));
}

}  // namespace

bool is_mesh_file(const std::string& path) { return format_of(path) != Format::kUnknown; }

namespace {

// A PLY header's element counts against the file's size (every element takes
// at least a byte): CGAL would otherwise try to read what a lying count
// announces, and says only "not a valid PLY file".
void check_ply_header(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  std::string head(std::min<std::uintmax_t>(size, 1 << 16), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::size_t end = head.find("end_header");
  if (head.compare(0, 3, "ply") != 0 || end == std::string::npos)
    throw_read(path, "not a valid PLY file (no 'ply' ... 'end_header' header in its first 64 KB)");
  head.resize(end);  // MeshText views the string: it must outlive the text
  MeshText text(path, head);
  while (text.next_line()) {
    if (text.tokens()[0] != "element") continue;
    const long long count = text.integer(2, "the element count");
    if (count < 0 || static_cast<std::uintmax_t>(count) > size)
      text.fail("the header announces " + std::to_string(count) + " " + std::string(text.tokens()[1]) +
                " elements, more than a file of " + std::to_string(size) + " bytes can hold");
  }
}

// PLY through CGAL (binary and ASCII, many property layouts), checked here.
TriangleMesh read_ply(const std::string& path) {
  check_readable(path);
  check_ply_header(path);
  const std::string invalid = "not a valid PLY file";
  std::vector<Point> points;
  std::vector<Polygon> polygons;
  bool ok = false;
  try {
    ok = read_ply_soup(path, points, polygons);
  } catch (const std::bad_alloc&) {
    // A corrupt header can announce billions of elements.
    throw_read(path, invalid + " (its element counts are impossibly large)");
  } catch (const std::exception& e) {
    // CGAL assertions and PLY property errors arrive as exceptions.
    throw_read(path, invalid + " (" + e.what() + ")");
  }
  if (!ok) throw_read(path, invalid);
  // Nothing in CGAL checks PLY indices.
  const std::size_t n = points.size();
  for (std::size_t f = 0; f < polygons.size(); ++f)
    for (std::size_t v : polygons[f])
      if (v >= n)
        throw_read(path, invalid + ": face " + std::to_string(f + 1) + " refers to vertex " +
                             std::to_string(static_cast<long long>(v) + 1) + " but the file holds " +
                             std::to_string(n) + " vertices");
  TriangleMesh mesh;
  mesh.positions.reserve(n);
  for (const Point& p : points) mesh.positions.emplace_back(p.x(), p.y(), p.z());
  for (const Polygon& f : polygons) {
    std::vector<Index> corners(f.begin(), f.end());
    if (corners.size() > kMaxPolygonCorners || !triangulate_polygon(mesh.positions, corners, mesh.triangles))
      throw_read(path, invalid + ": a face of " + std::to_string(f.size()) + " corners is too large or crosses itself");
  }
  return mesh;
}

}  // namespace

TriangleMesh read_mesh_file(const std::string& path) {
  const Format format = format_of(path);
  if (format == Format::kUnknown) throw_unknown_format(path, "read");
  TriangleMesh mesh;
  if (format == Format::kPly) {
    mesh = read_ply(path);
  } else {
    // STL, OBJ and OFF: our strict readers (io/mesh_readers.h) of the whole
    // file, which is never a device or a pipe.
    const std::string bytes = read_regular_file(path);
    mesh = format == Format::kStl ? read_stl(path, bytes) : format == Format::kObj ? read_obj(path, bytes)
                                                                                    : read_off(path, bytes);
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    if (!mesh.positions[i].allFinite())
      throw_read(path, std::string("not a valid ") + format_name(format) + " file: vertex " + std::to_string(i + 1) +
                           " has a non-finite coordinate");
  if (mesh.triangles.empty()) throw_read(path, "file holds no triangles");
  return mesh;
}

void write_mesh_file(const std::string& path, const TriangleMesh& mesh) {
  const Format format = format_of(path);
  if (format == Format::kUnknown) throw_unknown_format(path, "write");

  std::vector<Point> points;
  points.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<Polygon> polygons;
  polygons.reserve(mesh.triangles.size());
  for (const Tri& t : mesh.triangles) {
    polygons.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2])});
  }

  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) {
    throw InputError("cannot write mesh file '" + path + "': " + std::strerror(errno));
  }
  // ASCII formats get 17 significant digits: a double survives the round trip.
  const auto exact = CGAL::parameters::stream_precision(17);
  bool ok = false;
  switch (format) {
    case Format::kStl:
      CGAL::IO::set_mode(out, CGAL::IO::BINARY);
      ok = CGAL::IO::write_STL(out, points, polygons);
      break;
    case Format::kPly:
      CGAL::IO::set_mode(out, CGAL::IO::BINARY);
      ok = CGAL::IO::write_PLY(out, points, polygons);
      break;
    case Format::kObj:
      CGAL::IO::set_mode(out, CGAL::IO::ASCII);
      ok = CGAL::IO::write_OBJ(out, points, polygons, exact);
      break;
    case Format::kOff:
      CGAL::IO::set_mode(out, CGAL::IO::ASCII);
      ok = CGAL::IO::write_OFF(out, points, polygons, exact);
      break;
    default:
      break;
  }
  out.close();
  if (!ok || out.fail()) {
    throw InputError("cannot write mesh file '" + path + "': " +
                     (errno != 0 ? std::strerror(errno) : "write failed"));
  }
}

}  // namespace stripweave
