// Surface tension and adhesion after
//   N. Akinci, G. Akinci, M. Teschner: Versatile Surface Tension and Adhesion for SPH Fluids.
//   ACM Transactions on Graphics 32(6) (SIGGRAPH Asia), 2013, 182:
//   n_i   = h sum_j (m_j / rho_j) grad W_ij                       (Eq. 5, field "normal")
//   a_i  += sum_j K_ij [ -gamma m_j C(|x_ij|) x_ij / |x_ij|         (cohesion, Eqs. 1, 2)
//                        -gamma (n_i - n_j) ]                        (curvature, Eq. 4)
//         - beta sum_k m~_k A(|x_ik|) x_ik / |x_ik|                  (adhesion to boundaries, Eqs. 6, 7)
//   K_ij = 2 rho0 / (rho_i + rho_j)                                   (Eq. 3)
// with the cohesion spline C and the adhesion spline A of the paper (support h). The normals
// are a field registered by this plugin (sorted and exported: visible in the .vtu).
// Parameters: `surfaceTension` gamma and `boundaryAdhesion` beta. Units: the paper mixes them;
// in the cohesion term gamma multiplies m_j C (kg/m^3), so gamma is in m^4 kg^-1 s^-2 there,
// while in the curvature term it multiplies the dimensionless n_i - n_j (m/s^2). Values are
// SPlisHSPlasH's (0.05-2 for water at r = 0.025 m); they are not a physical sigma in N/m.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"
#include "Simulation/StepContext.h"

namespace consph {

template <class Settings>
class BoundParams;

class SurfaceTension_Akinci2013 final : public NonPressureForce {
 public:
  SurfaceTension_Akinci2013(const Params& params, FluidModel& fluid);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

  // The paper's kernels with support h (Eqs. 2 and 7), constants precomputed once per step.
  struct Kernels {
    explicit Kernels(Real h);
    Real cohesion(Real r) const;
    Real adhesion(Real r) const;
    Real h, cohesionScale, cohesionOffset, adhesionScale;
  };

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<SurfaceTension_Akinci2013>& bound();
  Real gamma_, beta_;
  std::vector<Vector3r>& normals_;  // n_i (dimensionless), sorted + exported field
};

}  // namespace consph
