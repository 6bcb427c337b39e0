// libFuzzer target: the native mesh readers (OFF, OBJ, STL, PLY) and sanitize_mesh
// on whatever they accept.
//
// Input: one byte choosing the format (0 OFF, 1 OBJ, 2 STL, 3 PLY; modulo 4), then
// the file's bytes. Every input must end in a TriangleMesh or an InputError:
// a crash, a sanitizer report, another exception or a hang is a finding.
// Build and run: tests/fuzz/run.sh (see tests/fuzz/README.md).
#include "stripweave/core/error.h"
#include "stripweave/io/mesh_readers.h"
#include "stripweave/surface/sanitize_mesh.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace stripweave;
  if (size == 0) return 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    TriangleMesh mesh;
    switch (data[0] % 4) {
      case 0: mesh = read_off("fuzz.off", bytes); break;
      case 1: mesh = read_obj("fuzz.obj", bytes); break;
      case 2: mesh = read_stl("fuzz.stl", bytes); break;
      default: mesh = read_ply("fuzz.ply", bytes); break;
    }
    if (mesh.triangles.size() <= 20000) sanitize_mesh(mesh);  // bounded: one input, one second at most
  } catch (const InputError&) {
    // the expected refusal
  }
  return 0;
}
