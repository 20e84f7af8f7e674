#!/usr/bin/env bash
# Peak resident memory (GNU time's %M) beside the estimate `--max-memory 1k` prints (BENCHMARKS.md,
# "Memory estimate"), for the engine (a few steps of `run` per integrator and sheet size, with and
# without --state) and for the pictures (run's still and frames, compare, encode, golden check).
# Runs one at a time: a 2048² implicit run peaks near 8 GB.
#   tools/reliability/memory_peaks.sh [BINARY] [SIZES] [INTEGRATORS] [PICTURES]
# PICTURES: "yes" (the default) adds the picture commands at 720p and 1080p, "no" leaves them.
# The clips (compare --video, encode) last VIDEO_SECONDS (2 by default: 60 frames, past x264's
# lookahead and frame threads, where a 6-frame clip peaks 40-50 MiB lower at 720p).
# prints one CSV row per run: case,peak_mib,estimate_mib,estimate_over_peak
set -u
bin=${1:-build/clothsim}
sizes=${2:-"256 1024 2048"}
integrators=${3:-"explicit_euler symplectic_euler midpoint rk4 implicit_euler xpbd projective_dynamics vbd"}
pictures=${4:-yes}
scene=${SCENE:-scenes/drape.yaml}
clip=${VIDEO_SECONDS:-2}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
to_mib() {  # "2.55 GB" -> MiB (format_bytes counts powers of 1024)
  awk -v n="$1" -v u="$2" 'BEGIN { s["B"]=1/1048576; s["kB"]=1/1024; s["MB"]=1; s["GB"]=1024; s["TB"]=1048576; printf "%.1f", n*s[u] }'
}
# measure NAME ARGS...: the estimate (refused at --max-memory 1k), then the peak of the real run.
measure() {
  local name=$1
  shift
  local line estimate peak
  line=$("$bin" "$@" --max-memory 1k 2>&1 | grep -o 'needs an estimated [0-9.]* [kMGT]*B')
  estimate=$(to_mib $(echo "$line" | awk '{print $4, $5}'))
  /usr/bin/time -f %M -o "$tmp/peak" "$bin" "$@" --max-memory 1T >/dev/null 2>"$tmp/err" ||
    { echo "$name: failed: $(tail -1 "$tmp/err")" >&2; return; }
  peak=$(awk '{printf "%.1f", $1/1024}' "$tmp/peak")
  echo "$name,$peak,$estimate,$(awk -v e="$estimate" -v p="$peak" 'BEGIN{printf "%.3f", e/p}')"
}
echo "case,peak_mib,estimate_mib,estimate_over_peak"
for n in $sizes; do
  for integrator in $integrators; do
    for state in no yes; do
      args=(run "$scene" --set "cloth.particles=[$n,$n]" --integrator "$integrator" --dt 1e-4 --duration 2e-4)
      [ "$state" = yes ] && args+=(--state "$tmp/s.csv")
      measure "run $n $integrator state=$state" "${args[@]}"
      rm -f "$tmp/s.csv"
    done
  done
done
[ "$pictures" = yes ] || exit 0
for size in "1280 720" "1920 1080"; do
  set -- $size
  px=(--width "$1" --height "$2")
  measure "run still ${1}x$2" run "$scene" "${px[@]}" --duration 0.2 --still 0.2 -o "$tmp/still.png"
  measure "run frames ${1}x$2" run "$scene" "${px[@]}" --duration 0.2 --frames "$tmp/fr"
  measure "compare still ${1}x$2" compare "$scene" "${px[@]}" --duration 0.2 --still 0.2 -o "$tmp/c.png"
  measure "compare video ${1}x$2 ${clip} s" compare "$scene" "${px[@]}" --duration "$clip" --video "$tmp/c.mp4"
  measure "run video ${1}x$2 ${clip} s" run "$scene" "${px[@]}" --duration "$clip" --video "$tmp/r.mp4"
  for d in a b c d; do "$bin" run "$scene" --width $(($1 / 2)) --height $(($2 / 2)) --duration "$clip" --frames "$tmp/e$d" >/dev/null 2>&1; done
  measure "encode 2x2 of $(($1 / 2))x$(($2 / 2)) ${clip} s" encode "$tmp/ea" "$tmp/eb" "$tmp/ec" "$tmp/ed" -o "$tmp/e.mp4"
  printf 'goldens:\n  - {scene: %s, times: [0.1, 0.2], name: g, size: [%s, %s]}\n' "$PWD/$scene" "$1" "$2" > "$tmp/m.yaml"
  "$bin" golden update "$tmp/m.yaml" >/dev/null 2>&1
  measure "golden check ${1}x$2" golden check "$tmp/m.yaml"
  rm -rf "$tmp"/fr "$tmp"/e? "$tmp"/*.png "$tmp"/*.mp4
done
