#!/usr/bin/env bash
# Makes a calibration file (`visfield calibrate -o FILE` or `visfield report --save-measurements
# FILE`) the built-in one: writes it, whole, to src/select/builtin_calibration.json, headed by the
# command that measured it. CMake embeds that file in the library; loading it fits the planner's
# model from its per-scene measurements with the code of the build.
#   scripts/builtin-calibration.sh CALIBRATION.json "COMMAND THAT WROTE IT"
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: $0 CALIBRATION.json \"COMMAND THAT WROTE IT\"" >&2
  exit 2
fi
out="$(dirname "$0")/../src/select/builtin_calibration.json"
tmp=$(mktemp)
{
  echo "// The built-in calibration, measured on the project's build machine by"
  echo "//   $2"
  echo "// Per-ray times are for its thread count; the planner rescales them to the threads in force."
  echo "// Re-measure with visfield calibrate on another machine."
  /usr/bin/python3 -c 'import json, sys; print(json.dumps(json.load(open(sys.argv[1])), indent=1))' "$1"
} > "$tmp"
mv "$tmp" "$out"
echo "wrote $out"
