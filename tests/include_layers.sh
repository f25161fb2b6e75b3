#!/usr/bin/env bash
# The include layers (issue 17): Utilities/ is the bottom layer and includes nothing from
# Simulation/, Boundary/, Plugins/ or pysph_bindings/; no C++ file outside pysph_bindings/
# includes the bindings; Simulation/ includes nothing from Boundary/ or Plugins/ (it sees them
# through its interfaces: BoundaryModel, MovingBodies, PressureSolver, NonPressureForce); and no
# OpenMP parallel region outside Utilities/ParallelFor.h (the one dispatch for particle loops).
# Usage: tests/include_layers.sh [SOURCE_DIR]   (ctest: include_layers)
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"
for d in Utilities Simulation Boundary Plugins pysph_bindings; do
  [ -d "$d" ] || { echo "include_layers: no $d/ in $(pwd)" >&2; exit 2; }
done

# includes DIRS... -- LAYERS: the '#include "LAYER/..."' (or <LAYER/...>) lines in the C++ files of DIRS.
includes() {
  local dirs=()
  while [ "$1" != "--" ]; do dirs+=("$1"); shift; done
  shift
  local layers
  layers=$(IFS='|'; echo "$*")
  grep -rnE --include='*.h' --include='*.hpp' --include='*.cpp' \
    "^[[:space:]]*#[[:space:]]*include[[:space:]]*[\"<]($layers)/" "${dirs[@]}" || true
}

failed=0
report() {  # report TITLE LINES
  [ -z "$2" ] && return 0
  echo "$1:"
  echo "$2" | sed 's/^/  /'
  failed=1
}
report "Utilities/ includes a layer above it" "$(includes Utilities -- Simulation Boundary Plugins pysph_bindings)"
others=()
for d in */; do
  d=${d%/}
  case "$d" in pysph_bindings | build* | output* | .*) continue ;; esac
  others+=("$d")
done
report "C++ outside pysph_bindings/ includes the bindings" "$(includes "${others[@]}" -- pysph_bindings)"

report "Simulation/ includes an implementation layer (it sees Boundary/ and Plugins/ through its interfaces)" \
  "$(includes Simulation -- Boundary Plugins)"
# One dispatch for particle loops (issue 17): OpenMP parallel regions only in Utilities/ParallelFor.h.
raw=$(grep -rnE --include='*.h' --include='*.hpp' --include='*.cpp' '^[[:space:]]*#[[:space:]]*pragma[[:space:]]+omp[[:space:]]+parallel' \
  Utilities Simulation Boundary Plugins pysph_bindings bench 2>/dev/null | grep -v '^Utilities/ParallelFor.h:' || true)
report "a parallel loop outside the dispatch (use Utilities/ParallelFor.h)" "$raw"
if [ "$failed" -ne 0 ]; then
  echo "include_layers: FAILED"
  exit 1
fi
echo "include_layers: ok"
