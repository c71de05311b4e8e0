#!/bin/bash
# pushpack bench as a SLURM job array: array task K of N runs shard K/N of the batch
# (`pushpack bench --shard K/N --resume`), so a preempted or failed task is simply resubmitted.
# docs/cluster.md says what to change for your cluster. Submit from the repository root (or set
# PUSHPACK_DIR), on a file system every node shares:
#
#   sbatch scripts/slurm/bench-array.sh                     # the defaults below
#   PUSHPACK_OUT=out/n12 sbatch scripts/slurm/bench-array.sh instances/random/n12
#   sbatch --array=7 scripts/slurm/bench-array.sh           # rerun task 7 alone (same N)
#   scripts/slurm/report.sh                                 # afterwards: check and report
#
# Settings (environment variables; sbatch passes the submitting shell's environment on):
#   PUSHPACK_DIR         directory to run in; relative paths below are relative to it
#                        (default: the directory sbatch was called from)
#   PUSHPACK_BIN         the pushpack binary (default target/release/pushpack); build it first
#   PUSHPACK_INSTANCES   instance files or directories, split at spaces, globs expanded
#                        (default "instances/random/n*"); arguments to the script replace it
#   PUSHPACK_PLANNERS    planner specs (default bl+paper+packing-only,bl+astar+packing-only,
#                        milp+astar+packing-only: the random sets allow every orientation, so
#                        their plans are judged as packings; docs/benchmarks.md)
#   PUSHPACK_TIME_LIMIT  seconds per run (default 60)
#   PUSHPACK_OUT         result directory, shared by all tasks (default out/bench)
#   PUSHPACK_JOBS        concurrent runs per task (default $SLURM_CPUS_PER_TASK, else 1)
#   PUSHPACK_SHARDS      N, the number of shards (default: the N recorded in PUSHPACK_OUT by
#                        the batch's first task, else the array's task count)
#   PUSHPACK_BENCH_ARGS  more bench options, split at spaces (e.g. "--hard-limit 300")
#
# The #SBATCH lines are the ones to edit: the array's size is the number of shards (0-15: 16),
# each task gets --cpus-per-task cores for as many concurrent runs; --mem must hold that many
# planner processes at once; --time must cover
# ceil(runs / (N * jobs)) * time limit with room (bench kills a run at 2 * limit + 30 s).
#SBATCH --job-name=pushpack-bench
#SBATCH --array=0-15
#SBATCH --cpus-per-task=2
#SBATCH --mem=16G
#SBATCH --time=04:00:00
#SBATCH --output=slurm-%x-%A_%a.out
## Uncomment and fill in what your site requires:
##SBATCH --partition=compute
##SBATCH --account=myproject
##SBATCH --qos=normal
set -euo pipefail

die() {
  echo "bench-array.sh: error: $*" >&2
  exit 1
}

# module load ...   # site modules, if the binary needs any at run time (it does not by default)

if [ -z "${SLURM_ARRAY_TASK_ID:-}" ]; then
  die "SLURM_ARRAY_TASK_ID is not set: submit this as a job array, 'sbatch --array=0-15 $0' (or keep the #SBATCH --array line)"
fi

if [ -n "${PUSHPACK_DIR:-}" ]; then
  cd "$PUSHPACK_DIR" || die "PUSHPACK_DIR=$PUSHPACK_DIR: no such directory"
fi

bin=${PUSHPACK_BIN:-target/release/pushpack}
planners=${PUSHPACK_PLANNERS:-bl+paper+packing-only,bl+astar+packing-only,milp+astar+packing-only}
time_limit=${PUSHPACK_TIME_LIMIT:-60}
out=${PUSHPACK_OUT:-out/bench}
jobs=${PUSHPACK_JOBS:-${SLURM_CPUS_PER_TASK:-1}}

if [ $# -gt 0 ]; then
  instances=("$@")
else
  # Split at spaces and expand globs on purpose: "instances/random/n*" is the default.
  # shellcheck disable=SC2206
  instances=(${PUSHPACK_INSTANCES:-instances/random/n*})
fi
[ ${#instances[@]} -gt 0 ] || die "no instances given (PUSHPACK_INSTANCES or arguments)"
for i in "${instances[@]}"; do
  [ -e "$i" ] || die "instance path '$i' does not exist (relative to $(pwd)); set PUSHPACK_DIR or PUSHPACK_INSTANCES"
done
[ -x "$bin" ] || die "pushpack binary '$bin' is missing or not executable (relative to $(pwd)); build it with 'cargo build --release --locked' or set PUSHPACK_BIN"

is_count() { [[ $1 =~ ^[0-9]+$ ]]; }
k=$SLURM_ARRAY_TASK_ID
is_count "$k" || die "SLURM_ARRAY_TASK_ID='$k' is not a number"
is_count "$jobs" && [ "$jobs" -ge 1 ] || die "PUSHPACK_JOBS (or SLURM_CPUS_PER_TASK)='$jobs' is not a positive number"

# N belongs to the batch, not to one submission: a single task resubmitted with --array=7 has
# SLURM_ARRAY_TASK_COUNT=1. The first task records N in the result directory; later tasks use
# the record, and an explicit PUSHPACK_SHARDS must agree with it (a different N would split the
# runs differently and rerun or skip some).
mkdir -p "$out" || die "cannot create the result directory $out"
record="$out/shard-count"
n=${PUSHPACK_SHARDS:-}
if [ -z "$n" ]; then
  if [ -s "$record" ]; then
    n=$(cat "$record")
    if [ "${SLURM_ARRAY_TASK_COUNT:-$n}" != "$n" ]; then
      echo "bench-array.sh: note: $out belongs to a batch of $n shards; this array has ${SLURM_ARRAY_TASK_COUNT} tasks (a resubmission of some?), so task $k runs shard $k/$n"
    fi
  else
    n=${SLURM_ARRAY_TASK_COUNT:-}
    [ -n "$n" ] || die "cannot tell the number of shards: set PUSHPACK_SHARDS"
  fi
fi
is_count "$n" && [ "$n" -ge 1 ] || die "number of shards '$n' is not a positive number"
# Create the record atomically (hard links do not replace), then check it.
tmp="$record.$$.$(hostname -s)"
echo "$n" >"$tmp"
ln "$tmp" "$record" 2>/dev/null || true
rm -f "$tmp"
recorded=$(cat "$record")
[ "$recorded" = "$n" ] || die "$out was started with $recorded shards, this task says $n: use PUSHPACK_SHARDS=$recorded, or another PUSHPACK_OUT for a new split"
[ "$k" -lt "$n" ] || die "array task $k is not a shard of $n (shards are 0..$((n - 1))): use --array=0-$((n - 1))"

# shellcheck disable=SC2206
extra=(${PUSHPACK_BENCH_ARGS:-})
cmd=("$bin" bench "${instances[@]}" --planners "$planners" --time-limit "$time_limit"
  --jobs "$jobs" --out "$out" --shard "$k/$n" --resume "${extra[@]}")
echo "bench-array.sh: job ${SLURM_ARRAY_JOB_ID:-?} task $k, shard $k/$n on $(hostname -s), in $(pwd), $(date -u +%FT%TZ)"
echo "bench-array.sh: ${cmd[*]}"
"${cmd[@]}"
echo "bench-array.sh: shard $k/$n finished $(date -u +%FT%TZ)"
