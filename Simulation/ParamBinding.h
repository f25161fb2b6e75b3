// A plugin's parameters declared once: each declaration (a ParamSpec) comes with where its value
// goes in the plugin's settings, so a parameter's name is written once, not once in the
// declaration and again in the look-up. A plugin keeps one table:
//
//   const BoundParams<Settings>& bound() {
//     static const BoundParams<Settings> table{
//         bindPercent({"maxError", ParamType::Real, 0.01, "tolerated compression, % of rho0", 1e-6, 100}, &Settings::maxError),
//         bind({"maxIterations", ParamType::Int, 100, "maximum iterations", 1, 100000}, &Settings::maxIterations),
//         bindChoice(densityRelaxationParameter(), [](Settings& s, const std::string& v) { s.relax = v == "resolution"; }),
//     };
//     return table;
//   }
//   parameters() returns bound().specs(); the constructor calls bound().assign(params, settings_).
#pragma once
#include <functional>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <vector>

#include "Simulation/Params.h"

namespace consph {

template <class Settings>
struct BoundParam {
  ParamSpec spec;
  std::function<void(const Params&, Settings&)> assign;  // reads spec.name from the validated Params
};

template <class Settings>
class BoundParams {
 public:
  BoundParams(std::initializer_list<BoundParam<Settings>> params) : params_(params) {}
  // The declarations, in table order (the registry's, --list-plugins').
  std::vector<ParamSpec> specs() const {
    std::vector<ParamSpec> out;
    for (const BoundParam<Settings>& p : params_) out.push_back(p.spec);
    return out;
  }
  // Every parameter's value into its place in `settings`.
  void assign(const Params& params, Settings& settings) const {
    for (const BoundParam<Settings>& p : params_) p.assign(params, settings);
  }
  // The values as declared, for a constructor that derives its members from them (a length in
  // particle radii turned into metres).
  Settings read(const Params& params) const {
    Settings settings{};
    assign(params, settings);
    return settings;
  }

 private:
  std::vector<BoundParam<Settings>> params_;
};

// The parameter's value as it is (Real, Int, Bool, String or Vector3: the member's type decides
// which look-up, and must be the spec's).
template <class Settings, class Member>
BoundParam<Settings> bind(ParamSpec spec, Member Settings::*member) {
  const std::string name = spec.name;
  return {std::move(spec), [name, member](const Params& p, Settings& s) {
            if constexpr (std::is_same_v<Member, bool>) s.*member = p.boolean(name);
            else if constexpr (std::is_same_v<Member, int>) s.*member = p.integer(name);
            else if constexpr (std::is_same_v<Member, std::string>) s.*member = p.string(name);
            else if constexpr (std::is_same_v<Member, Vector3r>) s.*member = p.vector3(name);
            else {
              static_assert(std::is_floating_point_v<Member>, "bind: a Real, int, bool, string or Vector3r member");
              s.*member = Member(p.real(name));
            }
          }};
}

// A Real parameter given in percent, stored as a fraction (value / 100).
template <class Settings>
BoundParam<Settings> bindPercent(ParamSpec spec, Real Settings::*member) {
  const std::string name = spec.name;
  return {std::move(spec), [name, member](const Params& p, Settings& s) { s.*member = p.real(name) / 100; }};
}

// A String parameter whose value the plugin turns into its own setting (an enum, a flag).
template <class Settings>
BoundParam<Settings> bindChoice(ParamSpec spec, std::function<void(Settings&, const std::string&)> set) {
  const std::string name = spec.name;
  return {std::move(spec), [name, set = std::move(set)](const Params& p, Settings& s) { set(s, p.string(name)); }};
}

}  // namespace consph
