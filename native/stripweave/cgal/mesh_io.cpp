// Reading and writing triangle meshes through CGAL's stream I/O.
//
// CGAL parses the four formats; this file adds what a CAD user needs around
// it: a precise message for every way a file can be unusable (CGAL only says
// "false"), index validation (CGAL's OBJ and PLY readers let out-of-range
// corners through), fan triangulation of polygons, and STL kept as the
// unwelded soup stored in the file.
#include "stripweave/cgal/mesh_io.h"

#include "stripweave/core/error.h"

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

// CGAL reports failure as a bare `false`; find out first whether the file is
// there at all, so that the user is told the real reason.
void check_readable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw_read(path, "file does not exist");
  if (fs::is_directory(st)) throw_read(path, "it is a directory");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw_read(path, std::string("cannot open it (") + std::strerror(errno) + ")");
  const auto size = fs::file_size(path, ec);
  if (!ec && size == 0) throw_read(path, "file is empty");
}

// A soup with no triangle is not always a broken file (an ASCII STL may
// hold an empty solid, a binary one may state zero facets). Tell the two apart
// so the message does not call a well-formed empty file invalid.
bool stl_header_is_well_formed(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string word;
  if (in >> word && word == "solid") return true;
  in.clear();
  in.seekg(0, std::ios::end);
  return static_cast<long long>(in.tellg()) >= 84;  // 80-byte header + facet count
}

bool read_soup(const std::string& path, Format format, std::vector<Point>& points,
               std::vector<Polygon>& polygons) {
  const auto quiet = CGAL::parameters::verbose(false);
  // Binary open mode for every format: STL and PLY may be binary, and on
  // POSIX the text mode makes no difference for the others.
  std::ifstream in(path, std::ios::binary);
  switch (format) {
    case Format::kStl:
      CGAL::IO::set_mode(in, CGAL::IO::BINARY);
      return CGAL::IO::read_STL(in, points, polygons, quiet);
    case Format::kObj:
      return CGAL::IO::read_OBJ(in, points, polygons, quiet);
    case Format::kOff:
      return CGAL::IO::read_OFF(in, points, polygons, quiet);
    case Format::kPly:
      // The stream overload of read_PLY defaults to verbose = true.
      CGAL::IO::set_mode(in, CGAL::IO::BINARY);
      return CGAL::IO::read_PLY(in, points, polygons, quiet);
    default:
      return false;
  }
}

}  // namespace

bool is_mesh_file(const std::string& path) { return format_of(path) != Format::kUnknown; }

TriangleMesh read_mesh_file(const std::string& path) {
  const Format format = format_of(path);
  if (format == Format::kUnknown) throw_unknown_format(path, "read");
  check_readable(path);

  const std::string invalid = std::string("not a valid ") + format_name(format) + " file";
  std::vector<Point> points;
  std::vector<Polygon> polygons;
  bool ok = false;
  try {
    ok = read_soup(path, format, points, polygons);
  } catch (const std::bad_alloc&) {
    // A corrupt header can announce billions of elements.
    throw_read(path, invalid + " (its element counts are impossibly large)");
  } catch (const std::exception& e) {
    // CGAL assertions and PLY property errors arrive as exceptions.
    throw_read(path, invalid + " (" + e.what() + ")");
  }
  if (!ok) throw_read(path, invalid);

  // CGAL's readers check indices loosely or not at all: a corner one past the
  // last vertex passes the OBJ reader and nothing checks PLY indices.
  const std::size_t n = points.size();
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    for (std::size_t v : polygons[f]) {
      if (v >= n) {
        throw_read(path, invalid + ": face " + std::to_string(f + 1) + " refers to vertex " +
                             std::to_string(static_cast<long long>(v) + 1) + " but the file holds " +
                             std::to_string(n) + " vertices");
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = points[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      throw_read(path, invalid + ": vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
    }
  }

  TriangleMesh mesh;
  if (format == Format::kStl) {
    // CGAL's STL reader merges bit-identical corners. Undo it: the contract is
    // the soup as stored, and welding (with its tolerance and its report) is
    // sanitize_mesh's job, not the reader's.
    mesh.positions.reserve(3 * polygons.size());
    mesh.triangles.reserve(polygons.size());
    for (const Polygon& f : polygons) {
      if (f.size() != 3) continue;  // the STL reader yields triangles only
      const Index base = static_cast<Index>(mesh.positions.size());
      for (std::size_t v : f) mesh.positions.emplace_back(points[v].x(), points[v].y(), points[v].z());
      mesh.triangles.push_back({base, base + 1, base + 2});
    }
  } else {
    mesh.positions.reserve(n);
    for (const Point& p : points) mesh.positions.emplace_back(p.x(), p.y(), p.z());
    mesh.triangles.reserve(polygons.size());
    for (const Polygon& f : polygons) {
      // Fan from the first corner: exact for the convex quads and n-gons CAD
      // exporters write; faces with fewer than three corners carry no area.
      for (std::size_t k = 1; k + 1 < f.size(); ++k) {
        mesh.triangles.push_back({static_cast<Index>(f[0]), static_cast<Index>(f[k]), static_cast<Index>(f[k + 1])});
      }
    }
  }

  if (mesh.triangles.empty()) {
    if (format == Format::kStl && !stl_header_is_well_formed(path)) throw_read(path, invalid);
    throw_read(path, "file holds no triangles");
  }
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
