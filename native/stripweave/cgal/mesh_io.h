// Reading and writing triangle meshes (CGAL stream I/O adapter).
//
// read_mesh_file(path) -> TriangleMesh
//   Formats by extension (case-insensitive): .stl (ASCII and binary), .obj,
//   .off, .ply (ASCII and binary, either byte order), by the strict readers of
//   io/mesh_readers.h. Polygons with more than three corners are
//   ear-clipped; faces with fewer than three are skipped. The result is
//   the raw soup as stored in the file: STL vertices are not welded (three per
//   triangle), nothing is repaired (see sanitize_mesh).
//   Throws InputError naming the file and the problem for a missing,
//   unreadable or empty file, or an unknown extension.
//
// write_mesh_file(path, mesh)
//   Writes the same formats (STL as binary, PLY as binary with double
//   coordinates, OBJ and OFF as ASCII with 17 digits; only binary STL rounds
//   coordinates, to float). Throws InputError if the file cannot be written.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <string>

namespace stripweave {

TriangleMesh read_mesh_file(const std::string& path);
void write_mesh_file(const std::string& path, const TriangleMesh& mesh);

// True if the extension names a mesh format read_mesh_file understands.
bool is_mesh_file(const std::string& path);

}  // namespace stripweave
