// A copy of the fluid's neighbour lists whose rows are padded to whole blocks of kPairBlock pairs
// (Utilities/SimdLanes.h), for the sums that take a block of pairs at a time (DFSPH's iterations,
// the standard viscosity). Row i is [offsets[i], offsets[i + 1]): its listed pairs in their order,
// then j = i with a gradient factor 0, whose terms in those sums are exactly zero.
// Why padded rather than a row's last, partial block handled apart: with masked loads, or a scalar
// loop for the remainder, the sums gained almost nothing over the scalar loops: two loops of
// varying length per particle mispredict their exits, and a partial block costs as much as a full
// one (bench/pair_loops.cpp; bench/RESULTS.md, "Packed pair sums"). The padding adds about 11 %
// lanes at DamBreak's 27-30 neighbours.
// Built by the simulation once per step after the neighbour search (StepContext::
// paddedFluidNeighbors), from lists with PairGradients::Factors.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "Simulation/NeighborSearch.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/SimdLanes.h"

namespace consph {

struct PaddedNeighborLists {
  std::vector<Index> offsets;  // (n + 1)
  std::vector<Index> indices;
  std::vector<Real> gradFactors;

  Index begin(std::size_t i) const { return offsets[i]; }
  Index end(std::size_t i) const { return offsets[i + 1]; }

  // For a reader's first use in a step: the lists must have been built for n particles, which the
  // simulation does only when a plugin says it reads them (readsPaddedNeighbors).
  void expectBuiltFor(std::size_t n, const char* reader) const {
    if (offsets.size() != n + 1)
      throw std::logic_error(std::string(reader) + " reads the padded neighbour lists, which were not built for this step: "
                             "its readsPaddedNeighbors() must return true");
  }

  void build(const NeighborLists& lists) {
    const std::size_t n = lists.queryCount();
    offsets.resize(n + 1);
    offsets[0] = 0;
    for (std::size_t i = 0; i < n; ++i) offsets[i + 1] = offsets[i] + (lists.count(i) + kPairBlock - 1) / kPairBlock * kPairBlock;
    indices.resize(offsets[n]);
    gradFactors.resize(offsets[n]);
    // One loop per row, listed pairs and padding together: std::copy_n and std::fill per row (four
    // library calls on rows of ~30 entries) made this build cost 3 ms per step at 80 k particles.
    parallelFor(lists.work, n, [&](std::size_t i) {
      const Index listed = lists.count(i), padded = offsets[i + 1] - offsets[i];
      const Index* fromIndices = lists.indices.data() + lists.begin(i);
      const Real* fromFactors = lists.gradFactors.data() + lists.begin(i);
      Index* toIndices = indices.data() + offsets[i];
      Real* toFactors = gradFactors.data() + offsets[i];
      for (Index k = 0; k < padded; ++k) {
        toIndices[k] = k < listed ? fromIndices[k] : Index(i);
        toFactors[k] = k < listed ? fromFactors[k] : Real(0);
      }
    });
  }
};

}  // namespace consph
