#!/bin/sh
# Tiled CPVS bakes against whole-map bakes: the night city's moon (light 239 of 256, directional: linear
# slices) at 512^2, whole and in 64^2 tiles, must be the same file byte for byte, and the streaming verify
# in 128^2 tiles must check every voxel (checked + undefined = 512^3) with 0 mismatches. A tile shard
# of a CPVS bake is refused with one line. Usage: bake_tiled_cpvs.sh MANYLIGHTS OUTDIR
set -eu
exe=$1
out=$2
mkdir -p "$out"
"$exe" bake --method cpvs --res 512 --lights 239 --quiet --out "$out/moon_whole.mlbk" > /dev/null
"$exe" bake --method cpvs --res 512 --lights 239 --tile 64 --quiet --out "$out/moon_tiled.mlbk" > "$out/bake.txt"
grep -q "tiles, " "$out/bake.txt" || { echo "the bake did not go tile by tile"; cat "$out/bake.txt"; exit 1; }
cmp "$out/moon_whole.mlbk" "$out/moon_tiled.mlbk"
"$exe" verify "$out/moon_tiled.mlbk" --tile 128 --quiet > "$out/verify.txt"
grep -q '"mismatches": 0}' "$out/verify.txt" || { echo "tiled verify found mismatches"; cat "$out/verify.txt"; exit 1; }
# every voxel: the checked ones and the undefined ones (inside closed objects) make 512^3
checked=$(sed -n 's/.*"checked": \([0-9]*\).*/\1/p' "$out/verify.txt" | tail -1)
undefined=$(sed -n 's/.*mismatches, \([0-9]*\) undefined.*/\1/p' "$out/verify.txt" | tail -1)
[ "$((checked + ${undefined:-0}))" -eq 134217728 ] || { echo "verify covered $checked + ${undefined:-0} voxels"; cat "$out/verify.txt"; exit 1; }
echo "cpvs: tiled bake equals the whole-map bake, tiled verify 0 mismatches over every voxel"
if "$exe" bake --method cpvs --res 512 --lights 239 --tile 64 --shard 0/2 --quiet --out "$out/part.mltp" 2> "$out/shard_err.txt"; then
    echo "a tile shard of a CPVS bake was accepted"; exit 1
fi
grep -q "tile shards build mh, mmh or dagmh" "$out/shard_err.txt"
