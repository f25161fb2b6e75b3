#!/usr/bin/env bash
# Fuzzes the scene reader with libFuzzer + ASan + UBSan for MINUTES minutes (default 5), seeded
# with the bundled scenes (issue 16). Needs clang (Debian package clang). Builds build-fuzz/
# (only the parser's sources), keeps the growing corpus in build-fuzz/corpus and writes any
# crashing input to build-fuzz/findings/ (the run then exits non-zero).
#   bench/fuzz_scene.sh [MINUTES] [extra libFuzzer flags, e.g. -jobs=2]
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-5}
shift || true
command -v clang++ >/dev/null || { echo "fuzz_scene.sh: clang++ not found (apt-get install clang)" >&2; exit 2; }
cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCONSPH_FUZZ=ON \
  -DCONSPH_BUILD_TESTS=OFF -DCONSPH_BUILD_PYTHON=OFF -DCONSPH_BUILD_BENCH=OFF -DCONSPH_NATIVE=OFF >/dev/null
nice -n 10 ninja -j1 -C build-fuzz scene_parser_fuzzer
mkdir -p build-fuzz/corpus build-fuzz/findings
cp -n data/scenes/*.json build-fuzz/corpus/
start=$(date +%s)
set +e
nice -n 10 build-fuzz/tests/fuzz/scene_parser_fuzzer -max_total_time=$((minutes * 60)) -timeout=10 -rss_limit_mb=2048 \
  -max_len=65536 -print_final_stats=1 -artifact_prefix=build-fuzz/findings/ "$@" build-fuzz/corpus 2>&1 | tail -25
status=${PIPESTATUS[0]}
set -e
echo "fuzz_scene.sh: ran $(( $(date +%s) - start )) s, exit $status, corpus $(ls build-fuzz/corpus | wc -l) inputs," \
     "findings: $(ls build-fuzz/findings | wc -l) (build-fuzz/findings/)"
exit $status
