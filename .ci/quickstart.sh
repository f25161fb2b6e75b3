#!/usr/bin/env bash
# The README's first command: set up, build, and run the bundled dam break into output/DamBreak.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup.sh
bash .ci/build.sh
# --overwrite: running it again replaces the previous run's frames.
./build/consph data/scenes/DamBreak.json --output-dir output/DamBreak --overwrite "$@"
echo "frames: output/DamBreak/water.pvd (open in ParaView)"
