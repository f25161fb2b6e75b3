#include "Boundary/MeshSampling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "Simulation/ResourceEstimate.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/ProgressLog.h"
#include "Utilities/TriangleBvh.h"

namespace consph {

std::vector<Vector3r> thinPoints(const std::vector<Vector3r>& points, Real minDistance) {
  // Serial: it runs once at start-up, and the order decides which point of a pair is kept.
  struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const {
      return std::size_t(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
    }
  };
  std::unordered_map<std::array<long long, 3>, std::vector<Index>, KeyHash> cells;
  std::vector<Vector3r> kept;
  const Real inv = Real(1) / minDistance, d2 = minDistance * minDistance;
  for (const Vector3r& p : points) {
    const std::array<long long, 3> c = {(long long)std::floor(p[0] * inv), (long long)std::floor(p[1] * inv),
                                        (long long)std::floor(p[2] * inv)};
    bool near = false;
    for (int dx = -1; dx <= 1 && !near; ++dx)
      for (int dy = -1; dy <= 1 && !near; ++dy)
        for (int dz = -1; dz <= 1 && !near; ++dz) {
          auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells.end()) continue;
          for (Index k : it->second)
            if ((kept[k] - p).squaredNorm() < d2) {
              near = true;
              break;
            }
        }
    if (near) continue;
    cells[c].push_back(Index(kept.size()));
    kept.push_back(p);
  }
  return kept;
}

namespace {

// body(i) for every i in [0, n), in parallel, in chunks with a progress report after each.
template <class Body>
void parallelForWithProgress(std::size_t n, std::size_t doneBefore, ProgressLog& progress, const Body& body) {
  const std::size_t chunk = std::max<std::size_t>(16384, n / 64);
  for (std::size_t begin = 0; begin < n; begin += chunk) {
    const std::size_t end = std::min(n, begin + chunk);
    parallelForDynamic(end - begin, [&](std::size_t i) { body(begin + i); });
    progress.report(doneBefore + end);
  }
}

void dropPointsNearerThan(const TriangleBvh& surface, const std::vector<Real>& distances, std::vector<Vector3r>& points,
                          std::size_t doneBefore, ProgressLog& progress) {
  // Moved faces overlap where the offset side is concave (a body's edges, moved inwards): their
  // points beyond the overlap sit closer to the neighbouring face than they were moved.
  std::vector<char> keep(points.size(), 1);
  parallelForWithProgress(points.size(), doneBefore, progress, [&](std::size_t i) {
    keep[i] = !surface.anyTriangleCloserThan(points[i], Real(0.98) * distances[i]);
  });
  std::size_t n = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (keep[i]) points[n++] = points[i];
  points.resize(n);
}

}  // namespace

std::vector<Vector3r> sampleMeshSurface(const TriangleMesh& mesh, Real spacing, Real normalOffset, const LogSink& log,
                                        const std::string& name) {
  // The lattice on every triangle, and the triangle each point belongs to.
  std::vector<Vector3r> points;
  std::vector<std::size_t> owners;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vector3r a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
    const Real longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, checkedCount(std::ceil(double(longest) / double(spacing)), "surface sampling of a triangle"));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        points.push_back(a + (b - a) * (Real(i) / n) + (c - a) * (Real(j) / n));
        owners.push_back(t);
      }
  }
  if (normalOffset == 0) return thinPoints(points, Real(0.6) * spacing);
  // Each point moved along its triangle's normal; the rays and the overlap test ask the
  // hierarchy (O(log n) each) instead of every triangle.
  const TriangleBvh surface(mesh);
  const std::size_t lattice = points.size();
  ProgressLog progress(log, "sampling " + (name.empty() ? std::string("a mesh") : name) + " (" + std::to_string(mesh.triangles.size()) +
                                " triangles, " + std::to_string(lattice) + " samples)",
                       2 * lattice);
  std::vector<Real> shifts(lattice, 0);  // how far each point was moved
  parallelForWithProgress(lattice, 0, progress, [&](std::size_t k) {
    const auto& tri = mesh.triangles[owners[k]];
    const Vector3r a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
    const Vector3r normal = (b - a).cross(c - a).normalized();
    if (!normal.allFinite()) return;
    const Vector3r dir = (normalOffset > 0 ? 1 : -1) * normal;
    // A part thinner than twice the offset (a paddle, a plate) keeps its layer at its
    // mid-plane instead of pushing it out of the other side; farther surfaces do not matter.
    const Real reach = 2 * std::abs(normalOffset);
    shifts[k] = std::min(std::abs(normalOffset), Real(0.5) * surface.firstHitDistance(points[k], dir, owners[k], reach));
    points[k] += shifts[k] * dir;
  });
  addCreaseSamples(mesh, spacing, normalOffset, points);
  shifts.resize(points.size(), std::abs(normalOffset));
  progress.setTotal(lattice + points.size());
  dropPointsNearerThan(surface, shifts, points, lattice, progress);
  progress.finish();
  return thinPoints(points, Real(0.6) * spacing);
}

