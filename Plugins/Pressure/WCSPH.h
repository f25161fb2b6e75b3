// Weakly compressible SPH after
//   M. Becker, M. Teschner: Weakly compressible SPH for free surface flows. SCA 2007.
// Pressure from the Tait equation p = k ((rho / rho0)^gamma - 1), clamped at 0; explicit.
// Boundary neighbours: BoundaryPressureTreatment (consistent, mirroring or extrapolation).
#pragma once
#include "Plugins/Pressure/BoundaryPressureTreatment.h"
#include "Simulation/Params.h"
#include "Simulation/PressureSolver.h"

namespace consph {

template <class Settings>
class BoundParams;

class WCSPH final : public PressureSolver {
 public:
  explicit WCSPH(const Params& params, BoundaryPressure treatment = BoundaryPressure::Consistent);
  void solve(StepContext& ctx) override;
  void boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const override;
  Real maxStableTimeStep(Real particleRadius, Real density0) const override;
  static std::vector<ParamSpec> parameters();

 private:
  struct Settings {
    Real stiffness, exponent;  // Tait: p = k ((rho / rho0)^gamma - 1)
  } settings_;
  // The parameters, each declared once with its place in settings_ (Simulation/ParamBinding.h).
  static const BoundParams<Settings>& bound();
  BoundaryPressureTreatment treatment_;
  std::vector<Real> beta_;  // p_i / rho_i^2
};

}  // namespace consph
