// Utilities/ParallelFor.h, the one dispatch for particle loops: every index visited exactly once
// (n = 0, 1, fewer than the threads, large), and reductions that match a serial loop over each
// thread's chunk joined in thread order, so that they repeat bit for bit.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdint>
#include <limits>
#include <vector>

#include "Utilities/ParallelFor.h"

using namespace consph;

namespace {

// Runs the test body with `threads` OpenMP threads and restores the previous count.
struct Threads {
  int before = omp_get_max_threads();
  explicit Threads(int n) { omp_set_num_threads(n); }
  ~Threads() { omp_set_num_threads(before); }
};

const std::size_t kSizes[] = {0, 1, 2, 3, 7, 1000, 100003};
const int kThreadCounts[] = {1, 2, 3, 4};

// A value per index whose sum is sensitive to the order of the additions.
double term(std::size_t i) { return 1.0 / (1.0 + double(i)) * (i % 3 == 0 ? -1.0 : 1.0) + 1e-9 * double(i % 17); }

}  // namespace

TEST(ParallelFor, VisitsEveryIndexOnce) {
  for (int threads : kThreadCounts) {
    Threads t(threads);
    for (std::size_t n : kSizes) {
      std::vector<int> visits(n, 0);
      parallelFor(n, [&](std::size_t i) { ++visits[i]; });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(visits[i], 1) << "n = " << n << ", i = " << i << ", " << threads << " threads";
      std::vector<int> dynamicVisits(n, 0);
      parallelForDynamic(n, [&](std::size_t i) { ++dynamicVisits[i]; }, 5);
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(dynamicVisits[i], 1) << "n = " << n << ", i = " << i << ", " << threads << " threads";
    }
  }
}

TEST(ParallelFor, StaticScheduleGivesEachThreadOneContiguousChunkInThreadOrder) {
  // What the reductions rely on (and OpenMP's schedule(static) guarantees).
  Threads t(3);
  const std::size_t n = 1000;
  std::vector<int> owner(n, -1);
  parallelFor(n, [&](std::size_t i) { owner[i] = omp_get_thread_num(); });
  for (std::size_t i = 1; i < n; ++i) EXPECT_LE(owner[i - 1], owner[i]) << i;
}

TEST(ParallelFor, SumMatchesTheChunkedSerialSum) {
  for (int threads : kThreadCounts) {
    Threads t(threads);
    for (std::size_t n : kSizes) {
      // Which thread owns which index (one contiguous chunk each), then a serial sum per chunk,
      // the chunks' sums added in thread order.
      std::vector<int> owner(n, -1);
      parallelFor(n, [&](std::size_t i) { owner[i] = omp_get_thread_num(); });
      std::vector<double> chunkSums(std::size_t(threads), 0.0);
      for (std::size_t i = 0; i < n; ++i) chunkSums[std::size_t(owner[i])] += term(i);
      double expected = 0;
      for (double s : chunkSums) expected += s;
      const double sum = parallelSum<double>(n, term);
      EXPECT_EQ(sum, expected) << "n = " << n << ", " << threads << " threads";
      EXPECT_EQ(parallelSum<double>(n, term), sum) << "repeats bit for bit";
    }
  }
}

TEST(ParallelFor, SumConvertsEachTermToTheAccumulatorType) {
  // float terms summed in double, as `double s; s += float(x)` would.
  Threads t(2);
  const std::size_t n = 4096;
  auto f = [](std::size_t i) { return float(1.0 / (1.0 + double(i))); };
  double serialHalves[2] = {0, 0};
  for (std::size_t i = 0; i < n; ++i) serialHalves[i < n / 2 ? 0 : 1] += f(i);
  EXPECT_EQ(parallelSum<double>(n, f), serialHalves[0] + serialHalves[1]);
}

TEST(ParallelFor, MaxAnyAndEmptyRanges) {
  for (int threads : kThreadCounts) {
    Threads t(threads);
    EXPECT_EQ(parallelSum<double>(0, term), 0.0);
    EXPECT_EQ(parallelMax<double>(0, -1.5, term), -1.5);
    EXPECT_FALSE(parallelAny(0, [](std::size_t) { return true; }));
    EXPECT_EQ(parallelSum<double>(1, term), term(0));
    EXPECT_EQ(parallelMax<double>(1, -1e9, term), term(0));

    const std::size_t n = 100003;
    double serialMax = 0;
    for (std::size_t i = 0; i < n; ++i) serialMax = std::max(serialMax, term(i));
    EXPECT_EQ(parallelMax<double>(n, 0.0, term), serialMax);
    EXPECT_EQ(parallelMax<double>(n, 10.0, term), 10.0) << "init is a lower bound";
    // NaN terms are skipped, as std::max(acc, NaN) keeps acc: the max over the even indices.
    double evenMax = 0;
    for (std::size_t i = 0; i < n; i += 2) evenMax = std::max(evenMax, term(i));
    EXPECT_EQ(parallelMax<double>(n, 0.0, [&](std::size_t i) { return i % 2 ? std::numeric_limits<double>::quiet_NaN() : term(i); }),
              evenMax);

    for (std::size_t hit : {std::size_t(0), n / 2, n - 1}) EXPECT_TRUE(parallelAny(n, [&](std::size_t i) { return i == hit; })) << hit;
    EXPECT_FALSE(parallelAny(n, [](std::size_t) { return false; }));
  }
}

