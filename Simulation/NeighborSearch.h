// Fixed-radius neighbour search on a dense uniform grid over the points' bounding box (cell
// size = support radius, 27 cells per query visited as 9 contiguous rows), built in parallel
// without locks. Results are flat CSR arrays,
// built once per step and reused by every solver iteration; each entry also caches the kernel
// gradient (as a vector, or as the scalar factor of x_ij: PairGradients), since every Jacobi
// iteration needs it and recomputing it costs a square root.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "Simulation/Common.h"
#include "Simulation/Kernel.h"
#include "Utilities/ParallelFor.h"

namespace consph {

// How a list holds each pair's kernel gradient grad W(x_i - x_j).
enum class PairGradients {
  Vectors,  // gradW[e]: the boundary lists (a volume map's gradient is not along x_ij)
  Factors,  // gradFactors[e], grad W = x_ij gradFactors[e]: the fluid's own lists. Their loops
            // read x_j anyway or find it in cache (Z-sorted positions), and stream 8 bytes per
            // pair instead of 16 in float (bench/RESULTS.md, "Pair gradients as factors").
};

// Neighbours of each query particle i: indices[offsets[i] .. offsets[i+1]).
struct NeighborLists {
  std::vector<Index> offsets;    // (n + 1)
  std::vector<Index> indices;    // (number of pairs)
  std::vector<Vector3r> gradW;   // (number of pairs) grad W(x_i - x_j); empty for PairGradients::Factors
  std::vector<Real> gradFactors; // (number of pairs) Kernel::gradFactor(|x_ij|); empty for PairGradients::Vectors
  // (n) only when the build was given kernel weights w, else empty: sum_j w_j W(x_i - x_j) over
  // the listed j, after w_i W(0) for a search of a set against itself (a density, Eq. 14's
  // fluid part, with w = m).
  std::vector<Real> kernelSums;
  // The queries split into a few ranges per thread (workChunkCount()) with about equal shares of
  // pairs (plus a fixed cost per query): the schedule of the loops over these lists
  // (parallelFor(work, n, f)).
  WorkPartition work;
  // Per-range scratch of the build, kept so that steady-state steps allocate nothing.
  std::vector<std::vector<Index>> scratchIndices;
  std::vector<std::vector<Vector3r>> scratchGradW;
  std::vector<std::vector<Real>> scratchGradFactors;
  std::vector<std::vector<Index>> scratchAccepted;  // per range: the accepted candidates of one query
  std::vector<std::vector<Real>> scratchDistances, scratchKernelValues, scratchKernelFactors;  // per range: theirs |x_ij|, W, gradFactor

  std::size_t queryCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  Index begin(std::size_t i) const { return offsets[i]; }
  Index end(std::size_t i) const { return offsets[i + 1]; }
  Index count(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  // grad W(x_ij) of pair e of a PairGradients::Factors list, x_ij = x_i - x_indices[e]: the
  // same bits as Kernel::gradW(x_ij) in double builds; in float builds on AVX2 or AVX-512 the
  // distance is the square root of the search's squared one, which may differ from Eigen's norm
  // in its last bit (NeighborSearch.cpp, kPacksSquaredDistances).
  Vector3r gradient(Index e, const Vector3r& xij) const { return xij * gradFactors[e]; }
  std::size_t pairCount() const { return indices.size(); }
};

// A dense uniform grid over the bounding box of one point set, cells in row-major order (x
// fastest), points counting-sorted by cell. The three cells of a row are contiguous in the
// sorted arrays, so a query visits 9 ranges instead of 27 cells, and no two cells share a slot
// (no hash aliasing to filter). Cells grow past `cellSize` only when the box would need more
// than kMaxCellsPerPoint cells per point (points flung far apart), which keeps memory bounded.
class PointGrid {
 public:
  void build(const Vector3r* points, std::size_t n, Real cellSize);
  std::size_t size() const { return sortedIndex_.size(); }
  Real cellSize() const { return cellSize_; }

