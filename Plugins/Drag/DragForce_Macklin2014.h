// Surface drag after
//   M. Macklin, M. Mueller, N. Chentanez, T.-Y. Kim: Unified Particle Physics for Real-Time
//   Applications. ACM Transactions on Graphics 33(4), 2014, 153 (Section 7.1, fluids):
//   a_i -= (c / m_i) (v_i - v_air) max(1 - rho_i / rho0, 0),
// a drag on particles missing neighbours (the free surface). The max(., 0) is ours: SPlisHSPlasH
// lets the factor go negative, which would push compressed interior particles forward.
// Parameters: `drag` c, kg/s (force per unit relative velocity); `airVelocity` v_air, m/s.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"

namespace consph {

template <class Settings>
class BoundParams;

class DragForce_Macklin2014 final : public NonPressureForce {
 public:
  explicit DragForce_Macklin2014(const Params& params);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<DragForce_Macklin2014>& bound();
  Real drag_;
  Vector3r airVelocity_;
};

}  // namespace consph
