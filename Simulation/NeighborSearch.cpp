#include "Simulation/NeighborSearch.h"


#include <algorithm>
#include <numeric>

#include "Utilities/Error.h"
#include "Utilities/ParallelFor.h"

namespace consph {

void PointGrid::build(const Vector3r* points, std::size_t n, Real cellSize) {
  keys_.resize(n);
  sortedIndex_.resize(n);
  sortedPoints_.resize(n);
  if (n == 0) {
    dims_ = {0, 0, 0};
    cellStart_.assign(1, 0);
    return;
  }
  // A NaN or inf point (or points spanning more than a double) would make the cell-growing
  // loop below run forever: refuse. (min/max skip a NaN, so each point is checked.)
  Vector3r lo = points[0], hi = points[0];
  bool finite = true;
  for (std::size_t i = 0; i < n; ++i) {
    finite &= points[i].allFinite();
    lo = lo.cwiseMin(points[i]);
    hi = hi.cwiseMax(points[i]);
  }
  if (!finite || !(hi - lo).allFinite())
    throw SimulationError("neighbour search: the points span a non-finite box (a NaN or inf position)");
  // Points flung far apart would need a huge box of small cells: grow the cells instead (still
  // >= cellSize, so the 27-cell query stays complete).
  cellSize_ = cellSize;
  const std::size_t maxCells = std::max<std::size_t>(kMaxCellsPerPoint * n, 4096);
  for (;;) {
    std::size_t cells = 1;
    for (int a = 0; a < 3; ++a) {
      dims_[a] = int(std::min<Real>(std::floor((hi[a] - lo[a]) / cellSize_) + 1, Real(1 << 20)));
      cells *= std::size_t(dims_[a]);
    }
    if (cells <= maxCells) break;
    cellSize_ *= 2;
  }
  invCellSize_ = Real(1) / cellSize_;
  origin_ = lo;
  const std::size_t cells = std::size_t(dims_[0]) * dims_[1] * dims_[2];
  parallelFor(n, [&](std::size_t i) {
    auto c = cellOf(points[i]);
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(c[a], 0, dims_[a] - 1);  // rounding at the box's upper faces
    keys_[i] = Index((std::size_t(c[2]) * dims_[1] + c[1]) * dims_[0] + c[0]);
  });
  // Counting sort by cell: O(n + cells), serial, a small fraction of the neighbour-list build.
  cellStart_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++cellStart_[keys_[i] + 1];
  std::partial_sum(cellStart_.begin(), cellStart_.end(), cellStart_.begin());
  std::vector<Index> cursor(cellStart_.begin(), cellStart_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const Index s = cursor[keys_[i]]++;
    sortedIndex_[s] = Index(i);
    sortedPoints_[s] = points[i];
  }
}

void buildNeighborLists(const PointGrid& grid, const Vector3r* queries, std::size_t n,
                        const CubicSplineKernel& kernel, bool excludeSelf, NeighborLists& out) {
  const Real h = kernel.supportRadius();
  out.offsets.resize(n + 1);
  out.offsets[0] = 0;
  const std::size_t chunks = parallelChunkCount();
  // Per-chunk buffers live in `out`, so steady-state steps allocate nothing.
  out.scratchIndices.resize(chunks);
  out.scratchGradW.resize(chunks);
  out.scratchCandidates.resize(chunks);
  out.scratchCandidateIds.resize(chunks);
  std::vector<std::size_t> chunkBegin(chunks, n);
  // A chunk a smaller team leaves out must not copy an earlier call's lists.
  for (std::size_t t = 0; t < chunks; ++t) out.scratchIndices[t].clear(), out.scratchGradW[t].clear();
  const Real h2 = h * h;
  constexpr Index kNoSelf = ~Index(0);  // no candidate has this index
  // Each chunk fills its own buffers, which are then copied into the CSR arrays by chunk (a GPU
  // backend would count, prefix-sum and fill instead).
  parallelChunks(n, [&](std::size_t t, std::size_t b, std::size_t e) {
    // Chunks in index order: concatenating their buffers gives the CSR array.
    // Queries are Z-sorted, so consecutive ones mostly share a cell: the candidates of the 27
    // cells around it are gathered once into a structure-of-arrays buffer, whose distance test
    // vectorises. grad W is evaluated while x_j is in cache. The order within a list is
    // deterministic (cells in a fixed order, entries in cell order).
    chunkBegin[t] = b;
    // The buffers are moved into locals: their headers (size, capacity) then live on this
    // thread's stack, not side by side in a shared array where every push_back would fight
    // over one cache line with the other threads (false sharing).
    std::vector<Index> idx = std::move(out.scratchIndices[t]), candId = std::move(out.scratchCandidateIds[t]);
    std::vector<Vector3r> grad = std::move(out.scratchGradW[t]);
    std::vector<Real> cand = std::move(out.scratchCandidates[t]);
    idx.clear();
    grad.clear();
    std::array<int, 3> cell = {0, 0, 0};
    bool haveCell = false;
    std::size_t nc = 0;
    std::vector<Real> d2;         // thread-local
    std::vector<Index> accepted;  // thread-local: positions in the candidate buffer
    const Vector3r* sp = grid.sortedPoints();
    const Index* si = grid.sortedIndices();
    for (std::size_t i = b; i < e; ++i) {
      const Vector3r xi = queries[i];
      const auto c = grid.cellOf(xi);
      if (!haveCell || c != cell) {
        cell = c;
        haveCell = true;
        candId.clear();
        grid.forEachCandidateRange(xi, [&](Index begin, Index end) {
          for (Index s = begin; s < end; ++s) candId.push_back(s);
        });
        nc = candId.size();
        cand.resize(3 * nc);
        for (std::size_t k = 0; k < nc; ++k) {
          const Vector3r& q = sp[candId[k]];
          cand[k] = q[0];
          cand[nc + k] = q[1];
          cand[2 * nc + k] = q[2];
          candId[k] = si[candId[k]];
        }
        d2.resize(nc);
        accepted.resize(nc);
      }
      const Real* cx = cand.data();
      const Real* cy = cx + nc;
      const Real* cz = cy + nc;
      const Real px = xi[0], py = xi[1], pz = xi[2];
#pragma omp simd
      for (std::size_t k = 0; k < nc; ++k) {
        const Real dx = px - cx[k], dy = py - cy[k], dz = pz - cz[k];
        d2[k] = dx * dx + dy * dy + dz * dz;
      }
      // Compact the accepted candidates without a branch: about one in six passes, in no
      // pattern a branch predictor can learn, and a mispredicted branch per candidate cost more
      // than the test (perf, bench/RESULTS.md "Where the volume-map dam break's step goes").
      // The order is the candidates' order, as before.
      const Index self = excludeSelf ? Index(i) : kNoSelf;
      std::size_t m = 0;
      for (std::size_t k = 0; k < nc; ++k) {
        accepted[m] = Index(k);
        m += std::size_t((d2[k] <= h2) & (candId[k] != self));
      }
      const std::size_t before = idx.size();
      idx.resize(before + m);
      grad.resize(before + m);
      for (std::size_t a = 0; a < m; ++a) {
        const std::size_t k = accepted[a];
        idx[before + a] = candId[k];
        grad[before + a] = kernel.gradW(Vector3r(px - cx[k], py - cy[k], pz - cz[k]));
      }
      out.offsets[i + 1] = Index(m);
    }
    out.scratchIndices[t] = std::move(idx);
    out.scratchGradW[t] = std::move(grad);
    out.scratchCandidates[t] = std::move(cand);
    out.scratchCandidateIds[t] = std::move(candId);
  });
  for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] += out.offsets[i];
  out.indices.resize(out.offsets[n]);
  out.gradW.resize(out.offsets[n]);
  parallelFor(chunks, [&](std::size_t t) {
    const std::size_t at = out.offsets[chunkBegin[t]];
    std::copy(out.scratchIndices[t].begin(), out.scratchIndices[t].end(), out.indices.begin() + at);
    std::copy(out.scratchGradW[t].begin(), out.scratchGradW[t].end(), out.gradW.begin() + at);
  });
}

