// Python objects <-> nlohmann::json, for scene dicts, overrides, summaries and plugin parameters.
#pragma once
#include <pybind11/pybind11.h>

#include "Simulation/Params.h"

namespace consph::python {

namespace py = pybind11;

// dict/list/tuple/str/bool/int/float/None and NumPy scalars and arrays (through .tolist()).
// Anything else (a NaN, which JSON cannot hold, an int outside 64 bits, a lone surrogate, a
// container that contains itself or nests deeper than kMaxJsonDepth) -> InputError naming `path`.
json toJson(py::handle value, const std::string& path);
py::object toPython(const json& value);

}  // namespace consph::python
