#!/bin/sh
# Tiled bakes against whole-map bakes: the night city's moon (light 239 of 256) at 512^2, whole and in
# 128^2 tiles, must be the same file byte for byte for mh, mmh and dagmh, and the streaming verify in
# 64^2 tiles must find 0 mismatches. Usage: bake_tiled.sh MANYLIGHTS OUTDIR
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