TEST(ParallelFor, ReduceJoinsSeveralAccumulatorsAndArrays) {
  struct Stats {
    double sum = 0, max = 0;
    std::int64_t count = 0;
  };
  auto join = [](Stats& into, const Stats& from) {
    into.sum += from.sum;
    into.max = std::max(into.max, from.max);
    into.count += from.count;
  };
  for (int threads : kThreadCounts) {
    Threads t(threads);
    const std::size_t n = 10007;
    const Stats s = parallelReduce(n, Stats{}, join, [](std::size_t i, Stats& acc) {
      acc.sum += double(i);  // exact in double
      acc.max = std::max(acc.max, double(i % 101));
      if (i % 7 == 0) ++acc.count;
    });
    EXPECT_EQ(s.sum, double(n - 1) * double(n) / 2);
    EXPECT_EQ(s.max, 100.0);
    EXPECT_EQ(s.count, std::int64_t((n + 6) / 7));

    // An array reduction (per-slot sums, as the probes use) and a dynamic one with exact joins.
    auto addSlots = [](std::vector<std::int64_t>& into, const std::vector<std::int64_t>& from) {
      for (std::size_t k = 0; k < into.size(); ++k) into[k] += from[k];
    };
    const std::vector<std::int64_t> zeros(5, 0);
    const auto slots = parallelReduce(n, zeros, addSlots, [](std::size_t i, std::vector<std::int64_t>& acc) { acc[i % 5] += 1; });
    const auto slotsDynamic =
        parallelReduceDynamic(n, zeros, addSlots, [](std::size_t i, std::vector<std::int64_t>& acc) { acc[i % 5] += 1; }, 3);
    for (std::size_t k = 0; k < 5; ++k) {
      const std::int64_t expected = std::int64_t(n / 5 + (k < n % 5 ? 1 : 0));
      EXPECT_EQ(slots[k], expected) << k;
      EXPECT_EQ(slotsDynamic[k], expected) << k;
    }
  }
}

TEST(ParallelFor, ChunksAreParallelForsThreadChunksInIndexOrder) {
  // parallelChunks hands each thread the chunk parallelFor's static schedule gives it, so a
  // per-chunk buffer filled over [begin, end) and joined in chunk order adds exactly as
  // parallelSum does, and concatenated lists come out in index order.
  for (int threads : kThreadCounts) {
    Threads t(threads);
    for (std::size_t n : kSizes) {
      std::vector<int> owner(n, -1);
      parallelFor(n, [&](std::size_t i) { owner[i] = omp_get_thread_num(); });
      const std::size_t chunks = parallelChunkCount();
      ASSERT_EQ(chunks, std::size_t(threads));
      std::vector<std::vector<std::size_t>> lists(chunks);
      std::vector<double> sums(chunks, 0.0);
      std::vector<int> calls(chunks, 0);
      parallelChunks(n, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
        ++calls[chunk];
        for (std::size_t i = begin; i < end; ++i) {
          lists[chunk].push_back(i);
          sums[chunk] += term(i);
          EXPECT_EQ(owner[i], int(chunk)) << "n = " << n << ", i = " << i << ", " << threads << " threads";
        }
      });
      std::vector<std::size_t> joined;
      double sum = 0;
      for (std::size_t c = 0; c < chunks; ++c) {
        EXPECT_EQ(calls[c], 1) << "every chunk once, empty ones too (n = " << n << ")";
        joined.insert(joined.end(), lists[c].begin(), lists[c].end());
        sum += sums[c];
      }
      ASSERT_EQ(joined.size(), n);
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(joined[i], i);
      EXPECT_EQ(sum, parallelSum<double>(n, term)) << "n = " << n << ", " << threads << " threads";
    }
  }
}

TEST(ParallelFor, WorkPartitionSplitsByCostIntoContiguousRanges) {
  // Costs like a dam break's neighbour lists: the first half of the indices twice as costly.
  for (int threads : kThreadCounts) {
    Threads t(threads);
    for (std::size_t n : kSizes) {
      std::vector<std::size_t> cumulative(n + 1, 0);
      for (std::size_t i = 0; i < n; ++i) cumulative[i + 1] = cumulative[i] + (i < n / 2 ? 2 : 1);
      WorkPartition work;
      work.balance(n, parallelChunkCount(), [&](std::size_t i) { return cumulative[i]; });
      ASSERT_EQ(work.size(), n);
      ASSERT_EQ(work.chunks(), std::size_t(threads));
      // Contiguous, in order, covering [0, n); each range's cost within one index's cost of an
      // equal share.
      const double share = double(cumulative[n]) / threads;
      for (std::size_t c = 0; c < work.chunks(); ++c) {
        EXPECT_EQ(work.begin(c), c == 0 ? 0 : work.end(c - 1));
        EXPECT_LE(work.begin(c), work.end(c));
        if (n >= 1000) {
          EXPECT_NEAR(double(cumulative[work.end(c)] - cumulative[work.begin(c)]), share, 2.0) << c;
        }
      }
      // Every index once; the reduction is the serial sum over each range, joined in range order
      // (the same bits whatever team runs it, a smaller one too).
      std::vector<int> visits(n, 0);
      parallelFor(work, n, [&](std::size_t i) { ++visits[i]; });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(visits[i], 1) << "n = " << n << ", i = " << i;
      double expected = 0;
      for (std::size_t c = 0; c < work.chunks(); ++c) {
        double part = 0;
        for (std::size_t i = work.begin(c); i < work.end(c); ++i) part += term(i);
        expected += part;
      }
      EXPECT_EQ(parallelSum<double>(work, n, term), expected) << "n = " << n << ", " << threads << " threads";
      {
        Threads fewer(1);
        EXPECT_EQ(parallelSum<double>(work, n, term), expected) << "one thread running " << threads << " ranges";
      }
      // A partition of another size is not used: the loop falls back to equal chunks.
      std::vector<int> more(n + 1, 0);
      parallelFor(work, n + 1, [&](std::size_t i) { ++more[i]; });
      for (std::size_t i = 0; i <= n; ++i) ASSERT_EQ(more[i], 1);
    }
  }
}
