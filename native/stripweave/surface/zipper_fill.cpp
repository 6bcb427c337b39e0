#include "stripweave/surface/zipper_fill.h"

namespace stripweave {

std::vector<Tri> zipper_fill(const std::vector<Index>& loop, const std::vector<Vec3>& positions) {
  const size_t n = loop.size();
  size_t a = 0, b = 1;
  double far = -1;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      const double d = (positions[loop[i]] - positions[loop[j]]).squaredNorm();
      if (d > far) far = d, a = i, b = j;
    }
  std::vector<Index> P, Q;  // both from loop[a] to loop[b]: P along the loop, Q against it
  for (size_t k = a;; k = (k + 1) % n) { P.push_back(loop[k]); if (k == b) break; }
  for (size_t k = a;; k = (k + n - 1) % n) { Q.push_back(loop[k]); if (k == b) break; }
  auto dist = [&](Index u, Index v) { return (positions[u] - positions[v]).squaredNorm(); };
  std::vector<Tri> out;
  size_t p = 0, q = 0;
  while (p + 1 < P.size() || q + 1 < Q.size()) {
    const bool advance_p = q + 1 == Q.size() || (p + 1 < P.size() && dist(P[p + 1], Q[q]) <= dist(P[p], Q[q + 1]));
    const Tri t = advance_p ? Tri{P[p + 1], P[p], Q[q]} : Tri{Q[q], Q[q + 1], P[p]};
    advance_p ? ++p : ++q;
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) out.push_back(t);
  }
  return out;
}

}  // namespace stripweave
