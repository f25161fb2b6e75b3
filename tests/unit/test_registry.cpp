// Plugin registry: built-ins present, unknown names and bad parameters are clear errors, and
// every registered plugin can be created from its declared defaults.
#include <gtest/gtest.h>

#include "Simulation/PluginRegistry.h"
#include "TestUtil.h"

using namespace consph;

namespace {
std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST(Registry, BuiltinNamesPresent) {
  const PluginRegistry& r = builtinPlugins();
  for (const char* name : {"DFSPH", "WCSPH"}) EXPECT_NE(r.pressureSolvers.find(name), nullptr) << name;
  EXPECT_NE(r.boundaryModels.find("Akinci2012"), nullptr);
  EXPECT_NE(r.forces.find("StandardViscosity"), nullptr);
  EXPECT_NE(r.pressureSolvers.find("dfsph"), nullptr);  // case-insensitive
}

TEST(Registry, DuplicateNameIsRefused) {
  PluginRegistry r = builtinPlugins();
  const auto& e = *r.pressureSolvers.find("DFSPH");
  EXPECT_THROW(r.pressureSolvers.add(e), std::logic_error);
}

TEST(Registry, UnknownNameListsValidOnes) {
  FluidModel fluid("water", 1000);
  LogSink log;
  const PluginContext ctx{&fluid, Real(0.025), Real(0.1), log};
  const std::string msg = messageOf([&] {
    builtinPlugins().pressureSolvers.create("SPHX", json{{"type", "SPHX"}}, "simulation.pressureSolver", ctx, log);
  });
  EXPECT_NE(msg.find("simulation.pressureSolver.type"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown pressure solver 'SPHX'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("DFSPH"), std::string::npos) << msg;
  EXPECT_NE(msg.find("WCSPH"), std::string::npos) << msg;
}

TEST(Registry, WrongTypeAndRangeNameTheJsonPath) {
  FluidModel fluid("water", 1000);
  LogSink log;
  const PluginContext ctx{&fluid, Real(0.025), Real(0.1), log};
  const auto& solvers = builtinPlugins().pressureSolvers;
  std::string msg = messageOf([&] {
    solvers.create("DFSPH", json{{"type", "DFSPH"}, {"maxError", "small"}}, "simulation.pressureSolver", ctx, log);
  });
  EXPECT_NE(msg.find("simulation.pressureSolver.maxError: expected a number"), std::string::npos) << msg;
  msg = messageOf([&] {
    solvers.create("DFSPH", json{{"type", "DFSPH"}, {"maxIterations", -3}}, "simulation.pressureSolver", ctx, log);
  });
  EXPECT_NE(msg.find("simulation.pressureSolver.maxIterations: value -3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
  msg = messageOf([&] {
    solvers.create("DFSPH", json{{"type", "DFSPH"}, {"maxIterations", 2.5}}, "simulation.pressureSolver", ctx, log);
  });
  EXPECT_NE(msg.find("expected an integer"), std::string::npos) << msg;
}

TEST(Registry, UnknownKeyWarnsWithPath) {
  FluidModel fluid("water", 1000);
  test::CapturedLog captured;
  const LogSink log = captured.sink();
  const PluginContext ctx{&fluid, Real(0.025), Real(0.1), log};
  builtinPlugins().pressureSolvers.create("DFSPH", json{{"type", "DFSPH"}, {"maxErorr", 0.1}}, "simulation.pressureSolver", ctx, log);
  ASSERT_EQ(captured.warnings.size(), 1u);
  EXPECT_NE(captured.warnings[0].find("simulation.pressureSolver.maxErorr"), std::string::npos) << captured.warnings[0];
  EXPECT_NE(captured.warnings[0].find("maxError"), std::string::npos);  // lists the known keys
}

namespace {
template <class Base>
void createEveryPluginFromDefaults(const Registry<Base>& registry) {
  for (const auto& entry : registry.entries()) {
    FluidModel fluid("water", 1000);
    test::CapturedLog captured;
    const LogSink log = captured.sink();
    const PluginContext ctx{&fluid, Real(0.025), Real(0.1), log};
    std::unique_ptr<Base> plugin;
    EXPECT_NO_THROW(plugin = registry.create(entry.name, json{{"type", entry.name}}, "p", ctx, log)) << entry.name;
    EXPECT_NE(plugin, nullptr) << entry.name;
    EXPECT_TRUE(captured.warnings.empty()) << entry.name;
    EXPECT_FALSE(entry.doc.empty()) << entry.name;
    for (const auto& p : entry.params) {
      EXPECT_FALSE(p.doc.empty()) << entry.name << "." << p.name;
      if (!p.defaultValue.is_null()) {
        EXPECT_NO_THROW(validateParam(p, p.defaultValue, p.name)) << entry.name << "." << p.name;
      }
    }
  }
}
}  // namespace

TEST(Registry, EveryPluginCreatesFromDeclaredDefaults) {
  createEveryPluginFromDefaults(builtinPlugins().pressureSolvers);
  createEveryPluginFromDefaults(builtinPlugins().boundaryModels);
  createEveryPluginFromDefaults(builtinPlugins().forces);
}

TEST(Registry, DescribeListsEveryPluginAndParameter) {
  const std::string text = builtinPlugins().describe();
  for (const auto& e : builtinPlugins().pressureSolvers.entries()) {
    EXPECT_NE(text.find(e.name), std::string::npos);
    for (const auto& p : e.params) EXPECT_NE(text.find(p.name), std::string::npos);
  }
}
