// Everything a plugin needs during one step, passed explicitly (no global simulation object).
#pragma once
#include <cstddef>
#include <string>

#include "Simulation/BodyResponse.h"
#include "Simulation/FluidModel.h"
#include "Simulation/Kernel.h"
#include "Simulation/NeighborSearch.h"
#include "Simulation/PaddedNeighborLists.h"
#include "Simulation/ParticleView.h"
#include "Utilities/Log.h"

namespace consph {

// How boundary neighbours enter the pressure solve (paper Sections 3.3 and 3.4.2).
enum class BoundaryPressure {
  Consistent,    // Eqs. (29)-(34): no boundary pressure at all
  Mirroring,     // p_k = p_i, a_k^p = 0 (Akinci 2012)
  Extrapolation  // p_k from an MLS fit of fluid pressures (Band et al. 2018), a_k^p = 0
};
const char* boundaryPressureName(BoundaryPressure b);

struct StepContext {
  FluidView fluid;                         // spans over the fluid's fields (Simulation/ParticleView.h)
  BoundaryView boundary;                   // and over the boundary samples'
  const NeighborLists& fluidNeighbors;     // fluid i -> fluid j (j != i)
  // The same pairs in rows padded to whole blocks, for the sums that take a block of pairs at a
  // time (Simulation/PaddedNeighborLists.h).
  const PaddedNeighborLists& paddedFluidNeighbors;
  const NeighborLists& boundaryNeighbors;  // fluid i -> boundary sample k
  const CubicSplineKernel& kernel;
  Vector3r gravity;
  Real particleRadius;
  Real dt;          // this step's time step (set before the pressure solve)
  Real dtPrevious;  // the previous step's (warm starts scale by it)
  // The time over which the implicit solvers remove a density excess a step starts with (drift),
  // s: the step the resolution calls for (Simulation::chooseTimeStepCap), not the step taken,
  // so lowering the step does not speed the correction up (SphPressureTerms.h, driftTarget).
  Real densityRelaxationTime;
  double time;  // s (double in both builds: Simulation::time_)
  std::size_t step;
  const LogSink& log;
  // The free dynamic bodies, for a solver that lets them answer within its iterations; null
  // when the scene has none.
  BodyResponse* bodies = nullptr;
  // The boundary samples are virtual particles rebuilt every step (volume maps), not sample layers.
  bool implicitBoundary = false;
};

// Passed to plugin factories: what a plugin may look at when it is created.
struct PluginContext {
  FluidModel* fluid;  // the fluid a force belongs to; every fluid for solvers (single fluid today)
  Real particleRadius;
  Real supportRadius;
  const LogSink& log;
  Real particleSpacing = 0;  // m, the fluid lattice spacing d (particle volume d^3); 0: 0.8^(1/3) 2r
  std::string sceneDirectory = {};  // the scene file's folder (relative paths a plugin writes, e.g. a cache)
  // The boundary pressure treatment, for pressure solvers: simulation.boundaryPressure with
  // "auto" resolved for the boundary model (Simulation's constructor).
  BoundaryPressure boundaryPressure = BoundaryPressure::Consistent;
};

}  // namespace consph
