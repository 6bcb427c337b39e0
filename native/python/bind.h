// The parts of the _stripweave module, one file per pipeline stage.
#pragma once

#include <pybind11/pybind11.h>

namespace stripweave_python {
void bind_loops(pybind11::module_& m);
void bind_field(pybind11::module_& m);   // cross field (paper §6.1)
void bind_param(pybind11::module_& m);   // global parameterization (§6.1)
void bind_design(pybind11::module_& m);  // designs, strips, compatibility (§4.1, §6)
}
