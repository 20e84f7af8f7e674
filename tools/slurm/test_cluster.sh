#!/usr/bin/env bash
# The cluster test of sharded studies (docs/cluster.md), run by tools/test.sh after ctest:
# starts the local one-node cluster (tools/slurm/local-cluster.sh, installing slurm-wlm and
# munge when missing), then
# 1. a 4-shard stability sweep and 2. a 4-shard bench through submit.sh --wait, each merged
#    CSV equal to the same study run in one process (timing columns aside);
#    and the merged --summary equal to the single-process one (timing aside);
# 3. a 2-shard `golden check` of a 4-entry manifest: merged report, CSV and summary equal;
# 4. a 2-shard stability sweep whose first task is stopped mid-run with
#    `scancel --signal=TERM`, then requeued: its finished items are kept, none runs twice,
#    and the merge equals the single-process CSV.
# Skipped, saying why, only where Slurm cannot run: not root and no password-less sudo, or
# neither Slurm nor apt-get to install it. Stops the cluster afterwards if it started it.
# Usage: tools/slurm/test_cluster.sh [CLOTHSIM] (default build/clothsim).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
clothsim=$(realpath "${1:-build/clothsim}")
scene=$root/scenes/drape.yaml

skip() { echo "test_cluster: SKIPPED: $*" >&2; exit 0; }
fail() { echo "test_cluster: FAIL: $*" >&2; exit 1; }
say() { echo "test_cluster: $*" >&2; }

[[ $(id -u) -eq 0 ]] || sudo -n true 2>/dev/null ||
  skip "munged, slurmctld and slurmd need root (or sudo without a password)"
command -v sbatch >/dev/null || command -v apt-get >/dev/null ||
  skip "no Slurm here and no apt-get to install slurm-wlm and munge"
[[ -x $clothsim ]] || fail "$clothsim: not built"

started=0 ok=0
if ! tools/slurm/local-cluster.sh status >/dev/null 2>&1; then
  tools/slurm/local-cluster.sh start
  started=1
fi
work=$(mktemp -d /var/tmp/clothsim-cluster-test.XXXXXX)
cleanup() {
  cd "$root"  # out of the folder about to go, so the stop runs in one that exists
  if ((ok)); then rm -rf "$work"; else echo "test_cluster: kept $work for inspection" >&2; fi
  ((started)) && "$root/tools/slurm/local-cluster.sh" stop
  return 0
}
trap cleanup EXIT
cd "$work"

# The CSV without its timing columns (they measure the machine, not the study).
untimed() {
  /usr/bin/python3 - "$1" <<'EOF'
import csv, sys
rows = list(csv.reader(open(sys.argv[1], newline="")))
keep = [i for i, name in enumerate(rows[0]) if name not in ("wall_seconds", "cpu_seconds")]
for row in rows:
    print(",".join(row[i] for i in keep))
EOF
}
same_rows() {
  cmp -s <(untimed "$1") <(untimed "$2") || { diff <(untimed "$1") <(untimed "$2") | head -5 >&2; fail "$3: $1 differs from $2"; }
  say "$3: merged $1 = single-process $2 ($(($(wc -l <"$2") - 1)) rows, timing columns aside)"
}
# Two --summary files equal but for their timing keys.
same_summary() {
  /usr/bin/python3 - "$1" "$2" <<'EOF' || fail "$3: $1 differs from $2"
import json, sys
def untimed(x):
    if isinstance(x, dict):
        return {k: untimed(v) for k, v in x.items() if k not in ("wall_seconds", "cpu_seconds")}
    return [untimed(v) for v in x] if isinstance(x, list) else x
a, b = (untimed(json.load(open(p))) for p in sys.argv[1:3])
sys.exit(0 if a == b else 1)
EOF
  say "$3: merged summary $1 = single-process $2 (timing aside)"
}
seconds() { date +%s.%N; }

stability=(stability "$scene" --duration 0.1 --values 2e4,2e5,2e6,2e7,2e8)
bench=(bench "$scene" --duration 0.04 --dts 1e-4,2e-4,4e-4,8e-4 --frame-dts none)