void addCreaseSamples(const TriangleMesh& mesh, Real spacing, Real normalOffset, std::vector<Vector3r>& points) {
  // Triangles moved apart along their normals leave a strip open along every crease where the
  // offset side is convex (a container's edges, moved outwards) and a hole at every corner:
  // close them with arcs of radius |offset| about the edge and one point per corner.
  struct EdgeFaces {
    Index a, b;
    int faces[2] = {-1, -1};
  };
  struct PairHash {
    std::size_t operator()(const std::pair<Index, Index>& e) const { return std::size_t(e.first) * 1000003u ^ std::size_t(e.second); }
  };
  std::unordered_map<std::pair<Index, Index>, EdgeFaces, PairHash> edges;
  std::vector<Vector3r> normals(mesh.triangles.size()), centroids(mesh.triangles.size());
  std::vector<Vector3r> vertexNormals(mesh.vertices.size(), Vector3r::Zero());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vector3r& a = mesh.vertices[tri[0]];
    const Vector3r& b = mesh.vertices[tri[1]];
    const Vector3r& c = mesh.vertices[tri[2]];
    const Vector3r n = (b - a).cross(c - a);
    normals[t] = n.norm() > 0 ? Vector3r(n.normalized()) : Vector3r::Zero();
    centroids[t] = (a + b + c) / 3;
    for (int e = 0; e < 3; ++e) {
      vertexNormals[tri[e]] += normals[t] * std::acos(std::clamp<Real>(
          (mesh.vertices[tri[(e + 1) % 3]] - mesh.vertices[tri[e]]).normalized().dot((mesh.vertices[tri[(e + 2) % 3]] - mesh.vertices[tri[e]]).normalized()), -1, 1));
      const Index u = std::min(tri[e], tri[(e + 1) % 3]), v = std::max(tri[e], tri[(e + 1) % 3]);
      EdgeFaces& ef = edges[{u, v}];
      ef.a = u;
      ef.b = v;
      (ef.faces[0] < 0 ? ef.faces[0] : ef.faces[1]) = int(t);
    }
  }
  const Real radius = std::abs(normalOffset);
  for (auto& [key, ef] : edges) {
    if (ef.faces[1] < 0) continue;
    const Vector3r n1 = normals[ef.faces[0]], n2 = normals[ef.faces[1]];
    const Real angle = std::acos(std::clamp<Real>(n1.dot(n2), -1, 1));
    if (angle < Real(0.05)) continue;  // flat: the faces' own samples meet
    const bool convex = (centroids[ef.faces[1]] - centroids[ef.faces[0]]).dot(n1) < 0;
    if (convex != (normalOffset > 0)) continue;  // the moved faces overlap here, no gap
    const Vector3r a = mesh.vertices[ef.a], b = mesh.vertices[ef.b];
    const Real sign = normalOffset > 0 ? 1 : -1;
    const int along = std::max(1, checkedCount(std::ceil(double((b - a).norm()) / double(spacing)), "surface sampling of a crease"));
    const int around = std::max(1, checkedCount(std::ceil(double(angle * radius) / double(spacing)), "surface sampling of a crease"));
    for (int i = 0; i <= along; ++i)
      for (int j = 1; j < around; ++j) {
        const Real w = Real(j) / around;
        const Vector3r n = ((1 - w) * n1 + w * n2).normalized();
        points.push_back(a + (b - a) * (Real(i) / along) + sign * radius * n);
      }
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (vertexNormals[v].norm() > 0) points.push_back(mesh.vertices[v] + normalOffset * vertexNormals[v].normalized());
}

std::vector<Vector3r> sampleBoxSurface(const Vector3r& lo, const Vector3r& hi, Real spacing) {
  std::vector<Vector3r> points;
  int n[3];
  for (int d = 0; d < 3; ++d) n[d] = std::max(1, checkedCount(std::ceil(double(hi[d] - lo[d]) / double(spacing)), "surface sampling of a box"));
  auto at = [&](int d, int i) { return lo[d] + (hi[d] - lo[d]) * Real(i) / n[d]; };
  for (int i = 0; i <= n[0]; ++i)
    for (int j = 0; j <= n[1]; ++j) {
      const bool interior = i > 0 && i < n[0] && j > 0 && j < n[1];
      if (interior) {  // only the two z faces
        points.emplace_back(at(0, i), at(1, j), lo[2]);
        points.emplace_back(at(0, i), at(1, j), hi[2]);
      } else {
        for (int k = 0; k <= n[2]; ++k) points.emplace_back(at(0, i), at(1, j), at(2, k));
      }
    }
  return points;
}

void dropPointsNearerThan(const TriangleMesh& mesh, const std::vector<Real>& distances, std::vector<Vector3r>& points) {
  ProgressLog silent({}, "", points.size());
  dropPointsNearerThan(TriangleBvh(mesh), distances, points, 0, silent);
}

}  // namespace consph
