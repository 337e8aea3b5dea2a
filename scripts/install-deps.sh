#!/usr/bin/env bash
# Installs every Debian package visfield needs to build, test, benchmark and fuzz (Debian 12, as root;
# clang-14 and its runtime are for the libFuzzer targets, see docs/fuzzing.md; the python3 packages
# for the Python module, its tests, its Dask renders and its examples).
# Safe to run twice: when everything is already installed it only checks and returns.
set -euo pipefail

packages=(
  build-essential cmake pkg-config python3
  libtbb-dev libassimp-dev libstb-dev libopenexr-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev libembree-dev pybind11-dev
  python3-dev python3-numpy python3-pytest python3-distributed python3-matplotlib
  clang-14 libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: error: missing packages (${missing[*]}); run as root or with sudo" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"