# 1. Stability, 4 shards, against one process with --jobs 1 and --jobs 2 (times are printed,
# never asserted: the machine may be shared).
t0=$(seconds)
"$root/tools/slurm/submit.sh" --tasks 4 --wait -- "$clothsim" "${stability[@]}" --csv s4.csv
t1=$(seconds)
"$clothsim" "${stability[@]}" --jobs 1 --csv s1.csv >/dev/null
t2=$(seconds)
"$clothsim" "${stability[@]}" --jobs 2 --csv s2.csv >/dev/null
t3=$(seconds)
same_rows s4.csv s1.csv "stability"
"$clothsim" "${stability[@]}" --jobs 2 --summary s1.json >/dev/null
"$root/tools/slurm/submit.sh" --tasks 2 --wait -- "$clothsim" "${stability[@]}" --csv s5.csv --summary s5.json >/dev/null
same_summary s5.json s1.json "stability"
say "$(awk -v a="$t0" -v b="$t1" -v c="$t2" -v d="$t3" 'BEGIN { printf "stability wall time: 4 shards %.1f s, one process --jobs 1 %.1f s (%.2fx), --jobs 2 %.1f s (%.2fx)", b - a, c - b, (b - a) / (c - b), d - c, (b - a) / (d - c) }')"

# 2. Bench, 4 shards.
"$root/tools/slurm/submit.sh" --tasks 4 --wait -- "$clothsim" "${bench[@]}" --csv b4.csv
"$clothsim" "${bench[@]}" --jobs 2 --csv b1.csv >/dev/null
same_rows b4.csv b1.csv "bench"

# 3. Golden check, 2 shards: the merge reports what one check reports.
cp "$scene" drape.yaml
cp "$root/scenes/spring.yaml" spring.yaml
printf '%s\n' "size: [96, 54]" "goldens:" "  - {scene: drape.yaml, times: [0.05, 0.1]}" \
  "  - {scene: spring.yaml, times: [0.5]}" "  - {scene: drape.yaml, name: drape_rk4, integrator: rk4, times: [0.05]}" \
  "  - {scene: drape.yaml, name: drape_mid, integrator: midpoint, times: [0.1]}" >goldens.yaml
"$clothsim" golden update goldens.yaml >/dev/null
"$clothsim" golden check goldens.yaml --csv g1.csv --summary g1.json >g1.out
"$root/tools/slurm/submit.sh" --tasks 2 --wait -- "$clothsim" golden check goldens.yaml --csv g2.csv \
  --summary g2.json
cmp -s g1.csv g2.csv || fail "golden: g2.csv differs from g1.csv"
cmp -s <(grep -E '^(ok|FAIL|golden:)' g1.out) <(grep -E '^(ok|FAIL|golden:)' g2.csv.merge.log) ||
  fail "golden: the merged report (g2.csv.merge.log) differs from one check's (g1.out)"
same_summary g2.json g1.json "golden"

# 4. A task stopped by SIGTERM mid-run, requeued: nothing finished runs twice.
out=$("$root/tools/slurm/submit.sh" --tasks 2 -- "$clothsim" "${stability[@]}" --csv r.csv)
array=$(sed -n 's/^array job \([0-9]*\) .*/\1/p' <<<"$out")
journal=r.csv.shard-1-of-2
for _ in $(seq 600); do
  (($(ls "$journal/items" 2>/dev/null | wc -l) >= 1)) && break
  sleep 0.1
done
scancel --batch --signal=TERM "${array}_0"
for _ in $(seq 300); do
  squeue -h -j "${array}_0" -t RUNNING,COMPLETING 2>/dev/null | grep -q . || break
  sleep 0.1
done
before=$(ls "$journal/items" | wc -l)
assigned=$(sed -n 's/^items: //p' "$journal/provenance" | wc -w)
grep -q 'interrupted:' r.csv.task-0.log || fail "task 0 finished before SIGTERM reached it (r.csv.task-0.log)"
say "requeue: task 0 stopped by SIGTERM with $before of $assigned items journaled"
scontrol requeue "${array}_0"
# Slurm delays a requeued job (its old credential is revoked to the second); 2 s is enough here.
scontrol update JobId="${array}_0" StartTime=now+2
for _ in $(seq 1200); do
  squeue -h -j "$array" 2>/dev/null | grep -q . || break
  sleep 0.1
done
grep -q "$before finished before" r.csv.task-0.log || fail "the requeued task did not resume from $before items"
dups=$(sort "$journal/log" | uniq -d)
[[ -z $dups ]] || fail "items ran twice after the requeue: $dups"
(($(wc -l <"$journal/log") == assigned)) || fail "$journal/log has $(wc -l <"$journal/log") records for $assigned items"
./r.csv.merge.sh >/dev/null
same_rows r.csv s1.csv "requeue"
ok=1
say "ok"
