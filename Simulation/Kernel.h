// Cubic spline kernel in 3D with support radius h (SPlisHSPlasH convention: h = 4 r).
// W(q) = k (6q^3 - 6q^2 + 1) for q <= 1/2, 2k (1 - q)^3 for 1/2 < q <= 1, k = 8 / (pi h^3).
#pragma once
#include <cmath>
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
  // per pair to stream instead of 12, and the same bits as this function.
  Real gradFactor(Real r) const {
    const Real q = r * invH_;
    if (q > Real(1) || r < Real(1e-9) * h_) return Real(0);
    const Real c = invH_ / r;  // |grad q| / r
    if (q <= Real(0.5)) return (l_ * q * (Real(3) * q - Real(2))) * c;
    const Real t = Real(1) - q;
    return (-l_ * t * t) * c;
  }
  Vector3r gradW(const Vector3r& x) const { return x * gradFactor(x.norm()); }

 private:
  Real h_ = 0, invH_ = 0, k_ = 0, l_ = 0, w0_ = 0;
};

}  // namespace consph
