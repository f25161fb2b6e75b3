// What solvers and forces see of the particles within one step: spans over the fields of a fluid
// and of the boundary samples (StepContext::fluid, StepContext::boundary), not the containers.
// A plugin reads and writes particle values through them; it cannot resize, reorder or reallocate
// them. What does (emitters, Z-order sorting, removal, a volume map's virtual samples rebuilt by
// the neighbour search) happens in Simulation outside the plugins' part of the step, and the view
// is made afresh after it every step (Simulation::step, makeContext): a view kept longer dangles.
// A view's const-ness is shallow, as a span's is: a `const FluidView&` still writes positions,
// velocities and pressures through its members (BodyResponse::respond writes sample velocities
// through a `const BoundaryView&`); what may not be written is typed `std::span<const T>`.
//
// The seam for another backend: every particle loop runs through Utilities/ParallelFor.h over
// index ranges, and every array it touches is one of these spans, the neighbour lists' CSR arrays
// (Simulation/NeighborSearch.h), a plugin's own per-particle vectors, or the fields plugins
// register on the fluid and hold as std::vector& (DFSPH's densityBeta_ / divergenceBeta_, the
// micropolar model's omega_, Akinci 2013's normals_, Weiler 2018's velocityChange_). A GPU
// backend would need (1) these spans to point at device (or unified) memory, made by its own
// FluidModel storage, (2) parallelFor / parallelSum / parallelChunks to launch their bodies as
// kernels (the bodies capture by reference; they would have to capture views by value and be
// device-callable), (3) the plugins' own scratch vectors and registered fields (DFSPH's
// increments, IISPH's a_ii, the MLS coefficients) allocated there too, and (4) the rigid-body
// coupling (BodyResponse), which gathers impulses per body, to stay on the host behind a
// reduction. Nothing here assumes one.
#pragma once
#include <cstddef>
#include <span>

#include "Simulation/BoundarySamples.h"
#include "Simulation/FluidModel.h"

namespace consph {

class FluidView {
 public:
  // Implicit: a StepContext is built from the FluidModel it views.
  FluidView(FluidModel& fluid)  // NOLINT(google-explicit-constructor)
      : positions(fluid.positions),
        velocities(fluid.velocities),
        accelerations(fluid.accelerations),
        densities(fluid.densities),
        pressures(fluid.pressures),
        masses(fluid.masses),
        density0_(fluid.density0()) {}

  std::size_t size() const { return positions.size(); }
  Real density0() const { return density0_; }

  std::span<Vector3r> positions;      // x_i (m)
  std::span<Vector3r> velocities;     // v_i (m/s)
  std::span<Vector3r> accelerations;  // non-pressure acceleration a_i^np (m/s^2)
  std::span<Real> densities;          // rho_i (kg/m^3), Eq. (14)
  std::span<Real> pressures;          // p_i (Pa), the solver's (FluidModel::pressures)
  std::span<const Real> masses;       // m_i (kg)

 private:
  Real density0_;
};

class BoundaryView {
 public:
  // Implicit: a StepContext is built from the boundary model's samples.
  BoundaryView(BoundarySamples& samples)  // NOLINT(google-explicit-constructor)
      : positions(samples.positions), velocities(samples.velocities), masses(samples.masses), bodies(samples.bodies) {}

  std::size_t size() const { return positions.size(); }

  std::span<const Vector3r> positions;  // x_k (m)
  // v_k (m/s): written within a solve only by BodyResponse (a free body's trial motion).
  std::span<Vector3r> velocities;
  std::span<const Real> masses;   // m~_k = rho0 V_k (kg), Eq. (14)
  std::span<const Index> bodies;  // the boundary object k belongs to
};

}  // namespace consph
