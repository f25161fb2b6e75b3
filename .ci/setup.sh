#!/usr/bin/env bash
# Installs consph's build dependencies from Debian's packages: only what is missing, so running
# it again costs nothing. No PyPI, no downloads at build time.
set -euo pipefail
packages=(build-essential cmake ninja-build libeigen3-dev nlohmann-json3-dev libassimp-dev libgtest-dev
          pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib zlib1g-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all dependencies present"
  exit 0
fi
echo "setup: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
