// Standard SPH viscosity (the Laplacian approximation used by SPlisHSPlasH's "Standard"
// viscosity, after Monaghan 2005 / Morris et al. 1997):
//   a_i = 2 (d + 2) nu sum_j (m_j / rho_j) (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) grad W_ij,
// with an optional boundary term using the boundary samples' masses and velocities.
// `viscosity` and `boundaryViscosity` are kinematic viscosities in m^2/s.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"

namespace consph {

class Viscosity_Standard final : public NonPressureForce {
 public:
  explicit Viscosity_Standard(const Params& params);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

 private:
  Real viscosity_, boundaryViscosity_;
};

}  // namespace consph
