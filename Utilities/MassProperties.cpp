#include "Utilities/MassProperties.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace consph {

namespace {
// Eberly's subexpressions of the polynomial integrals over one triangle along one axis.
struct Sub {
  double f1, f2, f3, g0, g1, g2;
};
Sub subexpressions(double w0, double w1, double w2) {
  Sub s;
  const double t0 = w0 + w1, t1 = w0 * w0, t2 = t1 + w1 * t0;
  s.f1 = t0 + w2;
  s.f2 = t2 + w2 * s.f1;
  s.f3 = w0 * t1 + w1 * t2 + w2 * s.f2;
  s.g0 = s.f2 + w0 * (s.f1 + w0);
  s.g1 = s.f2 + w1 * (s.f1 + w1);
  s.g2 = s.f2 + w2 * (s.f1 + w2);
  return s;
}
}  // namespace

MassProperties computeMassProperties(const TriangleMesh& mesh) {
  // Integrate about the vertex centroid (in double): far from the origin the products of large
  // coordinates would cancel catastrophically.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (auto& v : mesh.vertices) origin += v.cast<double>();
  if (!mesh.vertices.empty()) origin /= double(mesh.vertices.size());
  double in[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx
  for (auto& t : mesh.triangles) {
    const Eigen::Vector3d p0 = mesh.vertices[t[0]].cast<double>() - origin;
    const Eigen::Vector3d p1 = mesh.vertices[t[1]].cast<double>() - origin;
    const Eigen::Vector3d p2 = mesh.vertices[t[2]].cast<double>() - origin;
    const Eigen::Vector3d d = (p1 - p0).cross(p2 - p0);  // 2 area times the outward normal
    const Sub x = subexpressions(p0[0], p1[0], p2[0]);
    const Sub y = subexpressions(p0[1], p1[1], p2[1]);
    const Sub z = subexpressions(p0[2], p1[2], p2[2]);
    in[0] += d[0] * x.f1;
    in[1] += d[0] * x.f2;
    in[2] += d[1] * y.f2;
    in[3] += d[2] * z.f2;
    in[4] += d[0] * x.f3;
    in[5] += d[1] * y.f3;
    in[6] += d[2] * z.f3;
    in[7] += d[0] * (p0[1] * x.g0 + p1[1] * x.g1 + p2[1] * x.g2);
    in[8] += d[1] * (p0[2] * y.g0 + p1[2] * y.g1 + p2[2] * y.g2);
    in[9] += d[2] * (p0[0] * z.g0 + p1[0] * z.g1 + p2[0] * z.g2);
  }
  const double scale[10] = {1. / 6, 1. / 24, 1. / 24, 1. / 24, 1. / 60, 1. / 60, 1. / 60, 1. / 120, 1. / 120, 1. / 120};
  for (int i = 0; i < 10; ++i) in[i] *= scale[i];
  MassProperties m;
  const double V = in[0];
  m.volume = Real(V);
  if (V == 0) return m;
  const Eigen::Vector3d c(in[1] / V, in[2] / V, in[3] / V);
  // Inertia about the centre of mass (parallel-axis theorem on the second moments).
  Eigen::Matrix3d I;
  I(0, 0) = in[5] + in[6] - V * (c[1] * c[1] + c[2] * c[2]);
  I(1, 1) = in[4] + in[6] - V * (c[2] * c[2] + c[0] * c[0]);
  I(2, 2) = in[4] + in[5] - V * (c[0] * c[0] + c[1] * c[1]);
  I(0, 1) = I(1, 0) = -(in[7] - V * c[0] * c[1]);
  I(1, 2) = I(2, 1) = -(in[8] - V * c[1] * c[2]);
  I(0, 2) = I(2, 0) = -(in[9] - V * c[2] * c[0]);
  m.centerOfMass = (c + origin).cast<Real>();
  m.inertiaPerDensity = I.cast<Real>();
  return m;
}

Real windingNumber(const TriangleMesh& mesh, const Vector3r& p) {
  double omega = 0;
  for (auto& t : mesh.triangles) omega += triangleSolidAngle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
  return Real(omega / (4 * std::numbers::pi));
}

}  // namespace consph
