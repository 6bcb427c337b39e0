// Strict readers of the mesh formats: OFF, OBJ, STL and PLY.
//
// read_off(path, bytes), read_obj(path, bytes), read_stl(path, bytes) ->
//   TriangleMesh as stored (STL: three unwelded corners per triangle; OFF and
//   OBJ: their vertices, polygons ear-clipped, faces under three corners
//   skipped). `bytes` is the whole file (read_regular_file).
// Each refuses what it cannot read exactly with an InputError naming the
// file, the line (text) or byte offset (binary) and what was wrong:
//   OFF  a count larger than the file can hold (checked before allocating:
//        a face line claiming 999,999,999 corners), a corrupt number, a face
//        with more corners than its line, an index out of range, missing lines;
//   OBJ  an index that is not a whole number ("f 1.5 2 3"), zero or out of
//        range, a vertex with fewer than three finite coordinates;
//   both a polygon over kMaxPolygonCorners corners or one that crosses itself;
//   STL  binary: a header count that disagrees with the file size (84 + 50
//        bytes per triangle), either way; ASCII: a facet without exactly three
//        vertices, a corrupt number, a missing "endsolid";
//   PLY  (ascii, binary little and big endian) an element count larger than
//        the bytes after the header can hold (checked before allocating), a
//        header line it does not know, no vertex x y z or face vertex_indices,
//        a corrupt number, an index out of range, a line with more numbers
//        than its element, bytes after the last element. Other elements and
//        properties are read past by their declared types; polygons are
//        ear-clipped.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <string>

namespace stripweave {

TriangleMesh read_off(const std::string& path, const std::string& bytes);
TriangleMesh read_obj(const std::string& path, const std::string& bytes);
TriangleMesh read_stl(const std::string& path, const std::string& bytes);
TriangleMesh read_ply(const std::string& path, const std::string& bytes);

}  // namespace stripweave
