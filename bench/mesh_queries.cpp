// Timing of the mesh queries behind dynamic-body sampling and dropping fluid inside bodies, on
// spheres of 20 k / 200 k / 1 M triangles: with the hierarchy (Utilities/TriangleBvh.h) as the
// code runs now, and the brute force it replaced (every triangle per query), timed on a subset
// of the queries and scaled to all of them (the full brute force of 1 M triangles takes hours).
//
//   build/bench/mesh_queries [max_triangles]      (prints a Markdown table for bench/RESULTS.md)
#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include "Boundary/MeshSampling.h"
#include "Utilities/Log.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/MassProperties.h"
#include "Utilities/Timer.h"
#include "Utilities/TriangleBvh.h"
#include "Utilities/TriangleMesh.h"

using namespace consph;

namespace {

// What the sampler asked per lattice point before the hierarchy: the first hit along the
// inward normal over every triangle, and whether any triangle lies nearer than the offset
// (bounding spheres first, as the old code did).
double bruteSamplingSecondsPerPoint(const TriangleMesh& mesh, Real offset, int queries) {
  std::vector<Vector3r> centres(mesh.triangles.size());
  std::vector<Real> radii(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    centres[t] = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3;
    radii[t] = (mesh.vertices[tri[0]] - centres[t]).norm();
  }
  Timer timer;
  double sink = 0;
  for (int q = 0; q < queries; ++q) {
    const std::size_t owner = std::size_t(q) * 7919 % mesh.triangles.size();
    const auto& tri = mesh.triangles[owner];
    const Vector3r a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
    const Vector3r p = (a + b + c) / 3, dir = -(b - a).cross(c - a).normalized();
    Real best = std::numeric_limits<Real>::infinity();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (t == owner) continue;
      const auto& u = mesh.triangles[t];
      best = std::min(best, rayTriangleDistance(p, dir, mesh.vertices[u[0]], mesh.vertices[u[1]], mesh.vertices[u[2]]));
    }
    const Vector3r x = p + std::min(offset, best / 2) * dir;
    bool near = false;
    for (std::size_t t = 0; t < mesh.triangles.size() && !near; ++t) {
      if ((x - centres[t]).norm() - radii[t] >= Real(0.98) * offset) continue;
      const auto& u = mesh.triangles[t];
      near = (x - closestPointOnTriangle(x, mesh.vertices[u[0]], mesh.vertices[u[1]], mesh.vertices[u[2]])).norm() < Real(0.98) * offset;
    }
    sink += double(best) + near;
  }
  if (sink == -1) std::puts("");  // keeps the loop from being optimised away
  return timer.seconds() / queries;
}

}  // namespace

int main(int argc, char** argv) {
  const long maxTriangles = argc > 1 ? std::atol(argv[1]) : 1000000;
  const Real radius = Real(0.5), spacing = Real(0.02), offset = Real(0.015);
  const int points = 100000;
  std::printf("machine threads: %d, Real: %s; sphere r = %.2f m, sampling spacing %.3f m, layer %.3f m inside; %d points in its box\n\n",
              omp_get_max_threads(), sizeof(Real) == 8 ? "double" : "float", double(radius), double(spacing), double(offset), points);
  std::printf("| triangles | lattice samples | BVH build s | sampling s (BVH) | sampling s (brute, est.) | point-in-mesh s (BVH) | point-in-mesh s (brute, est.) |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|\n");
  const int grids[3][2] = {{200, 51}, {400, 251}, {1000, 501}};  // 2 slices (stacks - 1) triangles
  for (const auto& g : grids) {
    const TriangleMesh sphere = makeSphereMesh(Vector3r::Zero(), radius, g[0], g[1]);
    if (long(sphere.triangles.size()) > maxTriangles) break;
    Timer build;
    const TriangleBvh bvh(sphere);
    const double buildSeconds = build.seconds();
    // Dynamic-body sampling as the Akinci boundary does it (layer moved into the body).
    Timer sampling;
    // Progress lines (past 2 s) go to stderr, as the CLI's would.
    const std::vector<Vector3r> samples = sampleMeshSurface(sphere, spacing, -offset, stderrLogSink(false), "the sphere");
    const double samplingSeconds = sampling.seconds();
    // Lattice points the sampler moved: 3 per triangle here (every triangle is shorter than a spacing).
    std::size_t lattice = 0;
    for (const auto& tri : sphere.triangles) {
      const Real longest = std::max({(sphere.vertices[tri[1]] - sphere.vertices[tri[0]]).norm(),
                                     (sphere.vertices[tri[2]] - sphere.vertices[tri[1]]).norm(),
                                     (sphere.vertices[tri[0]] - sphere.vertices[tri[2]]).norm()});
      const std::size_t n = std::max<std::size_t>(1, std::size_t(std::ceil(double(longest / spacing))));
      lattice += (n + 1) * (n + 2) / 2;
    }
    const double bruteSampling = bruteSamplingSecondsPerPoint(sphere, offset, 200) * double(lattice) / omp_get_max_threads();
    // Point-in-mesh (fluid dropped inside a body): random points in the bounding box.
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-0.55, 0.55);
    std::vector<Vector3r> queries(points);
    for (auto& q : queries) q = Vector3r(Real(u(rng)), Real(u(rng)), Real(u(rng)));
    std::vector<char> inside(points);
    Timer pim;
    parallelForDynamic(std::size_t(points), [&](std::size_t i) { inside[i] = bvh.windingNumber(queries[i]) > Real(0.5); });
    const double pimSeconds = pim.seconds();
    Timer brute;
    const int bruteQueries = 50;
    int disagreements = 0;
    for (int i = 0; i < bruteQueries; ++i) disagreements += (windingNumber(sphere, queries[i]) > Real(0.5)) != bool(inside[i]);
    const double brutePim = brute.seconds() / bruteQueries * points / omp_get_max_threads();
    std::printf("| %zu | %zu | %.2f | %.2f | %.0f | %.3f | %.1f |%s\n", sphere.triangles.size(), lattice, buildSeconds, samplingSeconds,
                bruteSampling, pimSeconds, brutePim, disagreements ? " (inside/outside disagreed with the brute force!)" : "");
    std::fflush(stdout);
    if (samples.empty()) return 1;
  }
  return 0;
}
