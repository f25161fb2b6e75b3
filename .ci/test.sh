#!/usr/bin/env bash
# The README's second command: build and run every test (GoogleTest via ctest, then pytest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup.sh
bash .ci/build.sh
(cd build && ctest --output-on-failure -j "$(nproc)")
if [ -d tests/python ] && ls tests/python/test_*.py >/dev/null 2>&1; then
  PYTHONPATH="$PWD/build/python" /usr/bin/python3 -m pytest -q tests/python
fi
