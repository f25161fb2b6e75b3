// Implicit viscosity after
//   M. Weiler, D. Koschier, M. Brand, J. Bender: A Physically Consistent Implicit Viscosity
//   Solver for SPH Fluids. Computer Graphics Forum 37(2) (Eurographics), 2018, 145-155.
// Solves the backward-Euler system (Eq. 11)
//   (I - dt nu L) v' = v   (L: the velocity Laplacian of ViscosityLaplacian.h, Eq. 7,
//                           boundary velocities moved to the right-hand side)
// with a matrix-free conjugate gradient (block-Jacobi preconditioned); rows are multiplied by
// m_i, which makes the system symmetric positive definite for any particle masses. The force
// then adds a_i = (v'_i - v_i) / dt. Warm start: v + last step's v' - v (a sorted field).
//
// Time step: non-pressure forces run before the CFL step is chosen, so ctx.dt here is the
// previous step's dt (the initial time step in step 0); SPlisHSPlasH does the same.
//
// Parameters: `viscosity` nu and `boundaryViscosity` nu_b, kinematic viscosities in m^2/s;
// `maxError`: CG stops when |b - A v'| < maxError |b - A v|, i.e. relative to the viscous change
// (not to |b| as Eigen's default, which accepts an unchanged warm start); `maxIterations`.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"
#include "Simulation/StepContext.h"
#include "Utilities/ConjugateGradient.h"

namespace consph {

template <class Settings>
class BoundParams;

class Viscosity_Weiler2018 final : public NonPressureForce {
 public:
  Viscosity_Weiler2018(const Params& params, FluidModel& fluid);
  void addAccelerations(StepContext& ctx) override;
  bool readsPaddedNeighbors() const override { return kPackedPairSums; }  // packedFluidSum
  static std::vector<ParamSpec> parameters();
  const ConjugateGradientResult& lastSolve() const { return last_; }

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<Viscosity_Weiler2018>& bound();
  Real viscosity_, boundaryViscosity_, maxError_;
  int maxIterations_;
  std::vector<Vector3r>& velocityChange_;  // v' - v of the last solve (warm start), sorted field
  std::vector<Vector3r> rhs_, solution_;
  std::vector<Matrix3r> inverseDiagonal_;  // block-Jacobi preconditioner
  std::vector<Real> positionsVolumes_, fieldSlots_;  // slots of packedFluidSum (ViscosityLaplacian.h)
  ConjugateGradientWorkspace workspace_;
  ConjugateGradientResult last_;
  std::size_t capHits_ = 0;
};

}  // namespace consph
