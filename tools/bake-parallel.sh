#!/usr/bin/env bash
# A sharded bake on one machine: N `manylights bake ... --shard I/N` processes at once, then
# `manylights merge`. The result is byte-identical to a single `manylights bake` with the same flags.
#
#   tools/bake-parallel.sh [--jobs N] [--keep-parts] BAKE-FLAGS...
#     BAKE-FLAGS   exactly the flags of `manylights bake` (--method, --res, --lights, --out, ...)
#     --jobs N     shard processes (default: nproc); each renders and encodes its own lights
#     --keep-parts keep the part files (in OUT.parts/) instead of deleting them after the merge
#   MANYLIGHTS=path/to/manylights overrides the binary (default: the worktree's build/manylights,
#   else `manylights` on PATH).
#
# Parts and logs go to OUT.parts/ beside --out. A failing shard stops the run: its log is printed, the
# exit status is the first failing shard's (1: a usage error, 2: a bad input file), and nothing is merged.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
exe=${MANYLIGHTS:-}
if [[ -z "$exe" ]]; then
  if [[ -x "$here/../build/manylights" ]]; then exe="$here/../build/manylights"; else exe=manylights; fi
fi

jobs=$(nproc)
keep=0
out=""
bake_args=()
while (($#)); do
  case "$1" in
    --jobs)
      [[ $# -ge 2 && "$2" =~ ^[1-9][0-9]*$ ]] || { echo "bake-parallel: --jobs needs a whole number >= 1" >&2; exit 2; }
      jobs=$2; shift 2 ;;
    --keep-parts) keep=1; shift ;;
    --out)
      [[ $# -ge 2 ]] || { echo "bake-parallel: --out: missing value" >&2; exit 2; }
      out=$2; shift 2 ;;
    --shard) echo "bake-parallel: --shard is chosen by the runner (see --jobs)" >&2; exit 2 ;;
    -h|--help)
      sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) bake_args+=("$1"); shift ;;
  esac
done
[[ -n "$out" ]] || { echo "bake-parallel: --out: required (see --help)" >&2; exit 2; }
[[ -d "$(dirname -- "$out")" ]] || { echo "bake-parallel: --out: $(dirname -- "$out") is not a directory" >&2; exit 2; }

parts="$out.parts"
mkdir -p "$parts"
rm -f "$parts"/shard-*.mlbp "$parts"/shard-*.log

start=$(date +%s.%N)
echo "bake-parallel: $jobs shards running, logs in $parts/shard-I.log"
pids=()
for ((i = 0; i < jobs; i++)); do
  "$exe" bake "${bake_args[@]}" --shard "$i/$jobs" --out "$parts/shard-$i.mlbp" >"$parts/shard-$i.log" 2>&1 &
  pids+=($!)
done
failed=0
for ((i = 0; i < jobs; i++)); do
  rc=0
  wait "${pids[$i]}" || rc=$?
  if ((rc != 0)); then
    echo "bake-parallel: shard $i/$jobs failed (exit $rc); its log ($parts/shard-$i.log):" >&2
    cat "$parts/shard-$i.log" >&2
    ((failed != 0)) || failed=$rc
  fi
done
((failed == 0)) || exit "$failed"

part_files=()
for ((i = 0; i < jobs; i++)); do part_files+=("$parts/shard-$i.mlbp"); done
"$exe" merge "${part_files[@]}" --out "$out"
end=$(date +%s.%N)
awk -v s="$start" -v e="$end" -v j="$jobs" 'BEGIN { printf "bake-parallel: %d shards, %.2f s wall\n", j, e - s }'
if ((keep == 0)); then rm -rf "$parts"; fi
