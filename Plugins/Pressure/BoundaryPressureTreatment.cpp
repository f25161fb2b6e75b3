#include "Plugins/Pressure/BoundaryPressureTreatment.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>

#include "Utilities/ParallelFor.h"

namespace consph {

void BoundaryPressureTreatment::beginStep(const StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const BoundaryView& b = ctx.boundary;
  const NeighborLists& bn = ctx.boundaryNeighbors;
  invRho0Squared_ = Real(1) / (f.density0() * f.density0());
  const std::size_t n = f.size();
  gradientSum_.resize(n);
  diagonalTerm_.resize(n);
  // The squeeze of the consistent diagonal (diagonalTerm), on sampled walls only.
  const bool squeeze = !classicalDiagonal_ && !ctx.implicitBoundary;
  squeeze_.resize(keepSqueeze_ ? n : 0);
  // Samples of one object squeeze nothing (squeezeOf: 0 below two objects), so its pass over the
  // pairs is skipped then (3 % of a particle-wall dam break's step, whose tank is one object).
  const bool severalObjects =
      (squeeze || keepSqueeze_) && parallelAny(b.size(), [&](std::size_t k) { return b.bodies[k] != b.bodies[0]; });
  // The samples' part of the density rate (densityRate), only where it is read and some sample moves.
  const bool movingSamples =
      keepSampleFlux_ && parallelAny(b.size(), [&](std::size_t k) { return b.velocities[k] != Vector3r::Zero(); });
  sampleFlux_.resize(movingSamples ? n : 0);
  parallelFor(n, [&](std::size_t i) {
    Vector3r g = Vector3r::Zero();
    Real squares = 0, flux = 0;
    for (Index e = bn.begin(i); e < bn.end(i); ++e) {
      const Index k = bn.indices[e];
      const Real mk = b.masses[k];
      g += mk * bn.gradW[e];
      squares += mk * bn.gradW[e].squaredNorm();
      if (movingSamples) flux += mk * b.velocities[k].dot(bn.gradW[e]);
    }
    gradientSum_[i] = g;
    if (movingSamples) sampleFlux_[i] = flux;
    const Real squeezeI = severalObjects ? squeezeOf(ctx, i, g) : Real(0);
    if (keepSqueeze_) squeeze_[i] = squeezeI;
    const Real weight = classicalDiagonal_ ? Real(1) : squeeze ? squeezeI : Real(0);
    diagonalTerm_[i] = weight * f.masses[i] * squares;  // Eq. (15), weighted
  });
  if (extrapolates()) computeMlsCoefficients(ctx);
}

Real BoundaryPressureTreatment::squeezeOf(const StepContext& ctx, std::size_t i, const Vector3r& g) const {
  // g_i split by boundary object: 1 - |sum_o g_o| / sum_o |g_o|.
  const BoundaryView& b = ctx.boundary;
  const NeighborLists& bn = ctx.boundaryNeighbors;
  std::array<Index, kSqueezeObjects> object;
  std::array<Vector3r, kSqueezeObjects> objectGradient;
  int objects = 0;
  for (Index e = bn.begin(i); e < bn.end(i); ++e) {
    const Index k = bn.indices[e];
    int o = 0;
    while (o < objects && object[o] != b.bodies[k]) ++o;
    if (o == objects) {
      if (objects < kSqueezeObjects) object[objects] = b.bodies[k], objectGradient[objects++] = Vector3r::Zero();
      else o = objects - 1;
    }
    objectGradient[o] += b.masses[k] * bn.gradW[e];
  }
  if (objects < 2) return 0;
  Real lengths = 0;
  for (int o = 0; o < objects; ++o) lengths += objectGradient[o].norm();
  return lengths > 0 ? std::clamp(Real(1) - g.norm() / lengths, Real(0), Real(1)) : Real(0);
}

void BoundaryPressureTreatment::computeMlsCoefficients(const StepContext& ctx) {
  // Band et al. 2018, linear MLS around x_k with weights w_f = V_f W_kf:
  //   x_bar = sum w_f x_f / sum w_f,  M = sum w_f (x_f - x_bar)(x_f - x_bar)^T / sum w_f,
  //   p_k = p_bar + (M^-1 sum w_f p_f (x_f - x_bar) / sum w_f) . (x_k - x_bar)
  // is linear in the fluid pressures: p_k = sum_f c_kf p_f with
  //   c_kf = w_f / sum w_f (1 + (x_f - x_bar) . M^-1 (x_k - x_bar)),
  // so M is inverted once per step and each iteration is one sparse product (extrapolate()).
  // Near-singular M (the fluid around x_k is flat or a line): c_kf = w_f / sum w_f (the
  // weighted average p_bar).
  const FluidView& f = ctx.fluid;
  const BoundaryView& b = ctx.boundary;
  const CubicSplineKernel& kernel = ctx.kernel;
  transposeNeighborLists(ctx.boundaryNeighbors, b.size(), boundaryToFluid_);
  const NeighborLists& t = boundaryToFluid_;
  mlsCoefficients_.resize(t.pairCount());
  pk_.assign(b.size(), Real(0));
  pkChange_.assign(b.size(), Real(0));
  // Dynamic: samples without fluid neighbours cost nothing. The counts are integers, exact in
  // any grouping.
  struct Counts {
    std::size_t fallbacks = 0, limited = 0;
  };
  auto join = [](Counts& into, const Counts& from) {
    into.fallbacks += from.fallbacks;
    into.limited += from.limited;
  };
  const Counts counts = parallelReduceDynamic(b.size(), Counts{}, join, [&](std::size_t k, Counts& count) {
    if (t.count(k) == 0) return;
    const Vector3r xk = b.positions[k];
    Real sumW = 0;
    Vector3r xBar = Vector3r::Zero();
    for (Index e = t.begin(k); e < t.end(k); ++e) {
      const Index j = t.indices[e];
      const Real w = f.masses[j] / f.densities[j] * kernel.W(xk - f.positions[j]);
      mlsCoefficients_[e] = w;  // the weight for now, the coefficient below
      sumW += w;
      xBar += w * f.positions[j];
    }
    if (sumW <= Real(0)) {  // every neighbour exactly on the support sphere
      for (Index e = t.begin(k); e < t.end(k); ++e) mlsCoefficients_[e] = Real(1) / Real(t.count(k));
      ++count.fallbacks;
      return;
    }
    const Real invSumW = Real(1) / sumW;
    xBar *= invSumW;
    Matrix3r m = Matrix3r::Zero();
    for (Index e = t.begin(k); e < t.end(k); ++e) {
      const Vector3r d = f.positions[t.indices[e]] - xBar;
      m.noalias() += (mlsCoefficients_[e] * invSumW) * d * d.transpose();
    }
    // M^-1 (x_k - x_bar) from the eigen-decomposition: its eigenvalues tell how flat the fluid is.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<Real, 3, 3>> eig;
    eig.computeDirect(Eigen::Matrix<Real, 3, 3>(m));
    const auto& lambda = eig.eigenvalues();  // ascending
    Vector3r slope = Vector3r::Zero();
    if (t.count(k) >= 4 && lambda[2] > Real(0) && lambda[0] > kSingularRatio * lambda[2]) {
      const auto& v = eig.eigenvectors();
      slope = v * (v.transpose() * (xk - xBar)).cwiseQuotient(lambda);
      // The slope's amplification: how far the fit moves p_k from p_bar per unit of the fluid's
      // pressure spread, max_f |(x_f - x_bar) . M^-1 (x_k - x_bar)| (kMaxSlopeAmplification).
      Real amplification = 0;
      for (Index e = t.begin(k); e < t.end(k); ++e)
        amplification = std::max(amplification, std::abs((f.positions[t.indices[e]] - xBar).dot(slope)));
      if (amplification > kMaxSlopeAmplification) {
        slope *= kMaxSlopeAmplification / amplification;
        ++count.limited;
      }
    } else {
      ++count.fallbacks;
    }
    for (Index e = t.begin(k); e < t.end(k); ++e)
      mlsCoefficients_[e] *= invSumW * (Real(1) + (f.positions[t.indices[e]] - xBar).dot(slope));
  });
  fallbacks_ = counts.fallbacks;
  limitedSlopes_ = counts.limited;
}

void BoundaryPressureTreatment::computeExtrapolationCoupling(const StepContext& ctx) {
  // h_i = sum_k m~_k c_ki grad W_ik: how the boundary term of a_i^p moves with p_i through the
  // extrapolated p_k (each k's list holds its fluid neighbours in ascending order).
  const BoundaryView& b = ctx.boundary;
  const NeighborLists& bn = ctx.boundaryNeighbors;
  const NeighborLists& t = boundaryToFluid_;
  const std::size_t n = ctx.fluid.size();
  extrapolationGradient_.resize(n);
  parallelFor(n, [&](std::size_t i) {
    Vector3r h = Vector3r::Zero();
    for (Index e = bn.begin(i); e < bn.end(i); ++e) {
      const Index k = bn.indices[e];
      const auto first = t.indices.begin() + t.begin(k), last = t.indices.begin() + t.end(k);
      const auto slot = std::lower_bound(first, last, Index(i));
      h += (b.masses[k] * mlsCoefficients_[std::size_t(slot - t.indices.begin())]) * bn.gradW[e];
    }
    extrapolationGradient_[i] = h;
  });
}

void BoundaryPressureTreatment::resetBoundaryPressures() {
  std::fill(pk_.begin(), pk_.end(), Real(0));
  std::fill(pkChange_.begin(), pkChange_.end(), Real(0));
}

void BoundaryPressureTreatment::reactionImpulses(const StepContext& ctx, Real dt, const std::vector<Real>& beta,
                                                 std::span<const Real> pressure, std::vector<Vector3r>& impulsePerPair) const {
  const FluidView& f = ctx.fluid;
  const auto& bn = ctx.boundaryNeighbors;
  impulsePerPair.resize(bn.pairCount());
  parallelFor(f.size(), [&](std::size_t i) {
    for (Index e = bn.begin(i); e < bn.end(i); ++e) {
      const Index k = bn.indices[e];
      const Real c = dt * f.masses[i] * ctx.boundary.masses[k] * pairFactor(k, beta[i], pressure[i], pk_);
      impulsePerPair[e] = c * bn.gradW[e];
    }
  });
}

}  // namespace consph
