// Particle boundaries after
//   N. Akinci, M. Ihmsen, G. Akinci, B. Solenthaler, M. Teschner: Versatile rigid-fluid coupling
//   for incompressible SPH. ACM Transactions on Graphics 31(4), 2012.
// Boundary surfaces are sampled with particles; particle k gets the volume
// V_k = 1 / sum_l W_kl over the particles l of the same object, and the mass m~_k = rho0 V_k.
#pragma once
#include "Simulation/BoundaryModel.h"
#include "Simulation/Params.h"

namespace consph {

class ParticleBoundary_Akinci2012 final : public BoundaryModel {
 public:
  ParticleBoundary_Akinci2012(const Params& params, Real particleRadius);
  void initialize(const std::vector<BoundaryObject>& objects, Real density0, const CubicSplineKernel& kernel) override;
  void findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out) override;

  static std::vector<ParamSpec> parameters();

 private:
  Real samplingDistance_;  // m
  PointGrid grid_;
};

}  // namespace consph
