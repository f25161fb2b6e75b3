#include "Boundary/AddedMass.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

namespace consph {

namespace {
Matrix3r cross(const Vector3r& a) {
  Matrix3r m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}
}  // namespace

BodyIncrement shareWithTouchingFluid(const RigidBody& body, const Vector3r& N, const Vector3r& L, Real dt, Real addedMass,
                                     const std::vector<Index>& touching, const std::vector<Vector3r>& fluidPositions,
                                     const std::vector<Real>& fluidMasses, std::vector<Vector3r>& fluidVelocities) {
  const Matrix3r R = body.rotation();
  const Matrix3r I = R * body.inertiaBody * R.transpose();
  // As applyImpulses: the gyroscopic term of the body's own rotation.
  const Vector3r angular = L - dt * body.w.cross(I * body.w);
  BodyIncrement inc;
  // The touching fluid's mass, first moment and inertia about the body's centre.
  Real mass = 0;
  Vector3r first = Vector3r::Zero();
  Matrix3r inertia = Matrix3r::Zero();
  for (Index i : touching) {
    const Vector3r r = fluidPositions[i] - body.x;
    mass += fluidMasses[i];
    first += fluidMasses[i] * r;
    inertia += fluidMasses[i] * (r.squaredNorm() * Matrix3r::Identity() - r * r.transpose());
  }
  addedMass = std::min(addedMass, mass);
  if (!(addedMass > 0)) {
    inc.dv = N / body.mass;
    inc.dw = I.inverse() * angular;
    return inc;
  }
  // The body takes N / (m + m_a), the added mass acting at its centre as potential flow's does,
  // and I + s I_c for the angular impulse (s = m_a / the touching mass, I_c the touching fluid's
  // inertia about the body's centre).
  const Real share = addedMass / mass;
  inc.dv = N / (body.mass + addedMass);
  inc.dw = (I + share * inertia).inverse() * angular;
  // The rest, P and A about the centre, moves the touching fluid rigidly: dv_i = u + o x r_i
  // with [M, -[S]x; [S]x, I_c] (u, o) = (P, A), the cloud's rigid mass matrix (S its first
  // moment), so that its momentum and angular momentum change by exactly P and A.
  const Vector3r P = N - body.mass * inc.dv;
  const Vector3r A = angular - I * inc.dw;
  // That matrix is singular when the cloud is a point or a line (its inertia about its own
  // centre c = S / mass vanishes along some axis): one or two particles under a body reaching
  // the surface, or a row of them. Solved anyway, a row of three was thrown at 49.5 m/s under a
  // falling 400 kg/m^3 box (issue 15). Such a cloud instead moves with the body by the added
  // share, s (dv + dw x r_i): no particle faster than the body's own increment at its point.
  // Its momentum change is then s (M dv + dw x S), not P: the difference, s dw x S, is given to
  // the cloud as a uniform velocity, so momentum is exact. Angular momentum is not: the cloud
  // gains s (S x dv + I_c dw) - S x (s dw x S) / M instead of A = s I_c dw (one particle: s dv,
  // and s S x dv instead of A), a cloud of one or two particles' small share.
  const Vector3r c = first / mass;
  const Matrix3r ownInertia = inertia - mass * (c.squaredNorm() * Matrix3r::Identity() - c * c.transpose());
  Eigen::SelfAdjointEigenSolver<Matrix3r> eig;
  eig.computeDirect(ownInertia, Eigen::EigenvaluesOnly);
  if (!(eig.eigenvalues()[0] > kMinInertiaRatio * eig.eigenvalues()[2])) {
    const Vector3r uniform = -share * inc.dw.cross(first) / mass;
    for (Index i : touching) fluidVelocities[i] += share * (inc.dv + inc.dw.cross(fluidPositions[i] - body.x)) + uniform;
    return inc;
  }
  Eigen::Matrix<Real, 6, 6> M;
  M.topLeftCorner<3, 3>() = mass * Matrix3r::Identity();
  M.topRightCorner<3, 3>() = -cross(first);
  M.bottomLeftCorner<3, 3>() = cross(first);
  M.bottomRightCorner<3, 3>() = inertia;
  Eigen::Matrix<Real, 6, 1> rhs;
  rhs << P, A;
  const Eigen::Matrix<Real, 6, 1> uo = M.ldlt().solve(rhs);
  const Vector3r u = uo.head<3>(), o = uo.tail<3>();
  for (Index i : touching) fluidVelocities[i] += u + o.cross(fluidPositions[i] - body.x);
  return inc;
}

}  // namespace consph
