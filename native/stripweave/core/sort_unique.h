// sort_unique: a vector sorted, each value once (index lists of faces,
// neighbours, vertices).
#pragma once

#include <algorithm>
#include <vector>

namespace stripweave {

template <typename T>
void sort_unique(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace stripweave
