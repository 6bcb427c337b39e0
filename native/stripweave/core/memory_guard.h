// Refusing work that would exceed the machine (issue 23), before allocating:
// a clear one-line InputError rather than the kernel's OOM killer taking the
// process (and FreeCAD, with the user's unsaved work) down.
//
// memory_limit_mb()
//   The memory this process may use, in MB: STRIPWEAVE_MEMORY_LIMIT_MB when
//   set to a positive number (the CLI's --memory-limit sets it; tests use it
//   with a small value), else MemAvailable of /proc/meminfo (what the kernel
//   can give without swapping), else 0 (unknown: nothing is refused).
// surface_memory_mb(input_triangles, solver_triangles)
//   Estimated peak of building the surface (sanitizing or welding the input,
//   remeshing, curvature), from the per-triangle costs measured with
//   `stripweave bench` (see the constants in memory_guard.cpp).
// graph_memory_mb(solver_triangles, k, max_turn_deg)
//   Estimated peak of the elastica graph and the loop engine (and what the
//   strips and layout add), scaled from the measured cost at the defaults
//   (k = 4, 30 degrees) by the g' arc count: vertices within graph distance
//   k grow as 1 + 3k(k+1), arcs per g' node as that times the turn's share.
// check_memory(work, needed_mb)
//   Throws InputError "<work> needs about X MB, more than the Y MB available
//   (<where Y comes from>)" when needed_mb exceeds memory_limit_mb().
#pragma once

#include <string>

namespace stripweave {

double memory_limit_mb();
double surface_memory_mb(double input_triangles, double solver_triangles);
double graph_memory_mb(double solver_triangles, int k, double max_turn_deg);
void check_memory(const std::string& work, double needed_mb);

}  // namespace stripweave
