#!/bin/bash
# Queues a sharded bake on Slurm: an array job of N shards, then the merge, which starts only when every
# shard succeeded (afterok). Parts, logs and the merged file go to $SHARED, which every node must see.
#   SHARED=/shared/bakes/run1 [MANYLIGHTS=/shared/bin/manylights] [OUT=bake.mlbk] \
#     tools/farm/slurm-submit.sh N BAKE-FLAGS...      e.g. ... 16 --method dagmh --res 16384 --lights all
# Extra sbatch options (partition, account, time, memory) go in SBATCH_EXTRA, e.g. "-p gpu --time=4:00:00".
set -euo pipefail

# --- set these ----------------------------------------------------------------------------------------
SHARED=${SHARED:?set SHARED to a directory that every node can write, e.g. /lustre/proj/bakes/run1}
MANYLIGHTS=${MANYLIGHTS:-manylights}
OUT=${OUT:-bake.mlbk}
SBATCH_EXTRA=${SBATCH_EXTRA:-}
# ------------------------------------------------------------------------------------------------------

[[ $# -ge 2 && "$1" =~ ^[1-9][0-9]*$ ]] || { sed -n '2,8p' "$0"; exit 2; }
N=$1
shift
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$SHARED/logs" "$SHARED/parts"
if compgen -G "$SHARED/parts/shard-*.mlbp" >/dev/null; then
  echo "slurm-submit: $SHARED/parts already holds parts of another run; use a fresh SHARED" >&2
  exit 2
fi
export SHARED MANYLIGHTS OUT
# shellcheck disable=SC2086  # SBATCH_EXTRA is a list of options
bake=$(sbatch --parsable $SBATCH_EXTRA --array="0-$((N - 1))" --export=ALL \
  --output="$SHARED/logs/bake-%A_%a.out" "$here/slurm-bake.sbatch" "$@")
bake=${bake%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable $SBATCH_EXTRA --dependency="afterok:$bake" --kill-on-invalid-dep=yes --export=ALL \
  --output="$SHARED/logs/merge-%j.out" "$here/slurm-merge.sbatch")
echo "slurm-submit: bake array job $bake (shards 0-$((N - 1))), merge job $merge -> $SHARED/$OUT"
