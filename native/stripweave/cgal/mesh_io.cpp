// Reading and writing triangle meshes: dispatch by extension.
//
// All four formats are read by our strict readers (io/mesh_readers.h: CGAL's
// read "f 1.5 2 3" as "f 1 2 3", allocated what a lying count announced, read
// a FIFO forever and said only "false" for a bad PLY; its PLY parser was also
// the slowest part of loading a scan). Writing is CGAL's for all four.
#include "stripweave/cgal/mesh_io.h"

#include "stripweave/core/error.h"
#include "stripweave/io/mesh_readers.h"
#include "stripweave/io/mesh_text.h"

// Same as every CGAL translation unit of the library: class templates such as
// Default_diagonalize_traits change with this flag, so it must not differ
// between them (one definition rule).
// The per-format headers, not CGAL/IO/polygon_soup_io.h: we dispatch on the
// extension ourselves, and that header also pulls in the GOCAD and VTK readers.
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
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

}  // namespace

bool is_mesh_file(const std::string& path) { return format_of(path) != Format::kUnknown; }

TriangleMesh read_mesh_file(const std::string& path) {
  const Format format = format_of(path);
  if (format == Format::kUnknown) throw_unknown_format(path, "read");
  // Our strict readers (io/mesh_readers.h) of the whole file, which is never
  // a device or a pipe.
  const std::string bytes = read_regular_file(path);
  TriangleMesh mesh = format == Format::kStl   ? read_stl(path, bytes)
                      : format == Format::kObj ? read_obj(path, bytes)
                      : format == Format::kOff ? read_off(path, bytes)
                                               : read_ply(path, bytes);
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
