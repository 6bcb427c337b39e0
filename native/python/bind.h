// The parts of the _stripweave module, one file per pipeline stage.
#pragma once

#include <pybind11/pybind11.h>

namespace stripweave_python {
void bind_loops(pybind11::module_& m);
}
