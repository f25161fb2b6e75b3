// A plugin registry for Python: the built-in catalogue plus forces written in Python, registered
// under a name a scene file can use ({"type": "Wind", "strength": 2}). Each Simulation gets its
// own C++ PluginRegistry built from it at creation, so registering never touches C++ globals and
// two simulations never share plugin state.
#pragma once
#include "pysph_bindings/PySimulation.h"

namespace consph::python {

class PythonPlugins {
 public:
  // `parameters`: dicts {name, type ("real"|"int"|"bool"|"string"|"vector3"), default (None:
  // required), doc, min, max, choices}; `factory(**parameters)` returns the force object.
  void addForce(const std::string& name, const std::string& doc, const py::list& parameters, py::object factory);
  // The built-in plugins plus these Python forces, whose instances call back into `simulation`.
  PluginRegistry build(const std::weak_ptr<PySimulation>& simulation) const;
  std::vector<std::string> forceNames() const;

 private:
  struct ForceEntry {
    std::string name, doc;
    std::vector<ParamSpec> parameters;
    SharedPyObject factory;
  };
  std::vector<ForceEntry> forces_;
};

void bindPlugins(py::module_& m);

}  // namespace consph::python
