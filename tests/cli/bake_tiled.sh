#!/bin/sh
# Tiled bakes against whole-map bakes: the night city's moon (light 239 of 256) at 512^2, whole and in
# 128^2 tiles, must be the same file byte for byte for mh, mmh and dagmh, and the streaming verify in
# 64^2 tiles must find 0 mismatches; 4 tile shards merged must equal it too. Usage: bake_tiled.sh MANYLIGHTS OUTDIR
set -eu
exe=$1
out=$2
mkdir -p "$out"
for m in mh mmh dagmh; do
    "$exe" bake --method "$m" --res 512 --lights 239 --quiet --out "$out/moon_whole_$m.mlbk" > /dev/null
    "$exe" bake --method "$m" --res 512 --lights 239 --tile 128 --quiet --out "$out/moon_tiled_$m.mlbk" > /dev/null
    cmp "$out/moon_whole_$m.mlbk" "$out/moon_tiled_$m.mlbk"
    "$exe" verify "$out/moon_tiled_$m.mlbk" --tile 64 --quiet > "$out/verify_$m.txt"
    grep -q '"mismatches": 0}' "$out/verify_$m.txt" || { echo "$m: tiled verify found mismatches"; cat "$out/verify_$m.txt"; exit 1; }
    grep -q '"checked": 262144,' "$out/verify_$m.txt" || { echo "$m: tiled verify did not check every texel"; exit 1; }
    echo "$m: tiled bake equals the whole-map bake, verify 0 mismatches"
done
# One light's tiles in 4 shards (tile parts), merged: the single bake's file byte for byte; a missing
# shard is refused.
for i in 0 1 2 3; do
    "$exe" bake --method dagmh --res 512 --lights 239 --tile 64 --shard "$i/4" --quiet --out "$out/moon_tiles_$i.mltp" > /dev/null
done
"$exe" inspect "$out/moon_tiles_1.mltp" | grep -q "tile part 1/4 of light 239 (dagmh at 512^2, 64^2 tiles): 16 of 64 tiles"
"$exe" inspect "$out/moon_tiles_1.mltp" --json | grep -q '"part": "tiles", "method": "dagmh", "resolution": 512, "tile": 64, "light": 239, "shard": 1, "shards": 4, "tiles": 16, "tiles_total": 64'
"$exe" merge "$out"/moon_tiles_*.mltp --out "$out/moon_merged.mlbk" --quiet
cmp "$out/moon_whole_dagmh.mlbk" "$out/moon_merged.mlbk"
if "$exe" merge "$out/moon_tiles_0.mltp" "$out/moon_tiles_1.mltp" "$out/moon_tiles_3.mltp" --out "$out/bad.mlbk" 2> "$out/merge_err.txt"; then
    echo "a merge without shard 2 was accepted"; exit 1
fi
grep -q "shard 2/4 is missing" "$out/merge_err.txt"
echo "dagmh: 4 tile shards merged equal the whole-map bake; a missing shard is refused"
