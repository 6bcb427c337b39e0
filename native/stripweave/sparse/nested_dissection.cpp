// nested_dissection_order (see the header).
#include "stripweave/sparse/nested_dissection.h"

#include <metis.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace stripweave {

std::vector<int> nested_dissection_order(const std::vector<std::vector<int>>& adjacency) {
  const idx_t n = static_cast<idx_t>(adjacency.size());
  std::vector<int> order(n);
  if (n < 3) {  // nothing to dissect (and METIS wants at least an edge)
    std::iota(order.begin(), order.end(), 0);
    return order;
  }
  // METIS's compressed rows, without self loops or repeated neighbours.
  std::vector<idx_t> xadj(n + 1, 0), adjncy;
  std::vector<idx_t> row;
  for (idx_t i = 0; i < n; ++i) {
    row.assign(adjacency[i].begin(), adjacency[i].end());
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    for (idx_t j : row)
      if (j != i) adjncy.push_back(j);
    xadj[i + 1] = static_cast<idx_t>(adjncy.size());
  }
  if (adjncy.empty()) {
    std::iota(order.begin(), order.end(), 0);
    return order;
  }
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_SEED] = 1;
  std::vector<idx_t> perm(n), iperm(n);
  idx_t nodes = n;
  const int status = METIS_NodeND(&nodes, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data());
  if (status != METIS_OK) throw std::runtime_error("nested_dissection_order: METIS_NodeND failed");
  // METIS: row k of the reordered matrix is row perm[k] of the original.
  for (idx_t k = 0; k < n; ++k) order[k] = static_cast<int>(perm[k]);
  return order;
}

}  // namespace stripweave
