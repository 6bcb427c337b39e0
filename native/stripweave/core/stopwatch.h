// Stopwatch: wall-clock lap times of pipeline stages, for `stripweave bench`.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace stripweave {

using StageTimings = std::vector<std::pair<std::string, double>>;  // (stage, milliseconds), in order

class Stopwatch {
 public:
  explicit Stopwatch(StageTimings& out) : out_(out), last_(Clock::now()) {}
  // Record the time since the previous lap (or construction) under `stage`.
  void lap(const std::string& stage) {
    const auto now = Clock::now();
    out_.emplace_back(stage, std::chrono::duration<double, std::milli>(now - last_).count());
    last_ = now;
  }

 private:
  using Clock = std::chrono::steady_clock;
  StageTimings& out_;
  Clock::time_point last_;
};

}  // namespace stripweave
