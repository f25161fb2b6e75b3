#include "pysph_bindings/PythonPlugins.h"

#include "pysph_bindings/JsonConversion.h"
#include "pysph_bindings/PythonForce.h"

namespace consph::python {

namespace {

ParamType paramType(const std::string& name, const std::string& where) {
  if (name == "real" || name == "float" || name == "number") return ParamType::Real;
  if (name == "int" || name == "integer") return ParamType::Int;
  if (name == "bool" || name == "boolean") return ParamType::Bool;
  if (name == "string" || name == "str") return ParamType::String;
  if (name == "vector3") return ParamType::Vector3;
  throw py::value_error(where + ": unknown parameter type '" + name + "'; valid are: real, int, bool, string, vector3");
}

ParamSpec paramSpec(const py::handle& item, const std::string& where) {
  if (!py::isinstance<py::dict>(item)) throw py::type_error(where + ": expected a dict (or a consph.Param)");
  const py::dict d = item.cast<py::dict>();
  if (!d.contains("name") || !d.contains("type")) throw py::value_error(where + ": 'name' and 'type' are required");
  ParamSpec spec{d["name"].cast<std::string>(), paramType(d["type"].cast<std::string>(), where),
                 d.contains("default") ? toJson(d["default"], where + ".default") : json(),
                 d.contains("doc") ? d["doc"].cast<std::string>() : std::string()};
  if (d.contains("min") && !d["min"].is_none()) spec.min = d["min"].cast<double>();
  if (d.contains("max") && !d["max"].is_none()) spec.max = d["max"].cast<double>();
  if (d.contains("choices") && !d["choices"].is_none()) spec.choices = d["choices"].cast<std::vector<std::string>>();
  // A default must pass its own checks, or every scene using the plugin would fail later.
  if (!spec.defaultValue.is_null()) validateParam(spec, spec.defaultValue, where + ".default");
  return spec;
}

}  // namespace

void PythonPlugins::addForce(const std::string& name, const std::string& doc, const py::list& parameters,
                             py::object factory) {
  if (name.empty()) throw py::value_error("register_force: empty name");
  if (!PyCallable_Check(factory.ptr())) throw py::type_error("register_force('" + name + "'): the factory must be callable");
  if (builtinPlugins().forces.find(name))
    throw py::value_error("non-pressure force '" + name + "' is already registered (built in)");
  for (const ForceEntry& e : forces_)
    if (e.name == name) throw py::value_error("non-pressure force '" + name + "' is already registered in this registry");
  ForceEntry entry{name, doc, {}, sharePyObject(std::move(factory))};
  for (std::size_t i = 0; i < parameters.size(); ++i)
    entry.parameters.push_back(paramSpec(parameters[i], "register_force('" + name + "').parameters[" + std::to_string(i) + "]"));
  forces_.push_back(std::move(entry));
}

PluginRegistry PythonPlugins::build(const std::weak_ptr<PySimulation>& simulation) const {
  PluginRegistry registry = builtinPlugins();
  for (const ForceEntry& e : forces_) {
    auto factory = [factory = e.factory, simulation, name = e.name](const Params& p,
                                                                     const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      py::gil_scoped_acquire gil;  // factories run inside the Simulation's constructor, GIL released
      const py::dict kwargs = toPython(p.values());
      const py::object force = (*factory)(**kwargs);
      if (!py::hasattr(force, "add_acceleration") && !PyCallable_Check(force.ptr()))
        throw InputError(p.path() + ": the Python force '" + name + "' made an object without add_acceleration(ctx, fluid)");
      return std::make_unique<PythonForce>(force, simulation);
    };
    registry.forces.add({e.name, e.doc, e.parameters, std::move(factory)});
  }
  return registry;
}

std::vector<std::string> PythonPlugins::forceNames() const {
  std::vector<std::string> names;
  for (const ForceEntry& e : forces_) names.push_back(e.name);
  return names;
}

void bindPlugins(py::module_& m) {
  py::class_<PythonPlugins>(m, "_PluginRegistry")
      .def(py::init<>())
      .def("_add_force", &PythonPlugins::addForce, py::arg("name"), py::arg("doc"), py::arg("parameters"), py::arg("factory"))
      .def_property_readonly("python_forces", &PythonPlugins::forceNames, "names of the forces registered from Python")
      .def(
          "to_dict", [](const PythonPlugins& p) { return toPython(p.build({}).toJson()); },
          "Every plugin (built in and Python) with its parameters, as `consph --list-plugins --json`.")
      .def("describe", [](const PythonPlugins& p) { return p.build({}).describe(); },
           "The text `consph --list-plugins` prints.");
}

}  // namespace consph::python
