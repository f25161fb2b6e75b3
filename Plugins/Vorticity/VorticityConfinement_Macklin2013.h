// Vorticity confinement after
//   R. Fedkiw, J. Stam, H. W. Jensen: Visual Simulation of Smoke. SIGGRAPH 2001, 15-22,
// in the SPH form of
//   M. Macklin, M. Mueller: Position Based Fluids. ACM Transactions on Graphics 32(4), 2013, 104:
//   omega_i = (1 / rho_i) sum_j m_j (v_i - v_j) x grad W_ij            (curl v)
//   eta_i   = (1 / rho_i) sum_j m_j (|omega_j| - |omega_i|) grad W_ij  (grad |omega|)
//   a_i    += eps (eta_i / |eta_i|) x omega_i,
// which accelerates the flow around concentrations of vorticity, returning energy that numerical
// diffusion removes. Where |omega| is uniform (rigid rotation) the direction eta / |eta| is
// undefined and the force is zero. omega is recomputed every step (scratch, not a field).
// Note: SPlisHSPlasH's VorticityConfinement accumulates omega with the opposite sign (-curl v),
// so its force opposes the rotation; here the sign is Fedkiw's (test_forces_vorticity checks the
// energy gain).
// Parameter: `vorticity` eps, m/s (a = eps N x omega with N dimensionless, omega in 1/s).
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"

namespace consph {

template <class Settings>
class BoundParams;

class VorticityConfinement_Macklin2013 final : public NonPressureForce {
 public:
  explicit VorticityConfinement_Macklin2013(const Params& params);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<VorticityConfinement_Macklin2013>& bound();
  Real epsilon_;
  std::vector<Vector3r> omega_;  // curl v of this step (scratch)
  std::vector<Real> omegaNorm_;  // |omega| (scratch)
};

}  // namespace consph
