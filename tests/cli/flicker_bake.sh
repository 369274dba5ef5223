#!/bin/sh
# `bench flicker --bake`: the night city's moon (light 239) from stored MH and DAG-MH records at 256^2,
# 2 frames at 96x54, one tap and 3x3, each also by level: one row per file, radius and filter, pairs
# compared. A file of another light's record, or of another scene's lights, is refused with exit 2.
# Usage: flicker_bake.sh MANYLIGHTS OUTDIR
set -eu
exe=$1
out=$2
rm -rf "$out"
mkdir -p "$out"
"$exe" bake --method mh --res 256 --lights 239 --quiet --out "$out/mh.mlbk" > /dev/null
"$exe" bake --method dagmh --res 256 --lights 239 --quiet --out "$out/dagmh.mlbk" > /dev/null
"$exe" bench flicker --bake "$out/mh.mlbk,$out/dagmh.mlbk" --pcf 0,1 --by-level --frames 2 --size 96x54 \
    --out "$out/run" > "$out/table.txt" 2> "$out/err.txt"
rows=$(grep -c '^| \(mh\|dagmh\) | 256 |' "$out/table.txt")
[ "$rows" = 8 ] || { echo "expected 8 rows (mh 4, dagmh 4), got $rows"; cat "$out/table.txt"; exit 1; }
for m in mh dagmh; do
    grep -q "^| $m | 256 | 3x3 by level | [1-9]" "$out/table.txt" || { echo "no $m pairs by level"; cat "$out/table.txt"; exit 1; }
done
"$exe" bake --method mh --res 256 --lights 3 --quiet --out "$out/other.mlbk" > /dev/null
if "$exe" bench flicker --bake "$out/mh.mlbk,$out/other.mlbk" --frames 2 --size 96x54 --out "$out/bad" 2> "$out/bad.txt"; then
    echo "a file without light 239 was accepted"; exit 1
fi
grep -q "no record of light 239" "$out/bad.txt"
echo "bench flicker --bake: 8 rows over the same pairs; a file without the light refused"
