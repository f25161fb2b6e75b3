// Micropolar vorticity model after
//   J. Bender, D. Koschier, T. Kugelstadt, M. Weiler: Turbulent Micropolar SPH Fluids with Foam.
//   IEEE Transactions on Visualization and Computer Graphics 25(6), 2019, 2284-2295,
// in SPlisHSPlasH's discretisation (METHODS.md): each particle carries an angular velocity
// omega_i (the field "angularVelocity", registered by this plugin: sorted and exported), coupled
// to the linear velocity both ways:
//   a_i        += (nu_t / rho_i) sum_j m_j (omega_i - omega_j) x grad W_ij          (nu_t curl omega)
//   d omega_i/dt = Theta^-1 nu_t [ (1 / rho_i) sum_j m_j (v_i - v_j) x grad W_ij    (curl v)
//                                  - 2 omega_i ]
//                  - (Theta^-1 zeta / dt) sum_j (m_j / rho_j) (omega_i - omega_j) W_ij (XSPH on omega)
// Boundary samples enter both curls with omega_k = 0 and their velocity v_k. omega relaxes to
// curl v / 2 (the local rotation rate); then nu_t curl omega = -(nu_t / 2) laplacian v, which
// returns the energy numerical diffusion takes from small vortices. omega is advanced with
// explicit Euler inside the force, with ctx.dt (the previous step's dt, as in SPlisHSPlasH).
// The difference form of the curl is the paper's; it does not conserve linear momentum exactly.
// Parameters: `vorticity` nu_t (m^2/s), `inertiaInverse` Theta^-1 (1/m^2),
// `viscosityOmega` zeta (m^2, so that Theta^-1 zeta is the dimensionless XSPH factor).
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"
#include "Simulation/StepContext.h"

namespace consph {

template <class Settings>
class BoundParams;

class MicropolarModel_Bender2019 final : public NonPressureForce {
 public:
  MicropolarModel_Bender2019(const Params& params, FluidModel& fluid);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<MicropolarModel_Bender2019>& bound();
  Real vorticity_, inertiaInverse_, viscosityOmega_;
  std::vector<Vector3r>& omega_;              // angular velocity (1/s), sorted + exported field
  std::vector<Vector3r> angularAcceleration_;  // d omega / dt of this step (scratch)
};

}  // namespace consph
