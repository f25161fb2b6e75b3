#!/usr/bin/env bash
# The README's second command: build and run every test (GoogleTest and pytest, via ctest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup.sh
bash .ci/build.sh
# One test at a time: each physics test already uses every core through OpenMP. The pytest
# suite (tests/python) runs as the ctest entry python_tests.
(cd build && ctest --output-on-failure)
# The float-only code paths' unit tests, in a portable float build (.ci/float_paths.sh).
bash .ci/float_paths.sh
