#include "Simulation/NeighborSearch.h"


#include <algorithm>
#include <numeric>

#include "Utilities/AxisAlignedBox.h"
#include "Utilities/Error.h"
#include "Utilities/ParallelFor.h"

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define CONSPH_NEIGHBOR_AVX512 1
#elif defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define CONSPH_NEIGHBOR_AVX2 1
#endif

namespace consph {

namespace {
// The bit of the candidate at slot `selfSlot` among `lanes` candidates from slot k, 0 when it is
// not among them (selfSlot - k wraps to a huge value below k; no self: selfSlot = SIZE_MAX).
inline unsigned selfBit(std::size_t selfSlot, std::size_t k, std::size_t lanes) {
  const std::size_t o = selfSlot - k;
  return o < lanes ? 1u << o : 0u;
}

#if defined(CONSPH_NEIGHBOR_AVX512)
// Which of the 16 candidates at c (the `live` ones) lie within sqrt(h2) of p, |x_i - x_j|^2 as
// dx^2, then + dy^2, then + dz^2, fused (the AVX2 path's order; the scalar fallback's is the
// compiler's, so machines on different paths may decide a pair within an ulp of h differently,
// where W and grad W are zero to within an ulp). Float: the squared distances go to *d2.
#if CONSPH_USE_DOUBLE
__mmask16 withinRadius(__mmask16 live, const Real* cx, const Real* cy, const Real* cz, const Vector3r& p, Real h2, __m512*) {
  const auto half = [&](__mmask8 l, std::size_t o) {  // 8 doubles at a time
    const __m512d dx = _mm512_sub_pd(_mm512_set1_pd(p[0]), _mm512_maskz_loadu_pd(l, cx + o));
    const __m512d dy = _mm512_sub_pd(_mm512_set1_pd(p[1]), _mm512_maskz_loadu_pd(l, cy + o));
    const __m512d dz = _mm512_sub_pd(_mm512_set1_pd(p[2]), _mm512_maskz_loadu_pd(l, cz + o));
    const __m512d d2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
    return unsigned(_mm512_mask_cmp_pd_mask(l, d2, _mm512_set1_pd(h2), _CMP_LE_OQ));
  };
  return __mmask16(half(__mmask8(live), 0) | half(__mmask8(live >> 8), 8) << 8);
}
#else
__mmask16 withinRadius(__mmask16 live, const Real* cx, const Real* cy, const Real* cz, const Vector3r& p, Real h2, __m512* d2) {
  const __m512 dx = _mm512_sub_ps(_mm512_set1_ps(p[0]), _mm512_maskz_loadu_ps(live, cx));
  const __m512 dy = _mm512_sub_ps(_mm512_set1_ps(p[1]), _mm512_maskz_loadu_ps(live, cy));
  const __m512 dz = _mm512_sub_ps(_mm512_set1_ps(p[2]), _mm512_maskz_loadu_ps(live, cz));
  *d2 = _mm512_fmadd_ps(dz, dz, _mm512_fmadd_ps(dy, dy, _mm512_mul_ps(dx, dx)));
  return _mm512_mask_cmp_ps_mask(live, *d2, _mm512_set1_ps(h2), _CMP_LE_OQ);
}
#endif
#endif

#if defined(CONSPH_NEIGHBOR_AVX2)
// AVX2 has no compress-store: row `mask` of this table holds the lanes of the set bits of an
// 8-bit mask, packed to the front in ascending order (the rest 0), so that one permute-free
// store of position + row writes the accepted candidates of 8 in order, and one permute of the
// eight squared distances by the same row packs theirs (float).
struct LeftPackTable {
  alignas(32) std::uint32_t lanes[256][8];
  constexpr LeftPackTable() : lanes{} {
    for (unsigned mask = 0; mask < 256; ++mask) {
      unsigned m = 0;
      for (unsigned lane = 0; lane < 8; ++lane)
        if (mask >> lane & 1u) lanes[mask][m++] = lane;
    }
  }
};
constexpr LeftPackTable kLeftPack;

// Of the first `live` (1-8) candidates at c, the mask of those within sqrt(h2) of p and not in
// `excluded` (the query itself), |x_i - x_j|^2 as dx^2, then + dy^2, then + dz^2, fused, and
// (float) their squared distances written to d2[0 ..), packed in order (8 values written; those
// past the accepted ones are junk that the next call overwrites or nobody reads). A range's last
// few are read with masked loads, so that every candidate of a list goes through this one
// formula (a scalar tail contracted by the compiler may fuse in another order and, within an ulp
// of h, decide a pair differently: j listing i but not i j).
#if CONSPH_USE_DOUBLE
// Double builds keep the distances of Eigen's norm (kPacksSquaredDistances below): the mask only.
unsigned acceptEight(const Real* cx, const Real* cy, const Real* cz, const Vector3r& p, Real h2, std::size_t live, unsigned excluded,
                     Real*) {
  const auto half = [&](std::size_t o) {  // 4 doubles at a time
    using Lane = long long;
    const __m256i on = _mm256_cmpgt_epi64(_mm256_set1_epi64x(Lane(live)), _mm256_setr_epi64x(Lane(o), Lane(o + 1), Lane(o + 2), Lane(o + 3)));
    const __m256d dx = _mm256_sub_pd(_mm256_set1_pd(p[0]), _mm256_maskload_pd(cx + o, on));
    const __m256d dy = _mm256_sub_pd(_mm256_set1_pd(p[1]), _mm256_maskload_pd(cy + o, on));
    const __m256d dz = _mm256_sub_pd(_mm256_set1_pd(p[2]), _mm256_maskload_pd(cz + o, on));
    const __m256d d2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
    return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(d2, _mm256_set1_pd(h2), _CMP_LE_OQ)));
  };
  return (half(0) | half(4) << 4) & ((1u << live) - 1) & ~excluded;
}
#else
unsigned acceptEight(const Real* cx, const Real* cy, const Real* cz, const Vector3r& p, Real h2, std::size_t live, unsigned excluded,
                     Real* d2) {
  const __m256i on = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(live)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256 dx = _mm256_sub_ps(_mm256_set1_ps(p[0]), _mm256_maskload_ps(cx, on));
  const __m256 dy = _mm256_sub_ps(_mm256_set1_ps(p[1]), _mm256_maskload_ps(cy, on));
  const __m256 dz = _mm256_sub_ps(_mm256_set1_ps(p[2]), _mm256_maskload_ps(cz, on));
  const __m256 d = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
  const unsigned in = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(d, _mm256_set1_ps(h2), _CMP_LE_OQ))) & ((1u << live) - 1) & ~excluded;
  const __m256i lanes = _mm256_load_si256(reinterpret_cast<const __m256i*>(kLeftPack.lanes[in]));
  _mm256_storeu_ps(d2, _mm256_permutevar8x32_ps(d, lanes));
  return in;
}
#endif
#endif  // CONSPH_NEIGHBOR_AVX2

