// XSPH velocity smoothing after
//   J. J. Monaghan: On the problem of penetration in particle methods.
//   Journal of Computational Physics 82(1), 1989, 1-15,
// applied as an acceleration, as SPlisHSPlasH's XSPH viscosity does:
//   a_i -= (eps / dt) sum_j (2 m_j / (rho_i + rho_j)) (v_i - v_j) W_ij
//          + (eps_b / dt) sum_k (m~_k / rho_i) (v_i - v_k) W_ik.
// Monaghan's symmetric weight 2 m_j / (rho_i + rho_j) (SPlisHSPlasH uses m_j / rho_j) makes
// pair forces equal and opposite: linear momentum is conserved exactly; angular momentum is not
// (the pair force is along v_ij, not x_ij), as in the original method.
// Parameters: `viscosity` eps and `boundaryViscosity` eps_b are DIMENSIONLESS smoothing factors
// (the fraction of the velocity difference to the neighbourhood average removed per step, 0-1),
// not kinematic viscosities: the effective viscosity of XSPH grows like eps h^2 / dt.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"

namespace consph {

template <class Settings>
class BoundParams;

class Viscosity_XSPH final : public NonPressureForce {
 public:
  explicit Viscosity_XSPH(const Params& params);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<Viscosity_XSPH>& bound();
  Real factor_, boundaryFactor_;
};

}  // namespace consph
