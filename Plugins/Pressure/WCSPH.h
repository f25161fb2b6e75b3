// Weakly compressible SPH after
//   M. Becker, M. Teschner: Weakly compressible SPH for free surface flows. SCA 2007.
// Pressure from the Tait equation p = k ((rho / rho0)^gamma - 1), clamped at 0; explicit.
// Boundary neighbours: BoundaryPressureTreatment (consistent, mirroring or extrapolation).
#pragma once
#include "Plugins/Pressure/BoundaryPressureTreatment.h"
#include "Simulation/Params.h"
#include "Simulation/PressureSolver.h"

namespace consph {

class WCSPH final : public PressureSolver {
 public:
  explicit WCSPH(const Params& params);
  void solve(StepContext& ctx) override;
  void boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const override;
  Real maxStableTimeStep(Real particleRadius, Real density0) const override;
  static std::vector<ParamSpec> parameters();

 private:
  Real stiffness_, exponent_;
  BoundaryPressureTreatment treatment_;
  std::vector<Real> beta_;  // p_i / rho_i^2
};

}  // namespace consph
