// Fixed-radius neighbour search on a uniform grid with compact hashing (cell size = support
// radius, 27 cells per query), built in parallel without locks. Results are flat CSR arrays,
// built once per step and reused by every solver iteration; each entry also caches the kernel
// gradient, since every Jacobi iteration needs it and recomputing it costs a square root.
#pragma once
#include <array>
#include <vector>

#include "Simulation/Common.h"
#include "Simulation/Kernel.h"

namespace consph {

// Neighbours of each query particle i: indices[offsets[i] .. offsets[i+1]).
struct NeighborLists {
  std::vector<Index> offsets;    // (n + 1)
  std::vector<Index> indices;    // (number of pairs)
  std::vector<Vector3r> gradW;   // (number of pairs) grad W(x_i - x_j)
  // Per-thread scratch of the build, kept so that steady-state steps allocate nothing.
  std::vector<std::vector<Index>> scratchIndices;
  std::vector<std::vector<Vector3r>> scratchGradW;
  std::vector<std::vector<Real>> scratchCandidates;  // per thread: SoA x, y, z of one cell's candidates
  std::vector<std::vector<Index>> scratchCandidateIds;

  std::size_t queryCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  Index begin(std::size_t i) const { return offsets[i]; }
  Index end(std::size_t i) const { return offsets[i + 1]; }
  Index count(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  std::size_t pairCount() const { return indices.size(); }
};

// A hashed grid over one point set.
class PointGrid {
 public:
  void build(const Vector3r* points, std::size_t n, Real cellSize);
  std::size_t size() const { return sortedIndex_.size(); }

  // Calls f(begin, end) for the ranges of sorted entries (sortedPoints/sortedIndices) of the
  // distinct buckets of the 27 cells around p; candidates, to be filtered by distance.
  template <class F>
  void forEachCandidateRange(const Vector3r& p, F&& f) const {
    if (sortedIndex_.empty()) return;
    const int cx = cellCoord(p[0]), cy = cellCoord(p[1]), cz = cellCoord(p[2]);
    Index buckets[27];
    int nb = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const Index b = bucket(cx + dx, cy + dy, cz + dz);
          bool seen = false;  // two cells hashing to one bucket must not report a point twice
          for (int k = 0; k < nb; ++k) seen |= (buckets[k] == b);
          if (!seen) buckets[nb++] = b;
        }
    for (int k = 0; k < nb; ++k)
      if (cellStart_[buckets[k]] < cellStart_[buckets[k] + 1]) f(cellStart_[buckets[k]], cellStart_[buckets[k] + 1]);
  }

  // Calls f(j, x_j) for every point j within `radius` (<= cell size) of p.
  template <class F>
  void forEachNeighbor(const Vector3r& p, Real radius, F&& f) const {
    const Real r2 = radius * radius;
    forEachCandidateRange(p, [&](Index begin, Index end) {
      for (Index s = begin; s < end; ++s) {
        const Vector3r& q = sortedPoints_[s];
        if ((p - q).squaredNorm() <= r2) f(sortedIndex_[s], q);
      }
    });
  }

  // The cell of p: queries in one cell share their candidates.
  std::array<int, 3> cellOf(const Vector3r& p) const { return {cellCoord(p[0]), cellCoord(p[1]), cellCoord(p[2])}; }
  const Vector3r* sortedPoints() const { return sortedPoints_.data(); }
  const Index* sortedIndices() const { return sortedIndex_.data(); }

 private:
  int cellCoord(Real v) const { return static_cast<int>(std::floor(v * invCellSize_)); }
  Index bucket(int x, int y, int z) const {
    const std::uint32_t h = (std::uint32_t(x) * 73856093u) ^ (std::uint32_t(y) * 19349663u) ^ (std::uint32_t(z) * 83492791u);
    return h & tableMask_;
  }

  Real invCellSize_ = 1;
  Index tableMask_ = 0;
  std::vector<Index> cellStart_;       // (table size + 1)
  std::vector<Index> sortedIndex_;     // (n) point index in bucket order
  std::vector<Vector3r> sortedPoints_; // (n) positions in bucket order, for contiguous reads
  std::vector<Index> keys_;            // (n) scratch
};

// Builds neighbour lists of `queries` against the points of `grid` within the kernel's support
// radius; `excludeSelf` drops j == i (query set == grid set).
// The grid keeps its own copy of the points it was built over, for the cached kernel gradients.
void buildNeighborLists(const PointGrid& grid, const Vector3r* queries, std::size_t nQueries,
                        const CubicSplineKernel& kernel, bool excludeSelf, NeighborLists& out);

// A permutation that orders the points along a Z-order (Morton) curve of cells of `cellSize`,
// so that neighbours in space are neighbours in memory.
std::vector<Index> zOrderPermutation(const Vector3r* points, std::size_t n, Real cellSize);

// Lists reversed: for every point j of the target set (nTargets), the queries i listing it.
// gradW entries are grad W(x_j - x_i) = -grad W(x_i - x_j).
void transposeNeighborLists(const NeighborLists& lists, std::size_t nTargets, NeighborLists& out);

}  // namespace consph