namespace {
std::uint64_t spreadBits(std::uint64_t v) {  // 21 bits -> every third bit
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}
}  // namespace

std::vector<Index> zOrderPermutation(const Vector3r* points, std::size_t n, Real cellSize) {
  std::vector<Index> order(n);
  if (n == 0) return order;
  Vector3r lo = points[0];
  for (std::size_t i = 1; i < n; ++i) lo = lo.cwiseMin(points[i]);
  std::vector<std::pair<std::uint64_t, Index>> keyed(n);
  const Real inv = Real(1) / cellSize;
  parallelFor(n, [&](std::size_t i) {
    const Vector3r c = (points[i] - lo) * inv;
    std::uint64_t key = 0;
    for (int d = 0; d < 3; ++d) key |= spreadBits(std::uint64_t(std::max<Real>(c[d], 0))) << d;
    keyed[i] = {key, Index(i)};
  });
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t i = 0; i < n; ++i) order[i] = keyed[i].second;
  return order;
}

void transposeNeighborLists(const NeighborLists& lists, std::size_t nTargets, NeighborLists& out) {
  const std::size_t n = lists.queryCount();
  out.offsets.assign(nTargets + 1, 0);
  for (Index j : lists.indices) ++out.offsets[j + 1];
  std::partial_sum(out.offsets.begin(), out.offsets.end(), out.offsets.begin());
  out.indices.resize(lists.indices.size());
  out.gradW.resize(lists.gradW.size());
  std::vector<Index> cursor(out.offsets.begin(), out.offsets.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    for (Index e = lists.begin(i); e < lists.end(i); ++e) {
      const Index s = cursor[lists.indices[e]]++;
      out.indices[s] = Index(i);
      if (!lists.gradW.empty()) out.gradW[s] = -lists.gradW[e];
    }
}

}  // namespace consph