#if defined(CONSPH_NEIGHBOR_AVX512) || defined(CONSPH_NEIGHBOR_AVX2)
// The pairs' distances as the square roots of the test's squared distances, packed with the
// positions, instead of a second pass gathering x_j for Eigen's norm (which the compiler
// contracts in another order: 1 ulp apart for about one pair in six). Float builds only: double
// builds keep the norm's bits, as they keep the scalar pair sums (Utilities/SimdLanes.h,
// kPackedPairSums; bench/RESULTS.md, "List build by slots").
constexpr bool kPacksSquaredDistances = sizeof(Real) == 4;
// v[a] = sqrt(v[a]) for a < m, 8 at a time (v has room up to the next block of 8).
void squareRootsInPlace(Real* v, std::size_t m) {
#if !CONSPH_USE_DOUBLE
  for (std::size_t a = 0; a < m; a += 8) _mm256_storeu_ps(v + a, _mm256_sqrt_ps(_mm256_loadu_ps(v + a)));
#endif
}
#else
constexpr bool kPacksSquaredDistances = false;  // the scalar path writes no squared distances
void squareRootsInPlace(Real*, std::size_t) {}
#endif
// What acceptCandidates may write past the candidates it is given: a block of lanes.
#if defined(CONSPH_NEIGHBOR_AVX512)
constexpr std::size_t kAcceptSlack = 16;
#else
constexpr std::size_t kAcceptSlack = 8;
#endif

