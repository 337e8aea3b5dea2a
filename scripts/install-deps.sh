#!/usr/bin/env bash
# Installs the Debian packages visfield needs (Debian 12, as root).
#   scripts/install-deps.sh         what building and running `visfield` needs (the README's first command)
#   scripts/install-deps.sh --print [--all]   the packages it would install, one line, nothing installed
#   scripts/install-deps.sh --all   that and what the tests, the benchmark, the Python module, the fuzz
#                                   targets and the sanitizer runs need (the README's second command, CI):
#                                   GoogleTest, Google Benchmark, Embree, pybind11 and NumPy, pytest, hypothesis, Dask,
#                                   matplotlib, pip, venv, setuptools and wheel (the Python package), mypy, clang-14 and its runtime (libFuzzer, docs/fuzzing.md),
#                                   valgrind (scripts/count-instructions.py, docs/benchmark.md)
# Safe to run twice: when everything is already installed it only checks and returns.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  libtbb-dev libassimp-dev libstb-dev libopenexr-dev nlohmann-json3-dev libcli11-dev
)
print=0
if [[ "${1:-}" == --print ]]; then
  print=1
  shift
fi
case "${1:-}" in
  "") ;;
  --all)
    packages+=(
      libgtest-dev libgmock-dev libbenchmark-dev libembree-dev pybind11-dev
      python3 python3-dev python3-numpy python3-pytest python3-hypothesis python3-distributed python3-matplotlib
      python3-pip python3-venv python3-setuptools python3-wheel mypy
      clang-14 libclang-rt-14-dev valgrind
    )
    ;;
  *)
    echo "install-deps: error: unknown option '$1' (none, --all, --print)" >&2
    exit 2
    ;;
esac

if [[ $print == 1 ]]; then
  echo "${packages[*]}"
  exit 0
fi

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
