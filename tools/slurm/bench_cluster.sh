#!/usr/bin/env bash
# The issue's wall-time comparison on the local cluster (docs/cluster.md, BENCHMARKS.md):
# rounds of a stability sweep of the drape as 4 one-CPU shards through submit.sh --wait,
# then in one process with --jobs 1, then --jobs 2, back to back; one line per round (wall
# times, ratios, the shards' CPU from the CSV) and Slurm's steps from the controller's log.
# Usage: tools/slurm/bench_cluster.sh [CLOTHSIM]
#   (PARTICLES=50 DURATION=0.2 ROUNDS=2 VALUES=2e4,2e5,2e6,2e7: the structural stiffnesses)
# Needs a running local cluster (tools/slurm/local-cluster.sh start).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
clothsim=$(realpath "${1:-$root/build/clothsim}")
p=${PARTICLES:-50} duration=${DURATION:-0.2} rounds=${ROUNDS:-2} values=${VALUES:-2e4,2e5,2e6,2e7}
log=${CLOTHSIM_SLURM_DIR:-/var/tmp/clothsim-slurm}/log/slurmctld.log
sweep=(stability "$root/scenes/drape.yaml" --set "cloth.particles=[$p,$p]" --duration "$duration"
       --values "$values" --integrators explicit_euler,symplectic_euler,midpoint,rk4,implicit_euler)
work=$(mktemp -d /var/tmp/clothsim-bench-cluster.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"
now() { date +%s.%N; }
for r in $(seq "$rounds"); do
  rm -rf s4.csv*
  t0=$(now)
  out=$("$root/tools/slurm/submit.sh" --tasks 4 --wait -- "$clothsim" "${sweep[@]}" --csv s4.csv 2>&1)
  t1=$(now)
  "$clothsim" "${sweep[@]}" --jobs 1 --csv s1.csv >/dev/null
  t2=$(now)
  "$clothsim" "${sweep[@]}" --jobs 2 --csv s2.csv >/dev/null
  t3=$(now)
  shards=""
  for k in 1 2 3 4; do
    shards+=$(cat s4.csv.shard-$k-of-4/items/* | awk -F, '{s += $8} END {printf " %.2f", s}')
  done
  awk -v r="$r" -v a="$t0" -v b="$t1" -v c="$t2" -v d="$t3" -v cpu="$shards" -v load="$(cut -d' ' -f1 /proc/loadavg)" \
    'BEGIN { printf "round %d: 4 shards %.1f s, --jobs 1 %.1f s (%.2fx), --jobs 2 %.1f s (%.2fx); shards CPU s%s; load %s\n",
             r, b - a, c - b, (b - a) / (c - b), d - c, (b - a) / (d - c), cpu, load }'
  read -r array merge < <(sed -n 's/^array job \([0-9]*\) .*merge job \([0-9]*\).*/\1 \2/p' <<<"$out")
  grep -E "JobId=(${array}_[0-9]+|$merge)[ (]|submit_batch_job: JobId=($array|$merge) " "$log" |
    grep -E "submit_batch|Allocate|Started|done" | sed 's/^\[[^T]*T\([^]]*\)\]/  \1/' | cut -c1-90
done