// Writes the positions k in [first, last), in ascending order, of the candidates (SoA cx, cy, cz)
// within sqrt(h2) of p but for the one at `selfSlot` (the query itself), and returns how many;
// on the SIMD paths in float (kPacksSquaredDistances) their |x_i - x_j|^2 go to squaredDistances
// in the same order. Both outputs have room for kAcceptSlack entries past the candidates. About one
// candidate in six passes, in no pattern a branch predictor can learn, so there is no branch per
// candidate: with AVX-512 the test and the compaction (vpcompressd in a register) take 16 candidates at a
// time; with AVX2 (no compress-store) 8 at a time through a table of packed lanes (kLeftPack);
// otherwise a vectorised distance loop and a branch-free scalar compaction. Within one build
// every candidate takes one formula, so lists are symmetric (j lists i iff i lists j); the paths
// agree but for pairs within an ulp of h (perf, bench/RESULTS.md "Where the volume-map dam
// break's step goes"; on an AVX2-only EPYC the scalar compaction was a third of the list build:
// "AVX2 compaction, kernel in batches"). The query is left out by its slot, not by comparing
// every candidate's index (a load and a compare per block: "List build by slots").
std::size_t acceptCandidates(const Real* cx, const Real* cy, const Real* cz, std::size_t first, std::size_t last, const Vector3r& p,
                             Real h2, std::size_t selfSlot, Index* accepted, [[maybe_unused]] Real* squaredDistances) {
  std::size_t k = first, m = 0;
#if defined(CONSPH_NEIGHBOR_AVX512)
  constexpr std::size_t kLanes = 16;
  const __m512i step = _mm512_set1_epi32(int(kLanes));
  __m512i position =
      _mm512_add_epi32(_mm512_set1_epi32(int(first)), _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  for (; k < last; k += kLanes) {
    const __mmask16 live = last - k >= kLanes ? __mmask16(0xffff) : __mmask16((1u << (last - k)) - 1);
    __m512 d2;
    const __mmask16 in = withinRadius(live, cx + k, cy + k, cz + k, p, h2, &d2) & __mmask16(~selfBit(selfSlot, k, kLanes));
    // Compacted in a register and stored whole (the lanes past the accepted ones are junk within
    // the slack): vpcompressd straight to memory is microcoded on Zen 4, 21 ns per 16 candidates
    // against 1.4 ns this way (bench/RESULTS.md, "AVX-512 compaction in a register").
    _mm512_storeu_si512(accepted + m, _mm512_maskz_compress_epi32(in, position));
    if constexpr (kPacksSquaredDistances) _mm512_storeu_ps(squaredDistances + m, _mm512_maskz_compress_ps(in, d2));
    m += std::size_t(__builtin_popcount(unsigned(in)));
    position = _mm512_add_epi32(position, step);
  }
#elif defined(CONSPH_NEIGHBOR_AVX2)
  // 8 candidates at a time (the last few with masked loads): the mask of those within reach
  // and not the query picks a row of kLeftPack, and one 8-lane store writes their positions to
  // accepted[m..m+7], acceptEight their squared distances. The lanes past the accepted ones are
  // junk that the next store overwrites or nobody reads, within the outputs' slack.
  for (; k < last; k += 8) {
    const std::size_t live = std::min<std::size_t>(8, last - k);
    const unsigned in = acceptEight(cx + k, cy + k, cz + k, p, h2, live, selfBit(selfSlot, k, 8), squaredDistances + m);
    const __m256i lanes = _mm256_load_si256(reinterpret_cast<const __m256i*>(kLeftPack.lanes[in]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(accepted + m), _mm256_add_epi32(_mm256_set1_epi32(int(k)), lanes));
    m += std::size_t(__builtin_popcount(in));
  }
#else
  // Blocks of candidates: the distances vectorise, the compaction is scalar.
  constexpr std::size_t kBlock = 64;
  Real d2[kBlock];
  for (; k < last; k += kBlock) {
    const std::size_t nb = std::min(kBlock, last - k);
#pragma omp simd
    for (std::size_t j = 0; j < nb; ++j) {
      const Real dx = p[0] - cx[k + j], dy = p[1] - cy[k + j], dz = p[2] - cz[k + j];
      d2[j] = dx * dx + dy * dy + dz * dz;
    }
    for (std::size_t j = 0; j < nb; ++j) {
      accepted[m] = Index(k + j);
      m += std::size_t((d2[j] <= h2) & (k + j != selfSlot));
    }
  }
#endif
  return m;
}
}  // namespace

void PointGrid::build(const Vector3r* points, std::size_t n, Real cellSize) {
  keys_.resize(n);
  sortedIndex_.resize(n);
  slotOf_.resize(n);
  sortedPoints_.resize(n);
  for (auto& c : sortedCoords_) c.resize(n);
  if (n == 0) {
    dims_ = {0, 0, 0};
    cellStart_.assign(1, 0);
    return;
  }
  // A NaN or inf point (or points spanning more than a double) would make the cell-growing
  // loop below run forever: refuse. In parallel: serial, this pass was 1.7 % of a dam break's
  // step on 2 threads.
  const PointBox box = boxOfPoints(points, n);
  const Vector3r lo = box.lo, hi = box.hi;
  if (!box.finite || !(hi - lo).allFinite())
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
    slotOf_[i] = s;
    sortedPoints_[s] = points[i];
    for (int a = 0; a < 3; ++a) sortedCoords_[a][s] = points[i][a];
  }
}

