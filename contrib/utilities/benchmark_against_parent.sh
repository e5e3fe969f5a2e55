#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# fmpm-benchmark of this checkout side by side with another commit (by
# default the parent, HEAD~1), interleaved over ROUNDS rounds (this machine
# is noisy: each scene's best round counts), in one run:
#
#   contrib/utilities/benchmark_against_parent.sh [COMMIT] [ROUNDS] [-- ARGS]
#
# ARGS go to both fmpm-benchmark runs (scenes, overrides). The other commit
# is built in Release in $TMPDIR/fmpm-benchmark-<sha> (TMPDIR defaults to
# /tmp; a git worktree, kept for the next comparison); this checkout's build
# is build/.
set -eu
root="$(cd "$(dirname "$0")/../.." && pwd)"
commit="${1:-HEAD~1}"; [ $# -gt 0 ] && shift
rounds="${1:-3}"; [ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
sha="$(git -C "$root" rev-parse --short "$commit")"
other="${TMPDIR:-/tmp}/fmpm-benchmark-$sha"
if [ ! -x "$other/build/applications/benchmark/fmpm-benchmark" ]; then
  echo "building fmpm-benchmark of $sha in $other (once)" >&2
  [ -d "$other" ] || git -C "$root" worktree add --detach "$other" "$sha" >/dev/null
  cmake -S "$other" -B "$other/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$other/build" --target fmpm-benchmark -j "$(nproc)" >/dev/null
fi
cmake --build "$root/build" --target fmpm-benchmark -j "$(nproc)" >/dev/null

# Every 'particle-steps per second (time steps only)' line, with its scene.
rates() {
  awk '/^=== benchmark/ {scene=$3} /time steps only/ {print scene, $NF}' "$1" |
    sed 's|.*/||'
}
work="$(mktemp -d)"
for r in $(seq 1 "$rounds"); do
  echo "round $r of $rounds" >&2
  (cd "$work" && "$other/build/applications/benchmark/fmpm-benchmark" "$@" > "other-$r.log" 2>&1)
  (cd "$work" && "$root/build/applications/benchmark/fmpm-benchmark" "$@" > "this-$r.log" 2>&1)
  rates "$work/other-$r.log" >> "$work/other.rates"
  rates "$work/this-$r.log" >> "$work/this.rates"
done
echo "| scene | $sha particle-steps/s (best of $rounds) | this checkout | ratio |"
echo "|---|---|---|---|"
for scene in $(awk '{print $1}' "$work/this.rates" | sort -u); do
  a=$(awk -v s="$scene" '$1 == s && $2 > m {m = $2} END {print m}' "$work/other.rates")
  b=$(awk -v s="$scene" '$1 == s && $2 > m {m = $2} END {print m}' "$work/this.rates")
  awk -v s="$scene" -v a="$a" -v b="$b" \
    'BEGIN {printf "| %s | %.3g | %.3g | %.2f |\n", s, a, b, (a > 0 ? b / a : 0)}'
done
echo "(logs in $work)"
