// nested_dissection_order (see the header).
#include "stripweave/sparse/nested_dissection.h"

#include <metis.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace stripweave {

std::vector<Index> nested_dissection_order(const Csr& graph) {
  const idx_t n = graph.offsets.empty() ? 0 : static_cast<idx_t>(graph.offsets.size() - 1);
  std::vector<Index> order(n);
  if (n < 3 || graph.indices.empty()) {  // nothing to dissect (and METIS wants an edge)
    std::iota(order.begin(), order.end(), 0);
    return order;
  }
  // METIS takes non-const arrays of its own index type. Each row sorted, so
  // that the order depends on the graph, not on how its rows were listed.
  std::vector<idx_t> xadj(graph.offsets.begin(), graph.offsets.end());
  std::vector<idx_t> adjncy(graph.indices.begin(), graph.indices.end());
  for (idx_t i = 0; i < n; ++i) std::sort(adjncy.begin() + xadj[i], adjncy.begin() + xadj[i + 1]);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_SEED] = 1;
  std::vector<idx_t> perm(n), iperm(n);
  idx_t nodes = n;
  const int status = METIS_NodeND(&nodes, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data());
  if (status != METIS_OK) throw std::runtime_error("nested_dissection_order: METIS_NodeND failed");
  // METIS: row k of the reordered matrix is row perm[k] of the original.
  for (idx_t k = 0; k < n; ++k) order[k] = static_cast<Index>(perm[k]);
  return order;
}

}  // namespace stripweave
