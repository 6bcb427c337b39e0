// UnionFind: disjoint sets over the indices 0..n-1, with path halving.
//
// Input   n, then unite(a, b) calls.
// Output  find(a): the class's root, always its smallest index, so a
//         class's representative does not depend on the order of the
//         unions (results that iterate over roots stay deterministic).
#pragma once

#include "stripweave/core/types.h"

#include <algorithm>
#include <numeric>
#include <vector>

namespace stripweave {

struct UnionFind {
  std::vector<Index> parent;

  explicit UnionFind(Index n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }

  Index find(Index a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }

  // Joins the classes of a and b; false when they were one already.
  bool unite(Index a, Index b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

}  // namespace stripweave
