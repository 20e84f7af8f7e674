#!/bin/sh
# Issue 11's clip targets, measured side by side: the wall time of the comparison clip against
# the build before issues 9-13 (ef1fae7), in interleaved rounds on this machine.
#   tools/clip_ratio.sh [BUILD_DIR] [ROUNDS]      # defaults: build, 3
# Builds ef1fae7's clothsim once in a worktree (../clothsim-ef1fae7 next to this checkout,
# about 4 minutes on 2 cores) and runs, per round:
#   baseline  ef1fae7: compare scenes/drape.yaml --video (its own drape.yaml: the same four lanes)
#   same      compare scenes/drape.yaml --integrators explicit_euler,implicit_euler,midpoint,rk4
#             --color checker --video (the clip as it was: no reference lane)
#   default   compare scenes/drape.yaml --video (today's default clip)
# and prints each time with its ratio to that round's baseline. The machine should be otherwise
# idle: another process on the 2 cores moves the baseline's 25 s by seconds.
set -eu
cd "$(dirname "$0")/.."
BUILD=${1:-build}
ROUNDS=${2:-3}
BASE_REV=ef1fae7
BASE=${CLOTHSIM_BASELINE_TREE:-../clothsim-$BASE_REV}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

if [ ! -x "$BASE/build/clothsim" ]; then
  echo "== building $BASE_REV's clothsim in $BASE" >&2
  [ -d "$BASE" ] || git worktree add --detach "$BASE" "$BASE_REV" >&2
  cmake -S "$BASE" -B "$BASE/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$BASE/build" -j2 --target clothsim >/dev/null
fi
[ -x "$BUILD/clothsim" ] || { echo "clip_ratio.sh: no $BUILD/clothsim (build first: tools/build.sh)" >&2; exit 2; }
HERE=$(pwd)

# Wall seconds of one command (GNU time's %e).
wall() {
  /usr/bin/env time -f "%e" -o "$OUT/t" "$@" >/dev/null 2>"$OUT/err" || { cat "$OUT/err" >&2; exit 1; }
  cat "$OUT/t"
}

i=1
while [ "$i" -le "$ROUNDS" ]; do
  base=$(cd "$BASE" && wall ./build/clothsim compare scenes/drape.yaml --video "$OUT/base.mp4")
  same=$(wall "$BUILD/clothsim" compare "$HERE/scenes/drape.yaml" --integrators explicit_euler,implicit_euler,midpoint,rk4 \
    --color checker --video "$OUT/same.mp4" --quiet)
  default=$(wall "$BUILD/clothsim" compare "$HERE/scenes/drape.yaml" --video "$OUT/default.mp4" --quiet)
  awk -v r="$i" -v b="$base" -v s="$same" -v d="$default" 'BEGIN {
    printf "round %d: baseline %.2f s, same clip %.2f s (%.3fx, target 0.3x), default clip %.2f s (%.3fx, target 0.5x)\n",
           r, b, s, s / b, d, d / b }'
  i=$((i + 1))
done
