#!/usr/bin/env bash
# Peak resident memory (GNU time's %M) of a few steps of `run` per integrator and sheet size,
# with and without --state, beside the estimate `--max-memory 1k` prints (BENCHMARKS.md,
# "Memory estimate"). Runs one at a time: a 2048² implicit run peaks near 8 GB.
#   tools/reliability/memory_peaks.sh [BINARY] [SIZES] [INTEGRATORS]
# prints one CSV row per run: n,integrator,state,peak_mib,estimate_mib,estimate_over_peak
set -u
bin=${1:-build/clothsim}
sizes=${2:-"256 1024 2048"}
integrators=${3:-"explicit_euler symplectic_euler midpoint rk4 implicit_euler xpbd projective_dynamics vbd"}
scene=${SCENE:-scenes/drape.yaml}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
to_mib() {  # "2.55 GB" -> MiB (format_bytes counts powers of 1024)
  awk -v n="$1" -v u="$2" 'BEGIN { s["B"]=1/1048576; s["kB"]=1/1024; s["MB"]=1; s["GB"]=1024; s["TB"]=1048576; printf "%.1f", n*s[u] }'
}
echo "n,integrator,state,peak_mib,estimate_mib,estimate_over_peak"
for n in $sizes; do
  for integrator in $integrators; do
    for state in no yes; do
      args=(run "$scene" --set "cloth.particles=[$n,$n]" --integrator "$integrator" --dt 1e-4 --duration 2e-4)
      [ "$state" = yes ] && args+=(--state "$tmp/s.csv")
      line=$("$bin" "${args[@]}" --max-memory 1k 2>&1 | grep -o 'needs an estimated [0-9.]* [kMGT]*B')
      estimate=$(to_mib $(echo "$line" | awk '{print $4, $5}'))
      /usr/bin/time -f %M -o "$tmp/peak" "$bin" "${args[@]}" --max-memory 1T >/dev/null 2>"$tmp/err" ||
        { echo "$n,$integrator,$state: failed: $(tail -1 "$tmp/err")" >&2; continue; }
      peak=$(awk '{printf "%.1f", $1/1024}' "$tmp/peak")
      echo "$n,$integrator,$state,$peak,$estimate,$(awk -v e="$estimate" -v p="$peak" 'BEGIN{printf "%.3f", e/p}')"
      rm -f "$tmp/s.csv"
    done
  done
done
