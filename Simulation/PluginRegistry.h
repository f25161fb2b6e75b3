// The plugin tables of every plugin interface. Built-in plugins add themselves to the built-in
// catalogue from their own .cpp (PluginRegistration); the catalogue is filled before main() and
// never changes after. Each Simulation works on its own copy, to which Python may add plugins,
// so two simulations never share mutable state.
#pragma once
#include "Simulation/BoundaryModel.h"
#include "Simulation/NonPressureForce.h"
#include "Simulation/PressureSolver.h"
#include "Simulation/Registry.h"

namespace consph {

struct PluginRegistry {
  Registry<PressureSolver> pressureSolvers{"pressure solver"};
  Registry<BoundaryModel> boundaryModels{"boundary model"};
  Registry<NonPressureForce> forces{"non-pressure force"};

  template <class Base>
  Registry<Base>& get();

  // Every plugin with its parameters, as `consph --list-plugins` prints it.
  std::string describe() const;
  json toJson() const;
};

template <>
inline Registry<PressureSolver>& PluginRegistry::get<PressureSolver>() { return pressureSolvers; }
template <>
inline Registry<BoundaryModel>& PluginRegistry::get<BoundaryModel>() { return boundaryModels; }
template <>
inline Registry<NonPressureForce>& PluginRegistry::get<NonPressureForce>() { return forces; }

// The built-in catalogue (read-only after static initialisation).
const PluginRegistry& builtinPlugins();
PluginRegistry& builtinPluginsForRegistration();

template <class Base>
struct PluginRegistration {
  PluginRegistration(std::string name, std::string doc, std::vector<ParamSpec> params,
                     typename Registry<Base>::Factory factory) {
    builtinPluginsForRegistration().get<Base>().add({std::move(name), std::move(doc), std::move(params), std::move(factory)});
  }
};

}  // namespace consph
