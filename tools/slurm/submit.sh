#!/usr/bin/env bash
# Runs a clothsim study as a Slurm job array plus a dependent merge job (docs/cluster.md):
#
#   tools/slurm/submit.sh [--tasks N] [--partition P] [--time T] [--cpus-per-task C] [--mem M]
#                         [--wait] -- clothsim STUDY ARGS... --csv F [--plot F.png] [--summary F.json]
#
# STUDY is bench, stability, converge or `golden check`. Task i of the array runs `clothsim STUDY ...
# --shard auto` (part i+1 of N, written to F.shard-K-of-N/, with --jobs C (not golden) and
# --max-memory from SLURM_MEM_PER_NODE unless given); the merge job
# (--dependency=afterok:ARRAY) runs `clothsim merge` into F (and the plot and summary).
# --plot and --summary are merge's, so they are taken off the shards' command. Both job ids are printed;
# with --wait the script waits for the merge and exits with its exit code (1 when the
# array failed and the merge never ran; requeue the failed tasks, then run F.merge.sh).
# Logs: F.task-%a.log (task 0 runs shard 1) and F.merge.log.
# Every task may be requeued (scontrol requeue, preemption): a rerun skips what is done.
set -euo pipefail

usage() {
  sed -n '2,5p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}
fail() { echo "submit: $*" >&2; exit 2; }

tasks=4 partition= time_limit= cpus=1 mem= wait=0
while (($#)); do
  case $1 in
    --tasks) tasks=${2:?}; shift 2 ;;
    --partition) partition=${2:?}; shift 2 ;;
    --time) time_limit=${2:?}; shift 2 ;;
    --cpus-per-task) cpus=${2:?}; shift 2 ;;
    --mem) mem=${2:?}; shift 2 ;;
    --wait) wait=1; shift ;;
    --) shift; break ;;
    *) usage ;;
  esac
done
(($# >= 2)) || usage
[[ $tasks =~ ^[1-9][0-9]*$ ]] || fail "--tasks: '$tasks' is not a whole number >= 1"
[[ $cpus =~ ^[1-9][0-9]*$ ]] || fail "--cpus-per-task: '$cpus' is not a whole number >= 1"
clothsim=$(command -v "$1" 2>/dev/null) || fail "$1: no such program"
clothsim=$(realpath "$clothsim")
study=$2
shift 2
if [[ $study == golden ]]; then
  [[ ${1:-} == check ]] || fail "golden ${1:-}: only golden check takes --shard"
  study="golden check"
  shift
fi
[[ $study == bench || $study == stability || $study == converge || $study == "golden check" ]] ||
  fail "$study: only bench, stability, converge and golden check take --shard"

# The shards' arguments: the study's, without --plot (merge draws it); --csv is kept.
args=() csv= plot= summary= has_jobs=0 has_mem=0
while (($#)); do
  case $1 in
    --plot) plot=${2:?}; shift 2 ;;
    --plot=*) plot=${1#--plot=}; shift ;;
    --summary) summary=${2:?}; shift 2 ;;
    --summary=*) summary=${1#--summary=}; shift ;;
    --csv) csv=${2:?}; args+=("$1" "$2"); shift 2 ;;
    --csv=*) csv=${1#--csv=}; args+=("$1"); shift ;;
    --shard|--shard=*) fail "--shard: submit.sh adds --shard auto itself" ;;
    *) [[ $1 == --jobs* ]] && has_jobs=1; [[ $1 == --max-memory* ]] && has_mem=1; args+=("$1"); shift ;;
  esac
done
[[ -n $csv ]] || fail "the study needs --csv F (the shards write F.shard-K-of-N/, the merge writes F)"
# golden renders one entry at a time, converge runs one sweep at a time: neither takes --jobs
[[ $study == "golden check" || $study == converge ]] || ((has_jobs)) || args+=(--jobs "$cpus")

# A shard's command line, quoted for the job's shell; the memory limit is Slurm's when set.
shard_command=$(printf '%q ' "$clothsim" $study "${args[@]}" --shard auto)
((has_mem)) || shard_command+=' ${SLURM_MEM_PER_NODE:+--max-memory ${SLURM_MEM_PER_NODE}M}'
merge_command=$(printf '%q ' "$clothsim" merge)
for ((k = 1; k <= tasks; k++)); do merge_command+=$(printf '%q ' "$csv.shard-$k-of-$tasks"); done
merge_command+=$(printf '%q ' --csv "$csv")
[[ -n $plot ]] && merge_command+=$(printf '%q ' --plot "$plot")
[[ -n $summary ]] && merge_command+=$(printf '%q ' --summary "$summary")

common=(--parsable)
[[ -n $partition ]] && common+=(--partition="$partition")
[[ -n $time_limit ]] && common+=(--time="$time_limit")
array_opts=(--array="0-$((tasks - 1))" --cpus-per-task="$cpus" --requeue --job-name="clothsim-${study% check}"
            --output="$csv.task-%a.log")
[[ -n $mem ]] && array_opts+=(--mem="$mem")

array_id=$(sbatch "${common[@]}" "${array_opts[@]}" --wrap "exec $shard_command")
array_id=${array_id%%;*}
# Slurm cancels the merge once a task fails (afterok can then never hold, even after a
# requeue): the merge command is kept in F.merge.sh to run by hand after requeued tasks.
printf '#!/bin/sh\n%s\n' "$merge_command" >"$csv.merge.sh"
chmod +x "$csv.merge.sh"
merge_id=$(sbatch "${common[@]}" --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
  --job-name="clothsim-merge" --output="$csv.merge.log" --wrap "exec $merge_command")
merge_id=${merge_id%%;*}
echo "array job $array_id ($tasks tasks of clothsim $study), merge job $merge_id -> $csv"
((wait)) || exit 0

# The merge job's state and exit code, from scontrol while the controller remembers it
# (MinJobAge), else from sacct.
job_field() { scontrol -o show job "$merge_id" 2>/dev/null | tr ' ' '\n' | sed -n "s/^$1=//p" | head -1; }
while :; do
  state=$(job_field JobState)
  [[ -z $state ]] && state=$(sacct -n -X -P -j "$merge_id" -o State 2>/dev/null | head -1 | cut -d' ' -f1)
  case $state in
    COMPLETED|FAILED|CANCELLED*|TIMEOUT|OUT_OF_MEMORY|NODE_FAIL|PREEMPTED|BOOT_FAIL|DEADLINE) break ;;
  esac
  sleep 0.1  # the controller starts jobs on its once-a-second pass; a 1 s poll added 0.5 s on average
done
code=$(job_field ExitCode)
[[ -z $code ]] && code=$(sacct -n -X -P -j "$merge_id" -o ExitCode 2>/dev/null | head -1)
code=${code%%:*}
if [[ $state == CANCELLED* && $code == 0 ]]; then
  echo "submit: merge job $merge_id was cancelled: a task failed (see $csv.task-*.log); requeue it" \
       "(scontrol requeue ${array_id}_I), then run $csv.merge.sh" >&2
  exit 1
fi
echo "submit: merge job $merge_id $state, exit code $code (log $csv.merge.log)" >&2
exit "${code:-1}"
