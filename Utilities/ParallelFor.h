// One dispatch for particle loops: every parallel loop over particles (or samples, pairs, grid
// slices) goes through these functions, with OpenMP behind them today.
//
//   parallelFor(n, f)              f(i) for every i in [0, n), static schedule (equal chunks in
//                                  thread order): for loops whose iterations cost about the same
//   parallelForDynamic(n, f, c)    the same with a dynamic schedule in chunks of c: for iterations
//                                  of very different cost (mesh queries, grid slices)
//   parallelReduce(n, id, join, body)
//                                  body(i, acc) adds iteration i into acc, one accumulator per
//                                  thread starting at `id`; join(into, from) folds one into another
//   parallelReduceDynamic(n, id, join, body, c)
//                                  the same with a dynamic schedule, for exact joins only
//                                  (integer counts, min, max, flags)
//   parallelSum<T>(n, f)           sum of f(i) in T        parallelMax<T>(n, init, f)  max(init, f(i))
//   parallelAny(n, pred)           whether pred(i) holds for some i
//   parallelFor(work, n, f), parallelReduce(work, n, id, join, body), parallelChunks(work, body)
//                                  the same over a WorkPartition: contiguous ranges holding equal
//                                  shares of a per-index cost (a particle's neighbour pairs), for
//                                  the loops over neighbour lists (a particle at the free surface
//                                  has a fraction of the bulk's pairs; a dam break's first half of
//                                  Z-sorted particles held up to 1.3x the pairs of its second),
//                                  a few ranges per thread, taken as the threads come for them
//   parallelChunks(n, body)        body(chunk, begin, end) once per thread over its contiguous
//                                  chunk [begin, end) of [0, n), the chunks of parallelFor's static
//                                  schedule, chunk = 0 .. parallelChunkCount() - 1 in index order:
//                                  for loops that fill one buffer per chunk (neighbour lists, contact
//                                  lists, per-body sums) and then join the buffers in chunk order
//
// Reductions are reproducible: the schedule is static, each thread folds its own contiguous chunk
// in index order, and the threads' accumulators are joined in thread order after the loop, so
// a run gives the same bits with the same thread count. (OpenMP's reduction clause joins in the
// order the threads arrive; with two threads and a zero start the two orders give the same sum,
// which is why converting the clauses changed no result.) The result of a sum still depends on
// the thread count, as it did with the clause.
//
// What a GPU backend needs from this seam, and what the loops behind it already give it:
// - the body takes an index and nothing else: no iteration reads what another one writes, except
//   through parallelReduce's accumulator; no locks, no atomics, no omp_get_thread_num();
// - the data a body touches must live on the device: today the bodies capture std::vector& and
//   StepContext& by reference; a device backend needs them as spans (pointer and size) of fields
//   that are mirrored on the device, captured by value (issue 17: spans in the context), and the
//   bodies must be callable there (no virtual calls, no allocation, no exceptions, no logging);
// - a reduction's join must be associative (the device joins in a tree, not in thread order):
//   device sums will differ from the CPU's in the last bits, as they do across thread counts;
// - parallelForDynamic is a hint of uneven cost; a device launch ignores it;
// - parallelChunks' bodies (neighbour-list build, rigid contacts, per-body impulse gathering)
//   keep one buffer per chunk and concatenate or add them in chunk order: a device backend
//   replaces them with a count / prefix-sum / fill pass, or with a per-block reduction.
#pragma once
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace consph {

// f(i) for every i in [0, n), static schedule: equal contiguous chunks in thread order.
template <class F>
void parallelFor(std::size_t n, F&& f) {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) f(i);
}

// f(i) for every i in [0, n), dynamic schedule: threads take `chunk` iterations at a time.
template <class F>
void parallelForDynamic(std::size_t n, F&& f, std::size_t chunk = 256) {
  chunk = std::max<std::size_t>(chunk, 1);
#pragma omp parallel for schedule(dynamic, chunk)
  for (std::size_t i = 0; i < n; ++i) f(i);
}

// How many ranges a WorkPartition cuts for the loops over neighbour lists: kRangesPerThread per
// thread, which forEachChunk hands out as the threads come for them. A thread that runs slower
// (this VM's two vCPUs do not run alike, and the host takes one away now and then) then takes
// fewer ranges instead of keeping the other waiting at the loop's barrier. On 2 threads, libgomp
// held 10-14 % of a float dam break's samples (particle walls, r = 0.025) with one range per
// thread, 9-11 % with four, 6 % with eight, 5 % with sixteen (bench/RESULTS.md, "Ranges taken as
// the threads come").
inline constexpr std::size_t kRangesPerThread = 8;
inline std::size_t workChunkCount() {
#ifdef _OPENMP
  return kRangesPerThread * std::size_t(omp_get_max_threads());
#else
  return 1;
#endif
}

