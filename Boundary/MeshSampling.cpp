#include "Boundary/MeshSampling.h"

#include <cmath>
#include <unordered_map>

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

std::vector<Vector3r> sampleMeshSurface(const TriangleMesh& mesh, Real spacing) {
  std::vector<Vector3r> points;
  for (auto& t : mesh.triangles) {
    const Vector3r a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    const Real longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, int(std::ceil(longest / spacing)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) points.push_back(a + (b - a) * (Real(i) / n) + (c - a) * (Real(j) / n));
  }
  return thinPoints(points, Real(0.6) * spacing);
}

std::vector<Vector3r> sampleBoxSurface(const Vector3r& lo, const Vector3r& hi, Real spacing) {
  std::vector<Vector3r> points;
  int n[3];
  for (int d = 0; d < 3; ++d) n[d] = std::max(1, int(std::ceil((hi[d] - lo[d]) / spacing)));
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

}  // namespace consph
