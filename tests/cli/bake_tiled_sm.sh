#!/bin/sh
# SM in tiles against whole-map bakes: the night city's moon (light 239 of 256, a fitted directional map
# with fewer rows than columns) and spot light 0, at 512^2 whole and in 64^2 tiles, must be the same
# file byte for byte, and the tiled verify must find 0 mismatches over every texel. Every light of the
# indoor scene (point lights: six faces) at 128^2 must give the same file too. SM past 16384^2 is
# refused, with or without --tile, with the output's size as the reason.
# Usage: bake_tiled_sm.sh MANYLIGHTS OUTDIR
set -eu
exe=$1
out=$2
mkdir -p "$out"
for l in 239 0; do
    "$exe" bake --method sm --res 512 --lights $l --renderer cpu --quiet --out "$out/whole_$l.mlbk" > /dev/null
    "$exe" bake --method sm --res 512 --lights $l --renderer cpu --tile 64 --quiet --out "$out/tiled_$l.mlbk" > "$out/bake_$l.txt"
    grep -q "tiles, " "$out/bake_$l.txt" || { echo "light $l: the bake did not go tile by tile"; cat "$out/bake_$l.txt"; exit 1; }
    cmp "$out/whole_$l.mlbk" "$out/tiled_$l.mlbk"
    "$exe" verify "$out/tiled_$l.mlbk" --tile 64 --quiet > "$out/verify_$l.txt"
    grep -q '"mismatches": 0}' "$out/verify_$l.txt" || { echo "light $l: tiled verify found mismatches"; cat "$out/verify_$l.txt"; exit 1; }
    grep -q '"checked": 262144,' "$out/verify_$l.txt" || { echo "light $l: verify did not check every texel"; exit 1; }
    echo "sm light $l: tiled bake equals the whole-map bake, verify 0 mismatches"
done
# Every light of the indoor scene, spots and point lights' six cube faces, at 128^2 in 64^2 tiles.
"$exe" bake --scene indoor --method sm --res 128 --lights all --renderer cpu --quiet --out "$out/indoor_whole.mlbk" > /dev/null
"$exe" bake --scene indoor --method sm --res 128 --lights all --renderer cpu --tile 64 --quiet --out "$out/indoor_tiled.mlbk" > /dev/null
cmp "$out/indoor_whole.mlbk" "$out/indoor_tiled.mlbk"
echo "sm indoor: every spot and point light face tiled equals the whole-map bake"
for tile in "" "--tile 512"; do
    if "$exe" bake --method sm --res 32768 --lights 239 $tile --quiet --out "$out/bad.mlbk" 2> "$out/err.txt"; then
        echo "sm at 32768^2 ($tile) was accepted"; exit 1
    fi
    grep -q "sm stores 4 B a texel: 32768^2 is 4096 MiB, past any storage buffer a device binds" "$out/err.txt" ||
        { echo "sm at 32768^2 ($tile): not the output's size as the reason"; cat "$out/err.txt"; exit 1; }
done
echo "sm past 16384^2 refused with its output's size, whole or in tiles"
