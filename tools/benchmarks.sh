#!/bin/sh
# Runs every benchmark BENCHMARKS.md quotes, in one go, on this machine:
#   tools/benchmarks.sh [BUILD_DIR] [OUT_DIR]     # defaults: build, bench-results
# Google Benchmark targets (engine, integrators, renderer, PNG, encoder; median of 3; the
# Bullet peer where it was built), then
# the end-to-end commands timed whole: the default comparison clip and the default
# work-precision and stability studies of the drape. About 3 minutes on 2 idle cores.
# The machine should be otherwise idle: figures are recorded as ratios from one run.
set -eu
cd "$(dirname "$0")/.."
BUILD=${1:-build}
OUT=${2:-bench-results}
mkdir -p "$OUT"
REPS="--benchmark_repetitions=3 --benchmark_report_aggregates_only=true"

echo "== engine and integrators" >&2
"$BUILD"/tools/bench/clothsim_benchmarks $REPS | tee "$OUT/engine.txt"
if [ -x "$BUILD"/tools/bench/bullet_peer_benchmarks ]; then
  echo "== peer: Bullet btSoftBody beside clothsim (3 runs each inside)" >&2
  "$BUILD"/tools/bench/bullet_peer_benchmarks | tee "$OUT/bullet_peer.txt"
fi
echo "== renderer and PNG" >&2
"$BUILD"/tools/bench/render_benchmarks $REPS | tee "$OUT/render.txt"
echo "== encoder" >&2
"$BUILD"/tools/bench/video_benchmarks $REPS | tee "$OUT/video.txt"

# GNU time's %e is wall seconds, %U+%S CPU seconds, %M peak memory in KiB.
timed() {
  name=$1
  shift
  /usr/bin/env time -f "$name: %e s wall, %U s user + %S s sys, %M KiB peak" -a -o "$OUT/end_to_end.txt" "$@" \
    >"$OUT/$name.out" 2>"$OUT/$name.err"
}
: >"$OUT/end_to_end.txt"
echo "== compare (default clip)" >&2
timed compare "$BUILD"/clothsim compare scenes/drape.yaml --video "$OUT/drape.mp4"
echo "== bench (default study)" >&2
timed bench "$BUILD"/clothsim bench scenes/drape.yaml --csv "$OUT/bench.csv"
echo "== stability (default study)" >&2
timed stability "$BUILD"/clothsim stability scenes/drape.yaml --csv "$OUT/stability.csv"
cat "$OUT/end_to_end.txt"
grep -h '^compare:' "$OUT/compare.err" || true
