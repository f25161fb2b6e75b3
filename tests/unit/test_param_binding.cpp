// Simulation/ParamBinding.h: a plugin's parameters declared once with their place in its
// settings. The table's declarations are what the registry lists, in order, and assigning fills
// every member from the validated Params: as is, in percent, or through the plugin's own choice.
#include <gtest/gtest.h>

#include <string>

#include "Simulation/ParamBinding.h"
#include "Utilities/Error.h"

using namespace consph;

namespace {

struct Settings {
  Real tolerance = 0, stiffness = 0;
  int iterations = 0;
  bool warmStart = false;
  std::string cache;
  Vector3r air = Vector3r::Zero();
  enum class Mode { Fast, Exact } mode = Mode::Fast;
};

const BoundParams<Settings>& table() {
  static const BoundParams<Settings> t{
      bindPercent({"tolerance", ParamType::Real, 0.01, "tolerated error, %", 1e-6, 100}, &Settings::tolerance),
      bind({"stiffness", ParamType::Real, 5.0, "stiffness", 0, 1e6}, &Settings::stiffness),
      bind({"iterations", ParamType::Int, 100, "iterations", 1, 1000}, &Settings::iterations),
      bind({"warmStart", ParamType::Bool, true, "warm start"}, &Settings::warmStart),
      bind({"cache", ParamType::String, "cache", "folder"}, &Settings::cache),
      bind({"air", ParamType::Vector3, json::array({0, 0, 0}), "air velocity", -10, 10}, &Settings::air),
      bindChoice<Settings>({"mode", ParamType::String, "fast", "mode", -1e300, 1e300, {"exact", "fast"}},
                           [](Settings& s, const std::string& v) { s.mode = v == "exact" ? Settings::Mode::Exact : Settings::Mode::Fast; }),
  };
  return t;
}

const LogSink quiet = [](LogLevel, const std::string&) {};

}  // namespace

TEST(ParamBinding, DeclaresEachParameterOnceInTableOrder) {
  const std::vector<ParamSpec> specs = table().specs();
  ASSERT_EQ(specs.size(), 7u);
  const char* names[] = {"tolerance", "stiffness", "iterations", "warmStart", "cache", "air", "mode"};
  for (std::size_t i = 0; i < specs.size(); ++i) EXPECT_EQ(specs[i].name, names[i]);
  EXPECT_EQ(specs[6].choices, (std::vector<std::string>{"exact", "fast"}));
}

TEST(ParamBinding, AssignsGivenValuesAndDefaults) {
  Settings s;
  table().assign(Params(json{{"tolerance", 0.5}, {"iterations", 7}, {"warmStart", false}, {"air", {1, 2, 3}}, {"mode", "exact"}},
                        "plugin", table().specs(), quiet),
                 s);
  EXPECT_EQ(s.tolerance, Real(0.5) / 100);  // percent, divided as the solvers always did
  EXPECT_EQ(s.stiffness, Real(5));          // default
  EXPECT_EQ(s.iterations, 7);
  EXPECT_FALSE(s.warmStart);
  EXPECT_EQ(s.cache, "cache");
  EXPECT_EQ(s.air, Vector3r(1, 2, 3));
  EXPECT_EQ(s.mode, Settings::Mode::Exact);
}

TEST(ParamBinding, TheDeclarationsValidateTheScene) {
  // The table's specs are the ones Params checks: a value out of range or off the choices is an
  // InputError naming the path.
  auto errorOf = [](const json& j) -> std::string {
    try {
      Params(j, "simulation.plugin", table().specs(), quiet);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(errorOf(json{{"iterations", 0}}).find("simulation.plugin.iterations"), std::string::npos);
  EXPECT_NE(errorOf(json{{"mode", "slow"}}).find("simulation.plugin.mode"), std::string::npos);
}
