#include "Utilities/TriangleMesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Geometry>
#include <assimp/Importer.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "Utilities/Error.h"

namespace consph {

Real TriangleMesh::area() const {
  Real a = 0;
  for (auto& t : triangles) a += Real(0.5) * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
  return a;
}

void TriangleMesh::boundingBox(Vector3r& lo, Vector3r& hi) const {
  lo = Vector3r::Constant(std::numeric_limits<Real>::max());
  hi = -lo;
  for (auto& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
}

TriangleMesh makeBoxMesh(const Vector3r& lo, const Vector3r& hi, bool inverted) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]);
  // Outward-facing quads (counter-clockwise seen from outside).
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (auto& q : quads) {
    if (!inverted) {
      m.triangles.push_back({Index(q[0]), Index(q[1]), Index(q[2])});
      m.triangles.push_back({Index(q[0]), Index(q[2]), Index(q[3])});
    } else {
      m.triangles.push_back({Index(q[0]), Index(q[2]), Index(q[1])});
      m.triangles.push_back({Index(q[0]), Index(q[3]), Index(q[2])});
    }
  }
  return m;
}

TriangleMesh makeSphereMesh(const Vector3r& centre, Real radius, int slices, int stacks) {
  // Latitude-longitude grid: one vertex per pole, `slices` per inner ring, shared between
  // neighbouring triangles (closed, two-manifold).
  TriangleMesh m;
  slices = std::max(slices, 3);
  stacks = std::max(stacks, 2);
  const double pi = 3.14159265358979323846;
  m.vertices.push_back(centre + Vector3r(0, 0, radius));
  for (int i = 1; i < stacks; ++i) {
    const double theta = pi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2 * pi * j / slices;
      m.vertices.push_back(centre + radius * Vector3r(Real(std::sin(theta) * std::cos(phi)), Real(std::sin(theta) * std::sin(phi)),
                                                      Real(std::cos(theta))));
    }
  }
  const Index south = Index(m.vertices.size());
  m.vertices.push_back(centre - Vector3r(0, 0, radius));
  auto ring = [&](int i, int j) { return Index(1 + (i - 1) * slices + (j % slices)); };  // i = 1 .. stacks - 1
  for (int j = 0; j < slices; ++j) {
    m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
    m.triangles.push_back({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
    for (int i = 1; i + 1 < stacks; ++i) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  return m;
}

TriangleMesh loadMesh(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError("mesh file '" + path + "' does not exist");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (!scene || !scene->mRootNode) throw InputError("mesh file '" + path + "' could not be read: " + importer.GetErrorString());
  TriangleMesh m;
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* mesh = scene->mMeshes[mi];
    const Index base = Index(m.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      m.vertices.emplace_back(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z);
      // An inf or NaN vertex poisons every bounding box and grid built from the mesh.
      if (!m.vertices.back().allFinite())
        throw InputError("mesh file '" + path + "': vertex " + std::to_string(m.vertices.size()) + " is not finite (inf or NaN)");
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      m.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  if (m.triangles.empty()) throw InputError("mesh file '" + path + "' contains no triangles");
  return m;
}

void transformMesh(TriangleMesh& mesh, const Vector3r& scale, const Vector3r& axis, Real angle, const Vector3r& translation) {
  Matrix3r R = Matrix3r::Identity();
  // stableNormalized: normalized() overflows to the zero vector on [1e200, 0, 0].
  if (!axis.isZero(0)) R = Eigen::AngleAxis<Real>(angle, axis.stableNormalized()).toRotationMatrix();
  for (auto& v : mesh.vertices) v = R * v.cwiseProduct(scale) + translation;
  // A mirroring scale flips the orientation; keep the normals pointing the same way.
  if (scale.prod() < 0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
}

Vector3r closestPointOnTriangle(const Vector3r& p, const Vector3r& a, const Vector3r& b, const Vector3r& c, bool* onFace) {
  if (onFace) *onFace = false;
  // Voronoi regions of the vertices, edges and face (C. Ericson, Real-Time Collision Detection, 5.1.5).
  const Vector3r ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vector3r bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vector3r cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  if (onFace) *onFace = true;
  const Real denom = Real(1) / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

Real rayTriangleDistance(const Vector3r& o, const Vector3r& dir, const Vector3r& a, const Vector3r& b, const Vector3r& c) {
  constexpr Real kMiss = std::numeric_limits<Real>::infinity();
  const Vector3r e1 = b - a, e2 = c - a;
  const Vector3r pv = dir.cross(e2);
  const Real det = e1.dot(pv);
  if (std::abs(det) < Real(1e-14)) return kMiss;
  const Vector3r tv = o - a;
  const Real u = tv.dot(pv) / det;
  if (u < 0 || u > 1) return kMiss;
  const Vector3r qv = tv.cross(e1);
  const Real v = dir.dot(qv) / det;
  if (v < 0 || u + v > 1) return kMiss;
  const Real dist = e2.dot(qv) / det;
  return dist > Real(1e-9) ? dist : kMiss;
}

double triangleSolidAngle(const Vector3r& p, const Vector3r& a, const Vector3r& b, const Vector3r& c) {
  // In double: a winding number sums many of these, and float atan2 near 0/0 is noisy.
  const Eigen::Vector3d u = (a - p).cast<double>(), v = (b - p).cast<double>(), w = (c - p).cast<double>();
  const double lu = u.norm(), lv = v.norm(), lw = w.norm();
  const double num = u.dot(v.cross(w));
  const double den = lu * lv * lw + u.dot(v) * lw + v.dot(w) * lu + w.dot(u) * lv;
  return 2 * std::atan2(num, den);
}

}  // namespace consph
