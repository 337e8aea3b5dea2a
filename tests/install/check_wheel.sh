#!/usr/bin/env bash
# The Python package as pip makes it: a wheel built from the checkout (pyproject.toml, setup.py;
# through the existing CMake build BUILD_DIR, whose targets are up to date), installed into a fresh
# virtual environment (--system-site-packages: Debian's NumPy, pytest, Dask), then, from outside the
# source tree, imported, its `visfield` command run, the Python tests run against it, and mypy
# (Debian's) run over the examples with its types.
set -euo pipefail
build_dir=$(cd "$1" && pwd) source_dir=$(cd "$2" && pwd) work=$3
rm -rf "$work" && mkdir -p "$work"
work=$(cd "$work" && pwd)
python=$(sed -n 's/^PYTHON_EXECUTABLE:FILEPATH=//p' "$build_dir/CMakeCache.txt")
python=${python:-/usr/bin/python3}

(cd "$source_dir" && VISFIELD_BUILD_DIR="$build_dir" "$python" -m pip wheel -q --no-build-isolation --no-deps -w "$work/wheel" .)
wheel=$(ls "$work"/wheel/visfield-*.whl)
echo "wheel: $(basename "$wheel")"
"$python" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip install -q --no-index --no-deps "$wheel"

cd /
"$work/venv/bin/python" -c 'import sys, visfield; assert visfield.__file__.startswith(sys.prefix), visfield.__file__; print("import:", visfield.__file__)'
"$work/venv/bin/visfield" info builtin:sphere | grep "^kernels:"
# The tests against the installed package: no PYTHONPATH, run from / (the checkout is not on the path).
env -u PYTHONPATH "$work/venv/bin/python" -m pytest -q -p no:cacheprovider --basetemp="$work/pytest" "$source_dir/tests/python"
echo "tests against the wheel: ok"
command -v mypy >/dev/null || { echo "check_wheel: error: no mypy (scripts/install-deps.sh --all installs it)" >&2; exit 1; }
mypy --config-file "$source_dir/pyproject.toml" --python-executable "$work/venv/bin/python" --no-incremental --cache-dir=/dev/null \
  --check-untyped-defs "$source_dir/examples/python"
echo "mypy: ok"
