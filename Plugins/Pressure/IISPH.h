// Implicit incompressible SPH after
//   M. Ihmsen, J. Cornelis, B. Solenthaler, C. Horvath, M. Teschner: Implicit Incompressible SPH.
//   IEEE Transactions on Visualization and Computer Graphics 20(3), 2014,
// in the form of J. Bender, L. Westhofen, S. R. Jeske: Consistent SPH Rigid-Fluid Coupling,
// VMV 2023, Section 3.2: the PPE A p = s (Eq. 8) with s_i = (rho0 - rho*_i) / dt (Eqs. 5, 6),
// (A p)_i = dt nabla^2 p_i from the pressure accelerations (Eqs. 9, 10), diagonal Eq. (12), solved
// by relaxed Jacobi (Eq. 11, omega = 0.5) with negative pressures clamped to 0. Boundary
// neighbours by BoundaryPressureTreatment: Eqs. (15)-(17) (mirroring, extrapolation) or
// Eqs. (32)-(34) (consistent).
#pragma once
#include <vector>

#include "Plugins/Pressure/BoundaryPressureTreatment.h"
#include "Plugins/Pressure/SphPressureTerms.h"
#include "Simulation/Params.h"
#include "Simulation/PressureSolver.h"

namespace consph {

template <class Settings>
class BoundParams;

class IISPH final : public PressureSolver {
 public:
  explicit IISPH(const Params& params, BoundaryPressure treatment = BoundaryPressure::Consistent);
  void solve(StepContext& ctx) override;
  void boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const override;
  static std::vector<ParamSpec> parameters();

 private:
  struct Settings {
    Real maxError;  // fraction of rho0 (average predicted compression)
    int minIterations, maxIterations;
    Real omega;      // Jacobi relaxation
    bool warmStart;  // start from half of the previous step's pressure (Ihmsen et al. 2014)
    Real overlapReliefSpeed;  // m/s, 0: off (maxDensityDrop)
    DensityRelaxation densityRelaxation;  // driftTarget's relaxation time (densityRelaxationTime)
  } settings_;
  // The parameters, each declared once with its place in settings_ (Simulation/ParamBinding.h).
  static const BoundParams<Settings>& bound();

  // s_i (Eq. 5 with Eq. 6) and omega / A_ii (Eq. 12 / 15 / 32); the start pressure.
  void prepare(StepContext& ctx);
  // a_i^p from the current pressures: Eq. (9) plus Eq. (16) or (33).
  void computeAccelerations(StepContext& ctx);
  // One Jacobi sweep, Eq. (11) with Eq. (10) / (17) / (34); returns the average predicted
  // compression (fraction of rho0) of the pressures before the sweep.
  Real jacobiSweep(StepContext& ctx);

  BoundaryPressureTreatment treatment_;
  std::vector<Real> source_;        // (n) s_i = (rho0 - rho*_i) / dt
  std::vector<Real> omegaOverA_;    // (n) omega / A_ii, 0 where A_ii vanishes
  std::vector<Real> beta_;          // (n) p_i / rho_i^2
  std::vector<Vector3r> pressureAcc_;  // (n) a_i^p
};

}  // namespace consph
