#include "pysph_bindings/JsonConversion.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "Simulation/JsonLimits.h"

#include "Utilities/Error.h"

namespace consph::python {

namespace {

// Containers on the way from the root to the value being converted: a container met again is a
// cycle (l = []; l.append(l)), and their count is the nesting depth, bounded like a scene
// file's (kMaxJsonDepth) so that neither this recursion nor a later walk of the JSON overflows
// the stack.
using Ancestors = std::vector<PyObject*>;

std::string text(py::handle value, const std::string& path) {
  try {
    return value.cast<std::string>();
  } catch (const py::error_already_set&) {  // UnicodeEncodeError: a lone surrogate
    throw InputError(path + ": the string is not valid Unicode (a lone surrogate?)");
  } catch (const py::cast_error&) {
    throw InputError(path + ": the string is not valid Unicode (a lone surrogate?)");
  }
}

json convert(py::handle value, const std::string& path, Ancestors& ancestors) {
  if (value.is_none()) return nullptr;
  // bool before int: Python's bool is an int.
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) {
    // JSON numbers here are 64-bit: a negative int must fit int64, a positive one uint64.
    int overflow = 0;
    const long long x = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow == 0) return x;
    if (overflow > 0) {
      const unsigned long long u = PyLong_AsUnsignedLongLong(value.ptr());
      if (!PyErr_Occurred()) return u;
      PyErr_Clear();
    }
    throw InputError(path + ": the integer " + std::string(py::str(value)).substr(0, 40) + " is out of the 64-bit range");
  }
  if (py::isinstance<py::float_>(value)) {
    const double x = value.cast<double>();
    if (!std::isfinite(x)) throw InputError(path + ": " + std::to_string(x) + " is not a finite number");
    return x;
  }
  if (py::isinstance<py::str>(value)) return text(value, path);
  const bool isDict = py::isinstance<py::dict>(value);
  if (isDict || py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    if (std::find(ancestors.begin(), ancestors.end(), value.ptr()) != ancestors.end())
      throw InputError(path + ": the " + std::string(isDict ? "dict" : "list") + " contains itself");
    if (int(ancestors.size()) >= kMaxJsonDepth)
      throw InputError(path + ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    ancestors.push_back(value.ptr());
    json out = isDict ? json::object() : json::array();
    if (isDict) {
      for (auto item : value.cast<py::dict>()) {
        if (!py::isinstance<py::str>(item.first)) throw InputError(path + ": dictionary keys must be strings");
        const std::string key = text(item.first, path + " (a key)");
        out[key] = convert(item.second, path.empty() ? key : path + "." + key, ancestors);
      }
    } else {
      std::size_t i = 0;
      for (auto item : value) out.push_back(convert(item, path + "[" + std::to_string(i++) + "]", ancestors));
    }
    ancestors.pop_back();
    return out;
  }
  // NumPy scalars and arrays become plain Python values first.
  if (py::hasattr(value, "tolist")) return convert(value.attr("tolist")(), path, ancestors);
  throw InputError(path + ": cannot convert a " + std::string(py::str(value.get_type().attr("__name__"))) + " to JSON");
}

}  // namespace

json toJson(py::handle value, const std::string& path) {
  Ancestors ancestors;
  return convert(value, path, ancestors);
}

py::object toPython(const json& value) {
  switch (value.type()) {
    case json::value_t::null: return py::none();
    case json::value_t::boolean: return py::bool_(value.get<bool>());
    case json::value_t::number_integer: return py::int_(value.get<long long>());
    case json::value_t::number_unsigned: return py::int_(value.get<unsigned long long>());
    case json::value_t::number_float: return py::float_(value.get<double>());
    case json::value_t::string: return py::str(value.get<std::string>());
    case json::value_t::array: {
      py::list out;
      for (const auto& v : value) out.append(toPython(v));
      return out;
    }
    case json::value_t::object: {
      py::dict out;
      for (auto it = value.begin(); it != value.end(); ++it) out[py::str(it.key())] = toPython(it.value());
      return out;
    }
    default: return py::none();
  }
}

}  // namespace consph::python
