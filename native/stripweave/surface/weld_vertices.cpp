#include "stripweave/surface/weld_vertices.h"

#include <cstdint>
#include <cstring>

namespace stripweave {

namespace {

std::uint64_t bits(double x) {
  x += 0.0;  // -0.0 becomes 0.0: equal coordinates must hash alike
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// A 64-bit finalizer (splitmix64's): coordinates of a grid differ in few bits.
std::uint64_t mix(std::uint64_t h) {
  h ^= h >> 30, h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27, h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

std::uint64_t hash_of(const Vec3& p) { return mix(bits(p.x()) ^ mix(bits(p.y()) ^ mix(bits(p.z())))); }

}  // namespace

TriangleMesh weld_coincident(const TriangleMesh& raw) {
  TriangleMesh out;
  const std::size_t n = raw.positions.size();
  std::size_t capacity = 16;
  while (capacity < 2 * n) capacity *= 2;  // load at most one half: short probes
  std::vector<Index> slot(capacity, kInvalid);  // an output vertex, or empty
  const std::size_t mask = capacity - 1;
  std::vector<Index> remap(n);
  out.positions.reserve(n / 4 + 16);
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3& p = raw.positions[v];
    std::size_t i = hash_of(p) & mask;
    while (slot[i] != kInvalid && out.positions[slot[i]] != p) i = (i + 1) & mask;
    if (slot[i] == kInvalid) {
      slot[i] = static_cast<Index>(out.positions.size());
      out.positions.push_back(p);
    }
    remap[v] = slot[i];
  }
  out.positions.shrink_to_fit();
  out.triangles.reserve(raw.triangles.size());
  for (const Tri& t : raw.triangles) out.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  return out;
}

}  // namespace stripweave