// How many chunks parallelChunks may hand out: one per thread a parallel region may have.
inline std::size_t parallelChunkCount() {
#ifdef _OPENMP
  return std::size_t(omp_get_max_threads());
#else
  return 1;
#endif
}

// body(chunk, begin, end) once per thread, over the contiguous chunk [begin, end) of [0, n)
// that OpenMP's static schedule gives thread `chunk` (the first n % threads take one more), so
// that a loop over [begin, end) adds in the order parallelFor's and parallelReduce's would.
// Empty chunks are called too (a body may reset its buffer).
template <class Body>
void parallelChunks(std::size_t n, Body&& body) {
#ifdef _OPENMP
#pragma omp parallel
  {
    const std::size_t t = std::size_t(omp_get_thread_num()), threads = std::size_t(omp_get_num_threads());
    const std::size_t q = n / threads, r = n % threads;
    const std::size_t begin = t * q + std::min(t, r);
    body(t, begin, begin + q + (t < r ? 1 : 0));
  }
#else
  body(std::size_t(0), std::size_t(0), n);
#endif
}

namespace parallel_detail {
// One accumulator per thread, folded in thread order after the loop; chunk 0: static schedule.
template <class T, class Join, class Body>
T reduce(std::size_t n, T identity, Join& join, Body& body, std::size_t chunk) {
  T result = identity;
#ifdef _OPENMP
  // One slot per thread (a struct: std::vector<bool> packs bits that threads would share).
  struct Slot {
    T value;
  };
  std::vector<Slot> partial(std::size_t(omp_get_max_threads()), Slot{identity});
  int team = 1;
#pragma omp parallel
  {
    T local = identity;
    if (chunk == 0) {
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) body(i, local);
    } else {
#pragma omp for schedule(dynamic, chunk)
      for (std::size_t i = 0; i < n; ++i) body(i, local);
    }
    const int t = omp_get_thread_num();
    partial[std::size_t(t)].value = std::move(local);
    if (t == 0) team = omp_get_num_threads();
  }
  for (int t = 0; t < team; ++t) join(result, partial[std::size_t(t)].value);
#else
  for (std::size_t i = 0; i < n; ++i) body(i, result);
#endif
  return result;
}
}  // namespace parallel_detail

// body(i, acc) for every i in [0, n), static schedule, into one accumulator per thread that
// starts as a copy of `identity`; then identity, joined with every thread's accumulator in
// thread order by join(into, from), is returned. `identity` must be neutral for join (0 for a
// sum, the lowest value or a known lower bound for a max).
template <class T, class Join, class Body>
T parallelReduce(std::size_t n, T identity, Join&& join, Body&& body) {
  return parallel_detail::reduce(n, std::move(identity), join, body, 0);
}

// parallelReduce with a dynamic schedule (chunks of `chunk`): which thread adds which index
// changes from run to run, so only for joins whose result does not depend on the grouping
// (integer counts, min, max, flags), never for floating-point sums.
template <class T, class Join, class Body>
T parallelReduceDynamic(std::size_t n, T identity, Join&& join, Body&& body, std::size_t chunk = 256) {
  return parallel_detail::reduce(n, std::move(identity), join, body, std::max<std::size_t>(chunk, 1));
}

// The sum of f(i) over [0, n), accumulated in T (f's value is converted to T before it is added).
template <class T, class F>
T parallelSum(std::size_t n, F&& f) {
  return parallelReduce(n, T(0), [](T& into, const T& from) { into += from; }, [&](std::size_t i, T& acc) { acc += f(i); });
}

// max(init, f(0), ..., f(n-1)); a NaN f(i) is skipped (std::max keeps the accumulator).
template <class T, class F>
T parallelMax(std::size_t n, T init, F&& f) {
  return parallelReduce(n, init, [](T& into, const T& from) { into = std::max(into, from); },
                        [&](std::size_t i, T& acc) { acc = std::max<T>(acc, f(i)); });
}

// Whether pred(i) holds for some i in [0, n). Each thread stops calling pred once it has found
// one, so pred must have no side effects the caller relies on.
template <class Pred>
bool parallelAny(std::size_t n, Pred&& pred) {
  return parallelReduce(n, false, [](bool& into, bool from) { into = into || from; }, [&](std::size_t i, bool& found) {
    if (!found && pred(i)) found = true;
  });
}

