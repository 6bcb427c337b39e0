// Errors raised by the native library.
//
// Every failure caused by the user's input is an `InputError` whose message
// names the problem in words a CAD engineer understands ("non-manifold mesh:
// 3 edges are shared by more than two triangles, first near (1, 2, 3)").
// The Python bindings turn it into `stripweave.InputError` (a ValueError).
// `Cancelled` is raised when a long computation sees its cancel flag.
#pragma once

#include <stdexcept>
#include <string>

namespace stripweave {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("computation cancelled") {}
};

}  // namespace stripweave
