// SampleMemo: the refit's samples on the source, remembered between the
// fits of one fit_patch_network call (the first fit, each split trial, the
// refit of the splits that helped). A split changes only the patches of its
// strip and the edges it crosses; every other patch and edge comes back to
// the next fit with the same inputs, and takes its samples from here
// instead of projecting them onto the B-rep again.
//
// Input   a key: every input the samples are a function of, as exact bytes
//         (MemoKey); the fit samples each item from no warm start, so equal
//         inputs give equal samples, and a hit returns exactly what the
//         projection would.
// Output  the value stored under the key, or null.
// Not thread-safe: the fit looks up and stores on its own thread, and
// projects the misses side by side.
#pragma once

#include "stripweave/surface/triangle_mesh.h"
#include "stripweave/surfacing/edge_curves.h"
#include "stripweave/surfacing/patch_fit.h"

#include <cstring>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace stripweave {

// Bytes of the inputs, appended in a fixed order (sizes included, so two
// different inputs never give the same key).
class MemoKey {
 public:
  template <typename T>
  MemoKey& add(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
    return *this;
  }
  MemoKey& add(const Vec3& v) { return add(v.x()).add(v.y()).add(v.z()); }
  MemoKey& add(const Vec2& v) { return add(v.x()).add(v.y()); }
  template <typename T>
  MemoKey& add(const std::vector<T>& values) {
    add(values.size());
    for (const T& v : values) add(v);
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

template <typename T>
class Memo {
 public:
  const T* find(const MemoKey& key) const {
    const auto it = map_.find(key.bytes());
    return it == map_.end() ? nullptr : &it->second;
  }
  void store(const MemoKey& key, T value) { map_.emplace(key.bytes(), std::move(value)); }

 private:
  std::unordered_map<std::string, T> map_;
};

struct SampleMemo {
  Memo<EdgeSamples> edges;          // per edge: its samples (sample_edge)
  Memo<std::vector<Vec3>> moved;    // per patch: its mesh with the border on the smoothed edges
  Memo<PatchSamples> patches;       // per patch: its samples
};

}  // namespace stripweave