// [0, n) cut into contiguous ranges (workChunkCount(): a few per thread), each holding about an
// equal share of a cost per index, for loops whose iterations cost unevenly in a way known before
// the loop (a particle's neighbour pairs). In a Z-sorted dam break at r = 0.025 the first half of
// the particles held 1.03-1.30x the pairs of the second half over its first second (counted), so
// an equal split leaves one thread up to 13 % more pairs in every loop over the lists while the
// other waits at the barrier. Equal shares alone did not move the 2-core VM's wall time beyond its
// noise (bench/RESULTS.md, "Pair gradients as factors, loops balanced by pairs"): its threads do
// not run at one speed, so the ranges are handed out as the threads come for them (forEachChunk).
// A dynamic schedule over single particles measured slower (a cost per chunk); over a few ranges
// per thread it costs one atomic fetch per range. Deterministic: the ranges depend on the costs
// and the thread count only, and a reduction joins them in range order.
class WorkPartition {
 public:
  // `chunks` ranges over [0, n), cut where the cumulative cost, cumulative(i) = the
  // cost of [0, i) (non-decreasing, cumulative(0) = 0), crosses each equal share.
  template <class Cumulative>
  void balance(std::size_t n, std::size_t chunks, Cumulative&& cumulative) {
    chunks = std::max<std::size_t>(chunks, 1);
    bounds_.assign(chunks + 1, n);
    bounds_[0] = 0;
    const double total = double(cumulative(n));
    for (std::size_t t = 1; t < chunks; ++t) {
      const double share = total * double(t) / double(chunks);
      // The first i from the previous bound on whose cumulative cost reaches the share.
      std::size_t lo = bounds_[t - 1], hi = n;
      while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (double(cumulative(mid)) < share)
          lo = mid + 1;
        else
          hi = mid;
      }
      bounds_[t] = lo;
    }
  }
  std::size_t size() const { return bounds_.empty() ? 0 : bounds_.back(); }
  std::size_t chunks() const { return bounds_.empty() ? 0 : bounds_.size() - 1; }
  std::size_t begin(std::size_t chunk) const { return bounds_[chunk]; }
  std::size_t end(std::size_t chunk) const { return bounds_[chunk + 1]; }

 private:
  std::vector<std::size_t> bounds_;  // (chunks + 1)
};

namespace parallel_detail {
// body(chunk, begin, end) for every chunk of `work`, each thread of the team taking the next
// chunk when it is done with its last (a dynamic schedule over the chunks: which thread runs a
// chunk changes from run to run, what the chunk computes does not).
template <class Body>
void forEachChunk(const WorkPartition& work, Body&& body) {
  const std::size_t chunks = work.chunks();
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t c = 0; c < chunks; ++c) body(c, work.begin(c), work.end(c));
#else
  for (std::size_t c = 0; c < chunks; ++c) body(c, work.begin(c), work.end(c));
#endif
}
}  // namespace parallel_detail

// f(i) for every i in [0, n), each thread over its range of `work`; an equal split (parallelFor(n,
// f)) where `work` does not cover exactly [0, n) (lists built before particles were added).
template <class F>
void parallelFor(const WorkPartition& work, std::size_t n, F&& f) {
  if (work.size() != n) return parallelFor(n, f);
  parallel_detail::forEachChunk(work, [&](std::size_t, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) f(i);
  });
}

// parallelReduce over `work`'s ranges: one accumulator per range, joined in range order (the
// same bits for the same partition, whatever team runs it); parallelReduce(n, ...) where `work`
// does not cover exactly [0, n).
template <class T, class Join, class Body>
T parallelReduce(const WorkPartition& work, std::size_t n, T identity, Join&& join, Body&& body) {
  if (work.size() != n) return parallelReduce(n, std::move(identity), join, body);
  struct Slot {  // a struct: std::vector<bool> packs bits that threads would share
    T value;
  };
  std::vector<Slot> partial(work.chunks(), Slot{identity});
  parallel_detail::forEachChunk(work, [&](std::size_t c, std::size_t b, std::size_t e) {
    T local = identity;
    for (std::size_t i = b; i < e; ++i) body(i, local);
    partial[c].value = std::move(local);
  });
  T result = std::move(identity);
  for (Slot& p : partial) join(result, p.value);
  return result;
}

// The sum of f(i) over [0, n) in T, over `work`'s ranges.
template <class T, class F>
T parallelSum(const WorkPartition& work, std::size_t n, F&& f) {
  return parallelReduce(work, n, T(0), [](T& into, const T& from) { into += from; }, [&](std::size_t i, T& acc) { acc += f(i); });
}

// body(chunk, begin, end) once per range of `work`, as parallelChunks(n, body) does per thread.
template <class Body>
void parallelChunks(const WorkPartition& work, Body&& body) {
  parallel_detail::forEachChunk(work, body);
}

}  // namespace consph
