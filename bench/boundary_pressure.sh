#!/bin/bash
# Issue 3 benchmark (boundary pressure treatments x DFSPH/IISPH on SphereDrop): see boundary_pressure.py.
set -euo pipefail
cd "$(dirname "$0")/.."
exec /usr/bin/python3 bench/boundary_pressure.py "$@"
