// Cubic spline kernel in 3D with support radius h (SPlisHSPlasH convention: h = 4 r).
// W(q) = k (6q^3 - 6q^2 + 1) for q <= 1/2, 2k (1 - q)^3 for 1/2 < q <= 1, k = 8 / (pi h^3).
#pragma once
#include <cmath>
#include <cstring>
#include <numbers>

#include "Simulation/Common.h"

namespace consph {

class CubicSplineKernel {
 public:
  explicit CubicSplineKernel(Real supportRadius = Real(0.1)) { setSupportRadius(supportRadius); }

  void setSupportRadius(Real h) {
    h_ = h;
    invH_ = Real(1) / h;
    const Real pi = std::numbers::pi_v<Real>;
    k_ = Real(8) / (pi * h * h * h);
    l_ = Real(48) / (pi * h * h * h);
    w0_ = W(Real(0));
  }
  Real supportRadius() const { return h_; }
  Real W0() const { return w0_; }

  Real W(Real r) const {
    const Real q = r * invH_;
    if (q > Real(1)) return Real(0);
    if (q <= Real(0.5)) return k_ * (Real(6) * q * q * q - Real(6) * q * q + Real(1));
    const Real t = Real(1) - q;
    return k_ * Real(2) * t * t * t;
  }
  Real W(const Vector3r& x) const { return W(x.norm()); }

  // dW/dr at distance r (<= 0).
  Real dWdr(Real r) const {
    const Real q = r * invH_;
    if (q > Real(1)) return Real(0);
    if (q <= Real(0.5)) return l_ * q * (Real(3) * q - Real(2)) * invH_;
    const Real t = Real(1) - q;
    return -l_ * t * t * invH_;
  }

  // grad W(x) = x gradFactor(|x|) with x = x_i - x_j (points from j to i). Neighbour lists store
  // the scalar factor per pair and multiply it by x_ij where a loop needs the gradient: 4 bytes
  // per pair to stream instead of 12, and the same bits as this function (but in float builds on
  // AVX2 or AVX-512, whose distances may be an ulp off Eigen's norm: NeighborSearch.cpp).
  Real gradFactor(Real r) const {
    const Real q = r * invH_;
    if (q > Real(1) || r < Real(1e-9) * h_) return Real(0);
    const Real c = invH_ / r;  // |grad q| / r
    if (q <= Real(0.5)) return (l_ * q * (Real(3) * q - Real(2))) * c;
    const Real t = Real(1) - q;
    return (-l_ * t * t) * c;
  }
  Vector3r gradW(const Vector3r& x) const { return x * gradFactor(x.norm()); }

  // gradFactor(r[a]) into g[a] and, where w is given, W(r[a]) into w[a], for a in [0, n): the
  // neighbour search's accepted pairs, a vector register at a time (8 floats or 4 doubles with
  // AVX2). Both pieces of the spline are computed and the right one picked, each written as the
  // functions above write it, so the values have the same bits as theirs (the kernel test
  // asserts it); branching per pair on q <= 1/2, which holds for an eighth of the pairs in
  // no pattern, cost more than computing both.
  void evaluate(const Real* r, std::size_t n, Real* g, Real* w) const {
    if (w)
      evaluatePieces<true>(r, n, g, w);
    else
      evaluatePieces<false>(r, n, g, w);
  }

 private:
  template <bool kValues>
  void evaluatePieces(const Real* r, std::size_t n, Real* g, Real* w) const {
    std::size_t a = 0;
#if defined(__GNUC__)
    // GCC's vector types: element-wise arithmetic (contracted into FMAs as the scalar code is)
    // and element-wise selects, so no branch and no trapping operation under a condition, which
    // is what stops the plain loop from vectorising (-ftrapping-math).
    using Pack = Real __attribute__((vector_size(32)));
    constexpr std::size_t kLanes = sizeof(Pack) / sizeof(Real);
    const Real tiny = Real(1e-9) * h_;
    const std::size_t packed = n - n % kLanes;
    for (; a < packed; a += kLanes) {
      Pack ra;
      std::memcpy(&ra, r + a, sizeof(Pack));
      const Pack q = ra * invH_, t = Real(1) - q;
      const Pack c = invH_ / ra;  // gradFactor's; inf at r = 0, where the factor is 0
      const Pack inner = (l_ * q * (Real(3) * q - Real(2))) * c, outer = (-l_ * t * t) * c;
      const auto outside = (q > Real(1)) | (ra < tiny), near = q <= Real(0.5);
      const Pack zero = Pack{} , factor = outside ? zero : (near ? inner : outer);
      std::memcpy(g + a, &factor, sizeof(Pack));
      if constexpr (kValues) {
        const Pack innerW = k_ * (Real(6) * q * q * q - Real(6) * q * q + Real(1)), outerW = k_ * Real(2) * t * t * t;
        const Pack value = q > Real(1) ? zero : (near ? innerW : outerW);
        std::memcpy(w + a, &value, sizeof(Pack));
      }
    }
#endif
    for (; a < n; ++a) {
      g[a] = gradFactor(r[a]);
      if constexpr (kValues) w[a] = W(r[a]);
    }
  }

  Real h_ = 0, invH_ = 0, k_ = 0, l_ = 0, w0_ = 0;
};

}  // namespace consph