  // Calls f(begin, end) for the ranges of sorted entries (sortedPoints/sortedIndices) of the
  // 27 cells around p (as up to 9 row ranges); candidates, to be filtered by distance.
  template <class F>
  void forEachCandidateRange(const Vector3r& p, F&& f) const {
    if (sortedIndex_.empty()) return;
    const int cx = cellCoord(p[0], 0), cy = cellCoord(p[1], 1), cz = cellCoord(p[2], 2);
    const int x0 = std::max(cx - 1, 0), x1 = std::min(cx + 1, dims_[0] - 1);
    if (x0 > x1) return;
    for (int z = std::max(cz - 1, 0); z <= std::min(cz + 1, dims_[2] - 1); ++z)
      for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, dims_[1] - 1); ++y) {
        const std::size_t row = (std::size_t(z) * dims_[1] + y) * dims_[0];
        const Index begin = cellStart_[row + x0], end = cellStart_[row + x1 + 1];
        if (begin < end) f(begin, end);
      }
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
  std::array<int, 3> cellOf(const Vector3r& p) const { return {cellCoord(p[0], 0), cellCoord(p[1], 1), cellCoord(p[2], 2)}; }
  const Vector3r* sortedPoints() const { return sortedPoints_.data(); }
  const Index* sortedIndices() const { return sortedIndex_.data(); }
  // Where point i (by the index it was built with) sits in the sorted arrays.
  Index slotOf(std::size_t i) const { return slotOf_[i]; }
  // The sorted positions' coordinates along axis a (structure of arrays), for vectorised
  // distance tests straight over a candidate range.
  const Real* sortedCoordinates(int a) const { return sortedCoords_[a].data(); }

  static constexpr std::size_t kMaxCellsPerPoint = 64;

 private:
  // Cell coordinate along axis a, relative to the box; may lie outside [0, dims) for a query
  // point outside the box (clamped in the range loops).
  int cellCoord(Real v, int a) const {
    const Real c = std::floor((v - origin_[a]) * invCellSize_);
    return c < Real(-2) ? -2 : (c > Real(dims_[a] + 1) ? dims_[a] + 1 : int(c));
  }

  Real cellSize_ = 1, invCellSize_ = 1;
  Vector3r origin_ = Vector3r::Zero();
  std::array<int, 3> dims_ = {0, 0, 0};
  std::vector<Index> cellStart_;       // (cells + 1)
  std::vector<Index> sortedIndex_;     // (n) point index in cell order
  std::vector<Index> slotOf_;          // (n) the inverse: the slot of point i
  std::vector<Vector3r> sortedPoints_; // (n) positions in cell order, for contiguous reads
  std::array<std::vector<Real>, 3> sortedCoords_;  // (3 x n) the same, x, y and z apart
  std::vector<Index> keys_;            // (n) scratch
};

// Builds neighbour lists of `queries` against the points of `grid` within the kernel's support
// radius; `excludeSelf` drops j == i (query set == grid set).
// The grid keeps its own copy of the points it was built over, for the cached kernel gradients.
// With `kernelWeights` (one per grid point, by original index) it also fills out.kernelSums while
// each x_j is in cache, which saves the densities a pass over the lists. `kernelSumStarts` (one
// per query; not with excludeSelf): each sum starts there instead of at 0, so that a second set's
// terms continue a first set's sum in the order a loop over both lists would add them.
void buildNeighborLists(const PointGrid& grid, const Vector3r* queries, std::size_t nQueries, const CubicSplineKernel& kernel,
                        bool excludeSelf, PairGradients gradients, NeighborLists& out, const Real* kernelWeights = nullptr,
                        const Real* kernelSumStarts = nullptr);

// A permutation that orders the points along a Z-order (Morton) curve of cells of `cellSize`,
// so that neighbours in space are neighbours in memory.
std::vector<Index> zOrderPermutation(const Vector3r* points, std::size_t n, Real cellSize);

// Lists reversed: for every point j of the target set (nTargets), the queries i listing it.
// gradW entries are grad W(x_j - x_i) = -grad W(x_i - x_j); gradFactors entries are copied (the
// factor of x_ji = -x_ij is the same).
void transposeNeighborLists(const NeighborLists& lists, std::size_t nTargets, NeighborLists& out);

}  // namespace consph
