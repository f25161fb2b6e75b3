#include "Boundary/RestLayer.h"

#include <cmath>

namespace consph {

Real halfLatticeDensity(const CubicSplineKernel& kernel, Real d) {
  const int n = int(std::ceil(kernel.supportRadius() / d)) + 1;
  Real density = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = 0; k <= n; ++k) density += d * d * d * kernel.W(Vector3r(i * d, j * d, k * d));
  return density;
}

Real restDistance(Real fluidShare, Real h, const std::function<Real(Real)>& boundaryShare) {
  if (fluidShare + boundaryShare(0) <= 1) return 0;
  if (fluidShare >= 1) return h;
  Real lo = 0, hi = h;
  for (int it = 0; it < 60; ++it) {
    const Real mid = Real(0.5) * (lo + hi);
    (fluidShare + boundaryShare(mid) > 1 ? lo : hi) = mid;
  }
  return Real(0.5) * (lo + hi);
}

}  // namespace consph
