// Contract of every registered non-pressure force: it is created from its defaults, rejects a
// parameter of the wrong type or out of its declared range with the JSON path in the message,
// registers particle fields only when active, and gives no acceleration where physics says so
// (a fluid at rest, a fluid in rigid translation with the air).
#include <gtest/gtest.h>

#include "tests/physics/ForceTestSupport.h"

using namespace consph;
using namespace consph::test;

namespace {

std::vector<std::string> forceNames() {
  std::vector<std::string> names;
  for (auto& e : builtinPlugins().forces.entries()) names.push_back(e.name);
  return names;
}

// The catalogue this issue promises (scene names are stable).
TEST(ForcesContract, EveryPromisedForceIsRegistered) {
  for (const char* name : {"XSPH", "StandardViscosity", "Weiler2018", "Micropolar", "VorticityConfinement", "Gissler2017",
                           "Macklin2014", "Akinci2013"})
    EXPECT_NE(builtinPlugins().forces.find(name), nullptr) << name;
}

TEST(ForcesContract, CreatesWithDefaultsAndDocumentsEveryParameter) {
  for (auto& name : forceNames()) {
    ParticleSet set(4, 4, 4, 0.05);
    EXPECT_NO_THROW(set.create(name)) << name;
    for (auto& p : builtinPlugins().forces.find(name)->params) {
      EXPECT_FALSE(p.doc.empty()) << name << "." << p.name;
      EXPECT_FALSE(p.defaultValue.is_null()) << name << "." << p.name << " should have a default";
    }
  }
}

// A message must name the offending key by its JSON path.
void expectRejected(ParticleSet& set, const std::string& name, const std::string& key, const json& value) {
  try {
    set.create(name, json{{key, value}});
    ADD_FAILURE() << name << "." << key << " = " << value.dump() << " was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fluids[0].forces[0]." + key), std::string::npos)
        << name << ": '" << e.what() << "' does not name the JSON path";
  }
}

TEST(ForcesContract, RejectsWrongTypesAndOutOfRangeValuesWithThePath) {
  ParticleSet set(2, 2, 2, 0.05);
  for (auto& name : forceNames())
    for (auto& p : builtinPlugins().forces.find(name)->params) {
      const bool numeric = p.type == ParamType::Real || p.type == ParamType::Int;
      expectRejected(set, name, p.name, numeric || p.type == ParamType::Vector3 ? json("fast") : json(1.5));
      if (numeric && std::isfinite(p.min)) expectRejected(set, name, p.name, p.min - 1);
      if (numeric && std::isfinite(p.max)) expectRejected(set, name, p.name, p.max * 2 + 1);
      if (p.type == ParamType::Int) expectRejected(set, name, p.name, 1.5);
    }
}

TEST(ForcesContract, UnknownForceNameListsTheValidOnes) {
  try {
    auto sim = simulationFromJson(R"({"fluids": [{"forces": [{"type": "Viscosity9000"}],
                                                  "blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]}]})");
    ADD_FAILURE() << "unknown force accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("fluids[0].forces[0].type"), std::string::npos) << what;
    EXPECT_NE(what.find("Weiler2018"), std::string::npos) << what;
  }
}

// Fields exist only while the plugin that needs them is active.
TEST(ForcesContract, PluginFieldsAreAllocatedOnlyWhenActive) {
  const char* scene = R"({"fluids": [{"forces": FORCES, "blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]}]})";
  auto withForces = [&](const std::string& forces) {
    std::string s = scene;
    s.replace(s.find("FORCES"), 6, forces);
    return simulationFromJson(s);
  };
  auto bare = withForces("[]");
  for (const char* field : {"angularVelocity", "normal", "viscosityVelocityChange"})
    EXPECT_FALSE(bare->fluid().fields().has(field)) << field;
  const std::size_t baseFields = bare->fluid().fields().all().size();  // FluidModel's and the solver's

  auto micropolar = withForces(R"([{"type": "Micropolar"}])");
  EXPECT_TRUE(micropolar->fluid().fields().has("angularVelocity"));
  EXPECT_FALSE(micropolar->fluid().fields().has("normal"));
  EXPECT_TRUE(withForces(R"([{"type": "Akinci2013"}])")->fluid().fields().has("normal"));
  EXPECT_TRUE(withForces(R"([{"type": "Weiler2018"}])")->fluid().fields().has("viscosityVelocityChange"));
  for (const char* velocityOnly : {"XSPH", "StandardViscosity", "VorticityConfinement", "Gissler2017", "Macklin2014"})
    EXPECT_EQ(withForces(std::string(R"([{"type": ")") + velocityOnly + "\"}]")->fluid().fields().all().size(), baseFields)
        << velocityOnly << " should register no field";
}

// At rest, and in rigid translation together with the air, no force but surface tension acts;
// surface tension does not depend on the velocity at all (Galilean invariance).
TEST(ForcesContract, NoForceAtRestOrInRigidTranslation) {
  const Vector3r U(0.7, -0.3, 0.2);
  for (auto& name : forceNames()) {
    ParticleSet set(7, 7, 7, 0.05);
    const bool drag = name == "Gissler2017" || name == "Macklin2014";
    auto force = set.create(name, drag ? json{{"airVelocity", {U[0], U[1], U[2]}}} : json::object());
    auto restForce = set.create(name);
    const std::vector<Vector3r> atRest = set.accelerations(*restForce, 0.001);
    for (auto& v : set.fluid.velocities) v = U;
    const std::vector<Vector3r> moving = set.accelerations(*force, 0.001);
    Real scale = 0, restMax = 0, diffMax = 0;
    for (std::size_t i = 0; i < atRest.size(); ++i) {
      scale = std::max(scale, atRest[i].norm());
      restMax = std::max(restMax, atRest[i].norm());
      diffMax = std::max(diffMax, (moving[i] - atRest[i]).norm());
    }
    if (name == "Akinci2013") {
      EXPECT_GT(restMax, 0) << "surface tension acts on a cube at rest";
      EXPECT_LE(diffMax, 1e-12 * restMax) << name << " depends on the translation velocity";
    } else {
      EXPECT_EQ(restMax, 0) << name << " accelerates a fluid at rest";
      EXPECT_LE(diffMax, 1e-12) << name << " accelerates a fluid in rigid translation";
    }
  }
}

}  // namespace
