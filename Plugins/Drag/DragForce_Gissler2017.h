// Air drag after
//   C. Gissler, S. Band, A. Peer, M. Ihmsen, M. Teschner: Generalized Drag Force for
//   Particle-based Simulations. Computers & Graphics 69, 2017, 1-11
//   (first as "Approximate Air-Fluid Interactions for SPH", VRIPHYS 2017).
// Each particle is a droplet of radius L = (3 / (4 pi))^(1/3) 2r whose deformation y_max
// (Eqs. 6-8, Taylor analogy breakup) raises the drag coefficient of a sphere (Eq. 9, Liu et al.);
// with neighbours it blends towards a flat surface element (Eqs. 10, 13); the cross-section
// facing the air is occluded by neighbours upstream (Eqs. 14, 15):
//   a_i += c (1 / 2) (rho_a / m_i) |v_rel| v_rel C_D A,  v_rel = v_air - v_i.
// Constants (METHODS.md): rho_a = 1.2041 kg/m^3, sigma = 0.0724 N/m, mu_l = 0.00102 Pa s,
// mu_a = 1.845e-5 Pa s, C_F = 1/3, C_k = 8, C_d = 5, C_b = 0.5.
// Eq. (6) is used as published, t_max = -2 (atan(sqrt(t_d^2 w^2 + 1) + t_d w) - pi) / w;
// SPlisHSPlasH 2.x clamps the atan argument to [-pi/2, pi/2] first, which changes t_max and
// c_def (Eq. 7): at r = 0.025 its c_def is 1.42 where the paper's is 2.00.
// Parameters: `drag` c, dimensionless scale of the model's force (1: as published);
// `airVelocity` v_air, m/s.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"
#include "Simulation/StepContext.h"

namespace consph {

template <class Settings>
class BoundParams;

class DragForce_Gissler2017 final : public NonPressureForce {
 public:
  DragForce_Gissler2017(const Params& params, const PluginContext& context);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

  // The model's constants (public for tests and docs).
  static constexpr Real airDensity = Real(1.2041), surfaceTension = Real(0.0724), liquidViscosity = Real(0.00102),
                        airViscosity = Real(1.845e-5), cF = Real(1) / 3, cK = 8, cD = 5, cB = Real(0.5);
  Real dropletRadius() const { return L_; }
  Real deformationCoefficient() const { return yCoefficient_; }  // y_max = min(1, this |v_rel|^2)

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<DragForce_Gissler2017>& bound();
  Real drag_;
  Vector3r airVelocity_;
  Real diameter_, L_, yCoefficient_;
};

}  // namespace consph
