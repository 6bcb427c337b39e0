// Progress and cancellation of a long computation, shared between threads.
//
// The worker calls `stage()` / `advance()` and `check()`; the GUI thread
// polls `fraction()` / `stage_name()` and may call `cancel()`. No callbacks
// cross the thread boundary, so the worker never needs the Python GIL.
#pragma once

#include "stripweave/core/error.h"

#include <atomic>
#include <mutex>
#include <string>

namespace stripweave {

class Progress {
 public:
  // Enter a named stage that spans [begin, end] of the overall fraction.
  void stage(const std::string& name, double begin, double end) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      name_ = name;
    }
    begin_ = begin;
    end_ = end;
    fraction_.store(begin);
    check();
  }
  // Report progress t in [0,1] within the current stage.
  void advance(double t) {
    fraction_.store(begin_ + (end_ - begin_) * t);
    check();
  }
  void check() const {
    if (cancelled_.load()) throw Cancelled();
  }
  void cancel() { cancelled_.store(true); }
  bool cancelled() const { return cancelled_.load(); }
  double fraction() const { return fraction_.load(); }
  std::string stage_name() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return name_;
  }

 private:
  mutable std::mutex mutex_;
  std::string name_;
  double begin_ = 0.0, end_ = 1.0;
  std::atomic<double> fraction_{0.0};
  std::atomic<bool> cancelled_{false};
};

}  // namespace stripweave
