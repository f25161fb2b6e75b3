#include "Utilities/MeshClosure.h"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace consph {

std::string MeshClosure::describe() const {
  std::string s;
  auto add = [&](std::size_t n, const char* what) {
    if (n == 0) return;
    if (!s.empty()) s += ", ";
    s += std::to_string(n) + " " + what;
  };
  add(openEdges, openEdges == 1 ? "open edge" : "open edges");
  add(nonManifoldEdges, nonManifoldEdges == 1 ? "edge shared by more than two triangles" : "edges shared by more than two triangles");
  add(flippedEdges, flippedEdges == 1 ? "edge between triangles of opposite orientation"
                                      : "edges between triangles of opposite orientation");
  return s.empty() ? "closed" : s;
}

MeshClosure checkClosure(const TriangleMesh& mesh) {
  // Weld: one id per distinct position.
  std::map<std::array<Real, 3>, Index> idOf;
  std::vector<Index> id(mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vector3r& p = mesh.vertices[v];
    id[v] = idOf.try_emplace({p[0], p[1], p[2]}, Index(idOf.size())).first->second;
  }
  // Per undirected edge (lo, hi): how often it is used from lo to hi and from hi to lo. A closed,
  // consistently oriented surface uses every edge exactly once each way.
  std::map<std::pair<Index, Index>, std::pair<int, int>> uses;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const Index a = id[t[e]], b = id[t[(e + 1) % 3]];
      if (a == b) continue;  // degenerate triangle edge
      auto& u = uses[{std::min(a, b), std::max(a, b)}];
      (a < b ? u.first : u.second) += 1;
    }
  MeshClosure c;
  for (const auto& [edge, u] : uses) {
    const int n = u.first + u.second;
    if (n == 1) ++c.openEdges;
    else if (n > 2) ++c.nonManifoldEdges;
    else if (u.first != 1) ++c.flippedEdges;
  }
  return c;
}

}  // namespace consph
