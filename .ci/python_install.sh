#!/usr/bin/env bash
# The README's Python install, checked: `cmake --install BUILD --component python --prefix VENV`
# into a fresh venv (with the system's site-packages, for Debian's NumPy), then import consph
# from outside the source and build trees and read a signature from the installed stub.
# Usage: .ci/python_install.sh [BUILD] [PYTHON]   (defaults: build, /usr/bin/python3)
set -euo pipefail
build="$(cd "${1:-build}" && pwd)"
python="${2:-/usr/bin/python3}"
venv="$(mktemp -d)/venv"
trap 'rm -rf "$(dirname "$venv")"' EXIT
"$python" -m venv --system-site-packages --without-pip "$venv"
cmake --install "$build" --component python --prefix "$venv" >/dev/null
cd "$(dirname "$venv")"
env -u PYTHONPATH "$venv/bin/python" - "$venv" <<'PY'
import os, sys
import consph
venv = os.path.realpath(sys.argv[1])
where = os.path.realpath(consph.__file__)
assert where.startswith(venv + os.sep), f"consph imported from {where}, not from the venv {venv}"
stub = os.path.join(os.path.dirname(where), "_consph.pyi")
text = open(stub).read()
assert "def step(self, n: int = 1) -> None:" in text, "the installed stub lacks Simulation.step's signature"
assert os.path.exists(os.path.join(os.path.dirname(where), "py.typed"))
sim = consph.Simulation.from_dict({"fluids": [{"blocks": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}]}]}, output=False)
sim.step()
print(f"python install: consph {consph.__version__} ({consph.precision}) from {where}: ok")
PY
