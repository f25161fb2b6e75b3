#!/usr/bin/env bash
# The C++ unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (issue 16), in their own
# build folder build-asan/ (gcc, -O2 -g, Python module off). Not in .ci/run: the sanitized suite
# takes far longer than CI's budget on 2 cores (bench/RESULTS.md has the measured durations).
# -O2, not -O1: at -O1 Eigen's expressions are not inlined and the physics tests ran ~50 times
# slower than Release (44 tests in 44 min on 2 cores); reports still carry file and line.
#   bench/sanitize.sh [GTEST_FILTER]      e.g. bench/sanitize.sh 'TriangleBvh*:MeshSampling*'
# JOBS=N sets the build parallelism (default 1, which leaves the other core free).
# Exits non-zero on the first sanitizer report (halt_on_error) or failing test.
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-*}
start=$(date +%s)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCONSPH_NATIVE=OFF -DCONSPH_BUILD_PYTHON=OFF \
  -DCONSPH_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
nice -n 10 ninja -j"${JOBS:-1}" -C build-asan consph_tests
built=$(date +%s)
# Leak checking off: libgomp's thread pool lives until exit and is reported as leaked.
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=0:abort_on_error=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
nice -n 10 build-asan/tests/consph_tests --gtest_filter="$filter" --gtest_brief=1
echo "sanitize.sh: build $((built - start)) s, tests $(( $(date +%s) - built )) s (filter '$filter')"
