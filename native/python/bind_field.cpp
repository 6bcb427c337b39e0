// Bindings: see bind.h.
#include "bind.h"

namespace stripweave_python {
void bind_field(pybind11::module_& m) {}
}  // namespace stripweave_python
