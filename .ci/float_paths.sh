#!/usr/bin/env bash
# Float builds take code paths double builds do not: the packed pair sums (kPackedPairSums), the
# neighbour search's packed squared distances (kPacksSquaredDistances). The main suite is double,
# so this builds the tests in float without -march=native (the portable fallbacks of that SIMD
# code, which no benchmark machine takes) and runs the unit tests of those paths.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f build-float-portable/CMakeCache.txt ]; then
  cmake -S . -B build-float-portable "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DCONSPH_DOUBLE=OFF -DCONSPH_NATIVE=OFF \
    -DPython_EXECUTABLE=/usr/bin/python3
fi
cmake --build build-float-portable -j "$(nproc)" --target consph_tests
build-float-portable/tests/consph_tests --gtest_brief=1 \
  --gtest_filter='NeighborSearch.*:CubicSplineKernel.*:PackedPairSums.*:ParallelFor.*:DFSPH*.*'
