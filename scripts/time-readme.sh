#!/usr/bin/env bash
# Times the README's two commands as a new user meets them: each run in a fresh clone of HEAD, after
# the packages the command installs are purged (with what only they pulled in, and the downloaded
# packages), no compiler cache (CCACHE_DISABLE=1), 2 cores. The raw files (command, wall time, output)
# go to OUT/readme-command{1,2}-N.json; OUT defaults to bench/results/<date>-<cpu>-<kernels>, the
# folder scripts/measure.sh writes. Every package is installed again at the end (install-deps.sh --all).
#
# Usage (as root: it removes and installs Debian packages): scripts/time-readme.sh [RUNS] [OUT]
#   RUNS: runs of each command (default 3: the README states their median), or N1,N2: N1 runs of
#         command 1 and N2 of command 2 (0 skips it)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
runs=${1:-3}
[[ $runs =~ ^[0-9]+(,[0-9]+)?$ ]] || { echo "time-readme: error: RUNS is N or N1,N2, got '$runs'" >&2; exit 2; }
runs_of=([1]=${runs%%,*} [2]=${runs##*,})
[[ $(id -u) == 0 ]] || { echo "time-readme: error: run as root (it purges and installs packages)" >&2; exit 2; }
git -C "$root" diff --quiet HEAD || { echo "time-readme: error: commit first: the runs clone HEAD" >&2; exit 2; }
mapfile -t commands < <(sed -n '/^```sh$/,/^```$/p' "$root/README.md" | sed -n 2,3p)
[[ ${#commands[@]} == 2 && ${commands[0]} == *"visfield render"* ]] || { echo "time-readme: error: README's two commands not found" >&2; exit 2; }
kernels=$(grep -q avx512f /proc/cpuinfo && echo avx512 || echo avx2)
cpu=$(sed -n 's/^model name[^:]*: *//p' /proc/cpuinfo | head -1 | tr 'A-Z' 'a-z' | tr -cs 'a-z0-9' '-' | sed 's/-$//')
out=${2:-$root/bench/results/$(date -u +%Y-%m-%d)-$cpu-$kernels}
mkdir -p "$out"
[[ -f $out/machine.json ]] || /usr/bin/python3 "$root/scripts/results.py" machine "$out" "$root/build/bin/visfield"
work=$(mktemp -d /tmp/visfield-readme.XXXXXX)
trap 'rm -rf "$work"; bash "$root/scripts/install-deps.sh" --all >/dev/null' EXIT

purge() {  # purge [--all]: the packages install-deps.sh [--all] installs, as on a machine that never had them
  # but for python3 itself, which runs the timer (scripts/results.py) and which Debian's cloud images have.
  local packages
  packages=$(bash "$root/scripts/install-deps.sh" --print "$@" | tr ' ' '\n' | grep -vx python3 | tr '\n' ' ')
  apt-mark manual python3 >/dev/null
  # shellcheck disable=SC2086
  DEBIAN_FRONTEND=noninteractive apt-get purge -y -q $packages >/dev/null 2>&1 || true
  DEBIAN_FRONTEND=noninteractive apt-get autoremove --purge -y -q >/dev/null 2>&1 || true
  apt-get clean
}

for number in 1 2; do
  # Numbered after the runs already in OUT, so that more runs add to them.
  first=$(($(find "$out" -maxdepth 1 -name "readme-command$number-*.json" | wc -l) + 1))
  for run in $(seq "$first" $((first + runs_of[$number] - 1))); do
    purge $([[ $number == 2 ]] && echo --all)
    rm -rf "$work/clone"
    git clone -q "$root" "$work/clone"
    (cd "$work/clone" && CCACHE_DISABLE=1 /usr/bin/python3 "$root/scripts/results.py" run "$out" "readme-command$number-$run" -- \
      bash -c "${commands[$((number - 1))]}")
  done
done
