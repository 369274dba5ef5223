#!/bin/sh
# The Slurm recipe (tools/farm/slurm-bake.sbatch, slurm-merge.sbatch) on one light's tiles: the night
# city's moon at 512^2 in 64^2 tiles, as a 3-task array run here with the variables Slurm sets, then
# the merge script; the merged file must equal the single bake's byte for byte.
# Usage: farm_tile_shards.sh MANYLIGHTS SOURCE_DIR OUTDIR
set -eu
exe=$1
src=$2
out=$3
rm -rf "$out"
mkdir -p "$out"
for i in 0 1 2; do
    SHARED="$out" MANYLIGHTS="$exe" SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=3 SLURM_ARRAY_TASK_MIN=0 \
        SLURM_ARRAY_TASK_MAX=2 bash "$src/tools/farm/slurm-bake.sbatch" --method dagmh --res 512 --lights 239 \
        --tile 64 --quiet > "$out/task_$i.txt"
    grep -q "wrote tile part" "$out/task_$i.txt" || { echo "task $i did not write a tile part"; cat "$out/task_$i.txt"; exit 1; }
done
SHARED="$out" MANYLIGHTS="$exe" OUT=moon.mlbk bash "$src/tools/farm/slurm-merge.sbatch" > "$out/merge.txt"
"$exe" bake --method dagmh --res 512 --lights 239 --tile 64 --quiet --out "$out/single.mlbk" > /dev/null
cmp "$out/single.mlbk" "$out/moon.mlbk"
echo "slurm recipe: 3 tile shards of light 239 merged equal the single bake"
