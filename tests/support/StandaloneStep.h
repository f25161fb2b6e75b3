// A particle set with its neighbour lists and a StepContext, without a Simulation: for tests
// that call a pressure solver or a boundary treatment on hand-made particles.
#pragma once
#include <memory>
#include <vector>

#include "Simulation/StepContext.h"

namespace consph::test {

struct StandaloneStep {
  StandaloneStep(Real particleRadius, Real density0) : radius(particleRadius), kernel(4 * particleRadius), fluid("fluid", density0) {}

  // Neighbour lists of the current positions and the densities of Eq. (14).
  void update() {
    PointGrid fluidGrid;
    fluidGrid.build(fluid.positions.data(), fluid.size(), kernel.supportRadius());
    buildNeighborLists(fluidGrid, fluid.positions.data(), fluid.size(), kernel, true, PairGradients::Factors, fluidNeighbors);
    paddedFluidNeighbors.build(fluidNeighbors);
    PointGrid boundaryGrid;
    boundaryGrid.build(boundary.positions.data(), boundary.size(), kernel.supportRadius());
    buildNeighborLists(boundaryGrid, fluid.positions.data(), fluid.size(), kernel, false, PairGradients::Vectors, boundaryNeighbors);
    for (std::size_t i = 0; i < fluid.size(); ++i) {
      Real rho = fluid.masses[i] * kernel.W0();
      for (Index e = fluidNeighbors.begin(i); e < fluidNeighbors.end(i); ++e)
        rho += fluid.masses[fluidNeighbors.indices[e]] * kernel.W(fluid.positions[i] - fluid.positions[fluidNeighbors.indices[e]]);
      for (Index e = boundaryNeighbors.begin(i); e < boundaryNeighbors.end(i); ++e)
        rho += boundary.masses[boundaryNeighbors.indices[e]] * kernel.W(fluid.positions[i] - boundary.positions[boundaryNeighbors.indices[e]]);
      fluid.densities[i] = rho;
    }
  }

  StepContext context(Real dt) {
    return StepContext{fluid, boundary, fluidNeighbors, paddedFluidNeighbors, boundaryNeighbors, kernel, Vector3r(0, Real(-9.81), 0),
                       radius, dt, dt, /*densityRelaxationTime: within the step*/ Real(0), Real(0), 0, log};
  }

  Real radius;
  CubicSplineKernel kernel;
  FluidModel fluid;
  BoundarySamples boundary;
  NeighborLists fluidNeighbors, boundaryNeighbors;
  PaddedNeighborLists paddedFluidNeighbors;
  LogSink log = [](LogLevel, const std::string&) {};
};

}  // namespace consph::test
