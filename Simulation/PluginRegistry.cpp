#include "Simulation/PluginRegistry.h"

#include <sstream>

namespace consph {

PluginRegistry& builtinPluginsForRegistration() {
  static PluginRegistry catalogue;  // filled by static PluginRegistration objects, then read-only
  return catalogue;
}
const PluginRegistry& builtinPlugins() { return builtinPluginsForRegistration(); }

namespace {
template <class Base>
void describeRegistry(std::ostringstream& s, const Registry<Base>& r) {
  s << r.category() << "s:\n";
  for (auto& e : r.entries()) {
    s << "  " << e.name << "  - " << e.doc << "\n";
    for (auto& p : e.params) {
      s << "      " << p.name << " (" << paramTypeName(p.type) << ", default "
        << (p.defaultValue.is_null() ? std::string("required") : p.defaultValue.dump()) << ")";
      const std::string range = p.rangeText();
      if (!range.empty()) s << " " << range;
      s << ": " << p.doc << "\n";
    }
  }
}
template <class Base>
json registryJson(const Registry<Base>& r) {
  json out = json::array();
  for (auto& e : r.entries()) {
    json params = json::array();
    for (auto& p : e.params)
      params.push_back({{"name", p.name}, {"type", paramTypeName(p.type)}, {"default", p.defaultValue},
                        {"range", p.rangeText()}, {"doc", p.doc}});
    out.push_back({{"name", e.name}, {"doc", e.doc}, {"parameters", params}});
  }
  return out;
}
}  // namespace

std::string PluginRegistry::describe() const {
  std::ostringstream s;
  describeRegistry(s, pressureSolvers);
  describeRegistry(s, boundaryModels);
  describeRegistry(s, forces);
  return s.str();
}

json PluginRegistry::toJson() const {
  return {{"pressureSolvers", registryJson(pressureSolvers)},
          {"boundaryModels", registryJson(boundaryModels)},
          {"forces", registryJson(forces)}};
}

}  // namespace consph
