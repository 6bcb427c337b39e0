// See memory_guard.h.
#include "stripweave/core/memory_guard.h"

#include "stripweave/core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace stripweave {

namespace {

// Peak resident memory (/usr/bin/time) of `stripweave info` and `stripweave
// bench --repeat 1 --no-refit` (loops and strips) on generated models, Release
// build, December 2026:
//   the process with its libraries (info, 100 triangles)            66 MB
//   surface of a box STEP, 30k / 100k solver triangles               74 / 84 MB
//   surface of a UV-sphere STL, 159k / 808k input, 30k solver       184 / 682 MB
//     (0.77 kB per input triangle); 808k kept as they are (target 0) 470 MB
//   bench of the box, 9.9k / 30.9k / 79.1k solver triangles    159 / 392 / 882 MB
//     (11.1 then 10.2 kB per solver triangle; graph_mb 28.5 / 98.6 / 253.6)
//   bench of the 159k-triangle sphere at 30.2k solver triangles      424 MB
// Each constant is the measurement rounded up by a third or more: the guard
// must not pass work that then fails, and other stages (the layout, the
// preview) add a little to what bench measures.
constexpr double kBaseMb = 100;
constexpr double kSurfaceMbPerInputTriangle = 0.001;
constexpr double kSurfaceMbPerSolverTriangle = 0.0005;
constexpr double kGraphMbPerSolverTriangle = 0.015;  // graph, loop engine, strips at k = 4, 30 degrees

double limit_from_environment() {
  const char* text = std::getenv("STRIPWEAVE_MEMORY_LIMIT_MB");
  if (!text || !*text) return 0;
  char* end = nullptr;
  const double mb = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(mb > 0) || !std::isfinite(mb))
    throw InputError(std::string("STRIPWEAVE_MEMORY_LIMIT_MB must be a positive number of MB, got '") + text + "'");
  return mb;
}

double mem_available_mb() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb;
  std::string unit;
  while (in >> key >> kb) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return kb / 1024.0;
  }
  return 0;
}

// How many vertices lie within graph distance k on a regular triangle mesh.
double ring_vertices(int k) { return 1.0 + 3.0 * k * (k + 1); }

}  // namespace

double memory_limit_mb() {
  const double given = limit_from_environment();
  return given > 0 ? given : mem_available_mb();
}

double surface_memory_mb(double input_triangles, double solver_triangles) {
  return kBaseMb + kSurfaceMbPerInputTriangle * input_triangles + kSurfaceMbPerSolverTriangle * solver_triangles;
}

double graph_memory_mb(double solver_triangles, int k, double max_turn_deg) {
  const double arcs = ring_vertices(k) * ring_vertices(k) * std::clamp(max_turn_deg, 1.0, 180.0);
  const double arcs_at_defaults = ring_vertices(4) * ring_vertices(4) * 30.0;
  // The scaling by k and the turn is the arc count's, not measured at other values.
  return kBaseMb + kSurfaceMbPerSolverTriangle * solver_triangles +
         kGraphMbPerSolverTriangle * solver_triangles * (arcs / arcs_at_defaults);
}

void check_memory(const std::string& work, double needed_mb) {
  const bool given = limit_from_environment() > 0;
  const double limit = memory_limit_mb();
  if (!(limit > 0) || needed_mb <= limit) return;
  std::ostringstream msg;
  msg.precision(0);
  msg << std::fixed << work << " needs about " << needed_mb << " MB, more than the " << limit << " MB "
      << (given ? "allowed (STRIPWEAVE_MEMORY_LIMIT_MB or --memory-limit)" : "available (MemAvailable in /proc/meminfo)")
      << ": give a smaller target triangle count";
  throw InputError(msg.str());
}

}  // namespace stripweave
