// Matrix-free preconditioned conjugate gradient for a symmetric positive definite system whose
// unknowns are one Vector3r per particle (e.g. implicit viscosity). The matrix and the
// preconditioner are callables that write A x (resp. P^-1 r) into their output in one parallel
// particle loop, so no matrix is ever stored. Stops when |b - A x| <= tolerance (an absolute
// residual norm the caller chooses) or after maxIterations.
#pragma once
#include <cmath>
#include <vector>

#include "Utilities/ParallelFor.h"
#include "Utilities/Types.h"

namespace consph {

struct ConjugateGradientResult {
  int iterations = 0;
  Real residual = 0;  // |b - A x| at exit
  bool converged = false;
};

// Scratch vectors, kept by the caller between solves (no allocation once sized).
struct ConjugateGradientWorkspace {
  std::vector<Vector3r> r, z, p, ap;
};

namespace cg_detail {
inline Real dot(const std::vector<Vector3r>& a, const std::vector<Vector3r>& b) {
  return parallelSum<Real>(a.size(), [&](std::size_t i) { return a[i].dot(b[i]); });
}
}  // namespace cg_detail

// applyA(x, out): out = A x; applyPreconditioner(r, out): out = P^-1 r. x holds the initial guess.
template <class ApplyA, class ApplyP>
ConjugateGradientResult solveConjugateGradient(ApplyA&& applyA, ApplyP&& applyPreconditioner,
                                               const std::vector<Vector3r>& b, std::vector<Vector3r>& x,
                                               Real tolerance, int maxIterations, ConjugateGradientWorkspace& ws) {
  using cg_detail::dot;
  const std::size_t n = b.size();
  ws.r.resize(b.size());
  ws.z.resize(b.size());
  ws.p.resize(b.size());
  ws.ap.resize(b.size());
  ConjugateGradientResult result;
  const Real threshold2 = tolerance * tolerance;
  applyA(x, ws.ap);
  parallelFor(n, [&](std::size_t i) { ws.r[i] = b[i] - ws.ap[i]; });
  Real r2 = dot(ws.r, ws.r);
  if (r2 <= threshold2) {
    result.residual = std::sqrt(r2);
    result.converged = true;
    return result;
  }
  applyPreconditioner(ws.r, ws.z);
  ws.p = ws.z;
  Real rz = dot(ws.r, ws.z);
  while (result.iterations < maxIterations) {
    applyA(ws.p, ws.ap);
    const Real alpha = rz / dot(ws.p, ws.ap);
    parallelFor(n, [&](std::size_t i) {
      x[i] += alpha * ws.p[i];
      ws.r[i] -= alpha * ws.ap[i];
    });
    ++result.iterations;
    r2 = dot(ws.r, ws.r);
    if (r2 <= threshold2) break;
    applyPreconditioner(ws.r, ws.z);
    const Real rzNew = dot(ws.r, ws.z);
    const Real beta = rzNew / rz;
    rz = rzNew;
    parallelFor(n, [&](std::size_t i) { ws.p[i] = ws.z[i] + beta * ws.p[i]; });
  }
  result.residual = std::sqrt(r2);
  result.converged = r2 <= threshold2;
  return result;
}

}  // namespace consph
