// Test support for non-pressure forces: a particle set with its neighbour lists, built directly
// (no Simulation, no pressure solver), so a force can be evaluated on a velocity field the test
// prescribes; and scenes from JSON strings for runs through the whole step.
#pragma once
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "Simulation/PluginRegistry.h"
#include "Simulation/Scene.h"
#include "Simulation/Simulation.h"

namespace consph::test {

inline LogSink silentLog() {
  return [](LogLevel, const std::string&) {};
}

// A lattice of particles at spacing d (volume d^3, mass rho0 d^3) with kernel support h.
struct ParticleSet {
  FluidModel fluid{"fluid", 1000};
  BoundarySamples boundary;
  NeighborLists fluidNeighbors, boundaryNeighbors;
  PaddedNeighborLists paddedFluidNeighbors;
  CubicSplineKernel kernel;
  PointGrid grid;
  Real spacing, particleRadius;
  LogSink log = silentLog();

  // nx x ny x nz particles, lower corner at the origin; support h = supportFactor * d.
  ParticleSet(int nx, int ny, int nz, Real d, Real supportFactor = 2)
      : kernel(supportFactor * d), spacing(d), particleRadius(d / 2) {
    std::vector<Vector3r> x;
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j)
        for (int k = 0; k < nz; ++k) x.emplace_back(d * i, d * j, d * k);
    setPositions(x);
  }
  explicit ParticleSet(const std::vector<Vector3r>& x, Real d, Real supportFactor = 2)
      : kernel(supportFactor * d), spacing(d), particleRadius(d / 2) {
    setPositions(x);
  }

  void setPositions(const std::vector<Vector3r>& x) {
    fluid.resize(x.size());
    const Real mass = fluid.density0() * spacing * spacing * spacing;
    for (std::size_t i = 0; i < x.size(); ++i) {
      fluid.positions[i] = x[i];
      fluid.masses[i] = mass;
      fluid.ids[i] = Index(i);
    }
    update();
  }

  // Neighbour lists and densities (Eq. 14, no boundary) of the current positions.
  void update() {
    grid.build(fluid.positions.data(), fluid.size(), kernel.supportRadius());
    buildNeighborLists(grid, fluid.positions.data(), fluid.size(), kernel, true, PairGradients::Factors, fluidNeighbors);
    paddedFluidNeighbors.build(fluidNeighbors);
    boundaryNeighbors.offsets.assign(fluid.size() + 1, 0);
    boundaryNeighbors.indices.clear();
    boundaryNeighbors.gradW.clear();
    for (std::size_t i = 0; i < fluid.size(); ++i) {
      Real rho = fluid.masses[i] * kernel.W0();
      for (Index e = fluidNeighbors.begin(i); e < fluidNeighbors.end(i); ++e) {
        const Index j = fluidNeighbors.indices[e];
        rho += fluid.masses[j] * kernel.W(fluid.positions[i] - fluid.positions[j]);
      }
      fluid.densities[i] = rho;
    }
  }

  StepContext context(Real dt, std::size_t step = 0) {
    return StepContext{fluid, boundary, fluidNeighbors, paddedFluidNeighbors, boundaryNeighbors, kernel,
                       Vector3r::Zero(), particleRadius, dt, dt, /*densityRelaxationTime*/ Real(0), 0, step, log};
  }

  std::unique_ptr<NonPressureForce> create(const std::string& type, json params = json::object()) {
    params["type"] = type;
    const PluginContext pc{&fluid, particleRadius, kernel.supportRadius(), log};
    return builtinPlugins().forces.create(type, params, "fluids[0].forces[0]", pc, log);
  }

  // The acceleration `force` alone gives at the current state (accelerations start at zero).
  std::vector<Vector3r> accelerations(NonPressureForce& force, Real dt) {
    std::fill(fluid.accelerations.begin(), fluid.accelerations.end(), Vector3r::Zero());
    StepContext ctx = context(dt);
    force.addAccelerations(ctx);
    return fluid.accelerations;
  }

  Vector3r centre() const {
    Vector3r c = Vector3r::Zero();
    for (auto& x : fluid.positions) c += x;
    return c / Real(fluid.size());
  }
};

inline Real kineticEnergy(const FluidModel& f) {
  Real e = 0;
  for (std::size_t i = 0; i < f.size(); ++i) e += Real(0.5) * f.masses[i] * f.velocities[i].squaredNorm();
  return e;
}

// A Simulation of a scene given as a JSON string (no output).
inline std::unique_ptr<Simulation> simulationFromJson(const std::string& text) {
  json scene = json::parse(text);
  scene["output"] = {{"enabled", false}};
  return std::make_unique<Simulation>(parseScene(scene, ".", silentLog()), builtinPlugins(), silentLog());
}

}  // namespace consph::test