void buildNeighborLists(const PointGrid& grid, const Vector3r* queries, std::size_t n, const CubicSplineKernel& kernel,
                        bool excludeSelf, PairGradients gradients, NeighborLists& out, const Real* kernelWeights,
                        const Real* kernelSumStarts) {
  const Real h = kernel.supportRadius();
  const bool factors = gradients == PairGradients::Factors;
  out.offsets.resize(n + 1);
  if (kernelWeights)
    out.kernelSums.resize(n);
  else
    out.kernelSums.clear();  // no stale sums from an earlier call
  out.offsets[0] = 0;
  const std::size_t chunks = workChunkCount();
  // Per-chunk buffers live in `out`, so steady-state steps allocate nothing.
  out.scratchIndices.resize(chunks);
  out.scratchGradW.resize(chunks);
  out.scratchGradFactors.resize(chunks);
  out.scratchAccepted.resize(chunks);
  out.scratchDistances.resize(chunks);
  out.scratchKernelValues.resize(chunks);
  out.scratchKernelFactors.resize(chunks);
  std::vector<std::size_t> chunkBegin(chunks, n);
  // The ranges of the last build's balance while the queries are the same ones (their pairs
  // change little from step to step), equal ones otherwise.
  if (out.work.size() != n || out.work.chunks() != chunks) out.work.balance(n, chunks, [](std::size_t i) { return i; });
  // No chunk's buffer may carry an earlier call's lists into the copy below (every chunk runs and
  // clears its own; this guards the copy should one not run).
  for (std::size_t t = 0; t < chunks; ++t) out.scratchIndices[t].clear(), out.scratchGradW[t].clear(), out.scratchGradFactors[t].clear();
  const Real h2 = h * h;
  constexpr std::size_t kNoSelf = ~std::size_t(0);  // no candidate has this slot
  // A query's own work (its cell's ranges, its sums' set-up and stores) in pairs' worth, for
  // the balance of `out.work`; the loops over a dam break's lists hold ~40 pairs per query.
  constexpr std::size_t kCostPerQuery = 4;
  // Each chunk fills its own buffers, which are then copied into the CSR arrays by chunk (a GPU
  // backend would count, prefix-sum and fill instead).
  parallelChunks(out.work, [&](std::size_t t, std::size_t b, std::size_t e) {
    // Chunks in index order: concatenating their buffers gives the CSR array.
    // The grid keeps its sorted points as a structure of arrays, and the 27 cells around a
    // query are 9 contiguous ranges of it, so the distance test runs straight over those ranges
    // (no candidate is copied). Queries are Z-sorted, so consecutive ones mostly share a cell and
    // its ranges. grad W is evaluated while x_j is in cache. The order within a list is
    // deterministic (rows in a fixed order, entries in cell order).
    chunkBegin[t] = b;
    // The buffers are moved into locals: their headers (size, capacity) then live on this
    // thread's stack, not side by side in a shared array where every push_back would fight
    // over one cache line with the other threads (false sharing).
    std::vector<Index> idx = std::move(out.scratchIndices[t]), accepted = std::move(out.scratchAccepted[t]);
    std::vector<Vector3r> grad = std::move(out.scratchGradW[t]);
    std::vector<Real> factor = std::move(out.scratchGradFactors[t]);
    std::vector<Real> distance = std::move(out.scratchDistances[t]), value = std::move(out.scratchKernelValues[t]),
                      gradientFactor = std::move(out.scratchKernelFactors[t]);
    idx.clear();
    grad.clear();
    factor.clear();
    std::array<int, 3> cell = {0, 0, 0};
    bool haveCell = false;
    std::array<std::pair<Index, Index>, 9> ranges;
    std::size_t rangeCount = 0;
    const Real* sx = grid.sortedCoordinates(0);
    const Real* sy = grid.sortedCoordinates(1);
    const Real* sz = grid.sortedCoordinates(2);
    const Index* si = grid.sortedIndices();
    for (std::size_t i = b; i < e; ++i) {
      const Vector3r xi = queries[i];
      const auto c = grid.cellOf(xi);
      if (!haveCell || c != cell) {
        cell = c;
        haveCell = true;
        rangeCount = 0;
        std::size_t candidates = 0;
        grid.forEachCandidateRange(xi, [&](Index begin, Index end) {
          ranges[rangeCount++] = {begin, end};
          candidates += end - begin;
        });
        if (accepted.size() < candidates + kAcceptSlack) {
          accepted.resize(candidates + kAcceptSlack);
          distance.resize(candidates + kAcceptSlack), value.resize(candidates), gradientFactor.resize(candidates);
        }
      }
      // The query itself, in a search of a set against itself: the grid was built over the queries.
      const std::size_t selfSlot = excludeSelf ? std::size_t(grid.slotOf(i)) : kNoSelf;
      std::size_t m = 0;
      for (std::size_t r = 0; r < rangeCount; ++r)
        m += acceptCandidates(sx, sy, sz, ranges[r].first, ranges[r].second, xi, h2, selfSlot, accepted.data() + m, distance.data() + m);
      const std::size_t before = idx.size();
      idx.resize(before + m);
      if (factors)
        factor.resize(before + m);
      else
        grad.resize(before + m);
      const Real px = xi[0], py = xi[1], pz = xi[2];
      // The pairs' distances and indices, then the kernel for all of them at once (vectorised,
      // Kernel::evaluate), then the gradients and the weighted sum. The distances: Eigen's norm,
      // or in float SIMD builds the square roots of the test's squared ones (kPacksSquaredDistances).
      if constexpr (kPacksSquaredDistances) {
        squareRootsInPlace(distance.data(), m);
        for (std::size_t a = 0; a < m; ++a) idx[before + a] = si[accepted[a]];
      } else {
        for (std::size_t a = 0; a < m; ++a) {
          const std::size_t s = accepted[a];
          distance[a] = Vector3r(px - sx[s], py - sy[s], pz - sz[s]).norm();
          idx[before + a] = si[s];
        }
      }
      Real* g = factors ? factor.data() + before : gradientFactor.data();
      kernel.evaluate(distance.data(), m, g, kernelWeights ? value.data() : nullptr);
      if (!factors)
        for (std::size_t a = 0; a < m; ++a) {
          const std::size_t s = accepted[a];
          grad[before + a] = Vector3r(px - sx[s], py - sy[s], pz - sz[s]) * g[a];  // Kernel::gradW(x)
        }
      if (kernelWeights) {
        // The same sum, in the same order, as a loop over the finished list would give.
        Real sum = excludeSelf ? kernelWeights[i] * kernel.W0() : (kernelSumStarts ? kernelSumStarts[i] : Real(0));
        for (std::size_t a = 0; a < m; ++a) sum += kernelWeights[idx[before + a]] * value[a];
        out.kernelSums[i] = sum;
      }
      out.offsets[i + 1] = Index(m);
    }
    out.scratchIndices[t] = std::move(idx);
    out.scratchGradW[t] = std::move(grad);
    out.scratchGradFactors[t] = std::move(factor);
    out.scratchAccepted[t] = std::move(accepted);
    out.scratchDistances[t] = std::move(distance);
    out.scratchKernelValues[t] = std::move(value);
    out.scratchKernelFactors[t] = std::move(gradientFactor);
  });
  for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] += out.offsets[i];
  out.work.balance(n, chunks, [&](std::size_t i) { return std::size_t(out.offsets[i]) + kCostPerQuery * i; });
  out.indices.resize(out.offsets[n]);
  // The unused form is emptied: no stale gradients of an earlier call in the other form.
  out.gradW.resize(factors ? 0 : out.offsets[n]);
  out.gradFactors.resize(factors ? out.offsets[n] : 0);
  parallelFor(chunks, [&](std::size_t t) {
    const std::size_t at = out.offsets[chunkBegin[t]];
    std::copy(out.scratchIndices[t].begin(), out.scratchIndices[t].end(), out.indices.begin() + at);
    if (factors)
      std::copy(out.scratchGradFactors[t].begin(), out.scratchGradFactors[t].end(), out.gradFactors.begin() + at);
    else
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
  const Vector3r lo = boxOfPoints(points, n).lo;
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
  out.gradFactors.resize(lists.gradFactors.size());
  std::vector<Index> cursor(out.offsets.begin(), out.offsets.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    for (Index e = lists.begin(i); e < lists.end(i); ++e) {
      const Index s = cursor[lists.indices[e]]++;
      out.indices[s] = Index(i);
      if (!lists.gradW.empty()) out.gradW[s] = -lists.gradW[e];
      if (!lists.gradFactors.empty()) out.gradFactors[s] = lists.gradFactors[e];
    }
}

}  // namespace consph
