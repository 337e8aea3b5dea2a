#!/usr/bin/env bash
# Installs the build tree into a temporary prefix, then configures, builds and runs the examples
# against it: the C++ one (examples/cpp) through find_package, and the C example built once through
# find_package and once through pkg-config alone.
set -euo pipefail
build_dir=$1 source_dir=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
prefix="$work/prefix"
cmake --install "$build_dir" --prefix "$prefix" >/dev/null
cmake -S "$source_dir/examples/cpp" -B "$work/cpp" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/cpp" -j2 >/dev/null
"$work/cpp/trace" builtin:sphere bvh
"$work/cpp/trace" builtin:boxes beam:dirs=33,n=16 >/dev/null

example="$(cd "$source_dir" && pwd)/examples/c/visfield_example.c"
cmake -S "$source_dir/tests/install/c_consumer" -B "$work/c_consumer" -DCMAKE_PREFIX_PATH="$prefix" -DEXAMPLE="$example" >/dev/null
cmake --build "$work/c_consumer" -j2 >/dev/null
LD_LIBRARY_PATH="$prefix/lib:${LD_LIBRARY_PATH:-}" "$work/c_consumer/c_consumer" >/dev/null
echo "C example through find_package: ok"

# pkg-config knows the prefix the build was configured with; point it at this one.
libdir=$(ls -d "$prefix"/lib*/pkgconfig | head -1)
flags=$(PKG_CONFIG_PATH="$libdir" pkg-config --define-variable=prefix="$prefix" --cflags --libs visfield)
# shellcheck disable=SC2086
cc -std=c99 -Wall -Wextra -Werror "$example" $flags -o "$work/c_pkgconfig"
LD_LIBRARY_PATH="$prefix/lib:${LD_LIBRARY_PATH:-}" "$work/c_pkgconfig" >/dev/null
echo "C example through pkg-config: ok"

# The Python package, when the build made it: importable from the installed tree alone.
if [ -d "$build_dir/python/visfield" ]; then
  site=$(ls -d "$prefix"/lib*/python3/dist-packages | head -1)
  python=$(sed -n 's/^PYTHON_EXECUTABLE:FILEPATH=//p' "$build_dir/CMakeCache.txt")
  (cd "$work" && PYTHONPATH="$site" "${python:-python3}" -c 'import visfield; assert visfield.__file__.startswith("'"$prefix"'"); print("python package:", visfield.__version__)')
fi
