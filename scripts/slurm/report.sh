#!/bin/bash
# After a scripts/slurm/bench-array.sh batch: check that every shard's result file is there and
# holds a row for each of its runs, then merge the shards with `pushpack report`. Exits 1, naming
# the shards, when any is missing or incomplete (resubmit those tasks: `sbatch --array=K,...`),
# so that a report is never drawn silently from part of a batch. docs/cluster.md.
#
#   scripts/slurm/report.sh [INSTANCES...]
#
# It reads the settings bench-array.sh read: PUSHPACK_DIR, PUSHPACK_BIN, PUSHPACK_INSTANCES (or
# arguments), PUSHPACK_PLANNERS, PUSHPACK_OUT, with the same defaults; and PUSHPACK_REPORT, the
# report directory (default $PUSHPACK_OUT/report). PUSHPACK_PARTIAL=1 reports what is there,
# listing what is missing, instead of failing.
set -euo pipefail

die() {
  echo "report.sh: error: $*" >&2
  exit 1
}

if [ -n "${PUSHPACK_DIR:-}" ]; then
  cd "$PUSHPACK_DIR" || die "PUSHPACK_DIR=$PUSHPACK_DIR: no such directory"
fi
bin=${PUSHPACK_BIN:-target/release/pushpack}
planners=${PUSHPACK_PLANNERS:-bl+paper+packing-only,bl+astar+packing-only,milp+astar+packing-only}
out=${PUSHPACK_OUT:-out/bench}
report=${PUSHPACK_REPORT:-$out/report}
if [ $# -gt 0 ]; then
  instances=("$@")
else
  # shellcheck disable=SC2206
  instances=(${PUSHPACK_INSTANCES:-instances/random/n*})
fi
[ -x "$bin" ] || die "pushpack binary '$bin' is missing or not executable (relative to $(pwd)); set PUSHPACK_BIN"
[ -d "$out" ] || die "result directory '$out' does not exist (relative to $(pwd)); set PUSHPACK_OUT"
[ -s "$out/shard-count" ] || die "$out/shard-count is missing: no bench-array.sh task has started in $out"
n=$(cat "$out/shard-count")
[[ $n =~ ^[0-9]+$ ]] && [ "$n" -ge 1 ] || die "$out/shard-count holds '$n', not a number of shards"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
files=()
bad=()
for ((k = 0; k < n; k++)); do
  f="$out/results.shard-$k-of-$n.jsonl"
  if [ ! -s "$f" ]; then
    echo "report.sh: shard $k/$n: no results ($f is missing or empty)"
    bad+=("$k")
    continue
  fi
  files+=("$f")
  # Ask pushpack which runs the shard has and which are done, on a copy: --max-runs 0 runs
  # nothing, and the copy keeps the real files untouched while tasks may still write them.
  rm -rf "$scratch/s" && mkdir "$scratch/s" && cp "$f" "$scratch/s/"
  "$bin" bench "${instances[@]}" --planners "$planners" --jobs 1 --out "$scratch/s" \
    --shard "$k/$n" --resume --max-runs 0 >"$scratch/log" 2>&1 || true
  line=$(grep '^bench: ' "$scratch/log" || true)
  if [[ $line =~ ^bench:\ ([0-9]+)\ runs\ in\ this\ shard,\ ([0-9]+)\ already\ done ]]; then
    total=${BASH_REMATCH[1]}
    done_=${BASH_REMATCH[2]}
  else
    cat "$scratch/log" >&2
    die "cannot read the state of shard $k/$n from 'pushpack bench --max-runs 0' (instances '${instances[*]}', planners $planners): check that the settings are the batch's"
  fi
  if [ "$done_" -lt "$total" ]; then
    echo "report.sh: shard $k/$n: $done_ of $total runs done"
    bad+=("$k")
  else
    echo "report.sh: shard $k/$n: all $total runs done"
  fi
done

if [ ${#bad[@]} -gt 0 ]; then
  list=$(
    IFS=,
    echo "${bad[*]}"
  )
  if [ "${PUSHPACK_PARTIAL:-0}" != 1 ]; then
    die "shards $list of $n are missing or incomplete: resubmit them with 'sbatch --array=$list scripts/slurm/bench-array.sh' (same settings), or set PUSHPACK_PARTIAL=1 to report what is there"
  fi
  echo "report.sh: PUSHPACK_PARTIAL=1: reporting although shards $list are missing or incomplete" >&2
fi
[ ${#files[@]} -gt 0 ] || die "no shard has results yet"
"$bin" report "${files[@]}" --out "$report"
echo "report.sh: $report/summary.md"
