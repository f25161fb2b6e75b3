#include "pysph_bindings/JsonConversion.h"

#include <cmath>

#include "Utilities/Error.h"

namespace consph::python {

json toJson(py::handle value, const std::string& path) {
  if (value.is_none()) return nullptr;
  // bool before int: Python's bool is an int.
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<long long>();
  if (py::isinstance<py::float_>(value)) {
    const double x = value.cast<double>();
    if (!std::isfinite(x)) throw InputError(path + ": " + std::to_string(x) + " is not a finite number");
    return x;
  }
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::dict>(value)) {
    json out = json::object();
    for (auto item : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(item.first)) throw InputError(path + ": dictionary keys must be strings");
      const std::string key = item.first.cast<std::string>();
      out[key] = toJson(item.second, path.empty() ? key : path + "." + key);
    }
    return out;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    json out = json::array();
    std::size_t i = 0;
    for (auto item : value) out.push_back(toJson(item, path + "[" + std::to_string(i++) + "]"));
    return out;
  }
  // NumPy scalars and arrays become plain Python values first.
  if (py::hasattr(value, "tolist")) return toJson(value.attr("tolist")(), path);
  throw InputError(path + ": cannot convert a " + std::string(py::str(value.get_type().attr("__name__"))) + " to JSON");
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
