#!/bin/sh
# The CPVS tiled bake's own memory estimate (bake/bake_estimate.h): the night city's moon (light 239) at
# 1024^2 in 128^2 tiles must print an estimate at least its measured peak, and below the estimate of the
# same bake by dagmh (the MH family's formula, a tree node per 64 texels): a CPVS bake that fell back to
# that formula prints the same figure and fails here. Usage: bake_estimate_cpvs.sh MANYLIGHTS OUTDIR
set -eu
exe=$1
out=$2
mkdir -p "$out"
"$exe" bake --method cpvs --res 1024 --lights 239 --tile 128 --quiet --out "$out/cpvs.mlbk" > /dev/null 2> "$out/cpvs.txt"
"$exe" bake --method dagmh --res 1024 --lights 239 --tile 128 --quiet --out "$out/dagmh.mlbk" > /dev/null 2> "$out/dagmh.txt"
mib() { sed -n "s/.*$1 peak memory \([0-9]*\) MiB.*/\1/p" "$2" | tail -1; }
estimate=$(mib estimated "$out/cpvs.txt")
measured=$(mib measured "$out/cpvs.txt")
mh=$(mib estimated "$out/dagmh.txt")
[ -n "$estimate" ] && [ -n "$measured" ] && [ -n "$mh" ] || { echo "a peak line is missing"; cat "$out/cpvs.txt" "$out/dagmh.txt"; exit 1; }
[ "$estimate" -ge "$measured" ] || { echo "cpvs estimate $estimate MiB is below the measured peak $measured MiB"; exit 1; }
[ "$estimate" -lt "$mh" ] || { echo "cpvs estimate $estimate MiB is not below the MH formula's $mh MiB"; exit 1; }
echo "cpvs 1024^2 in 128^2 tiles: estimate $estimate MiB >= measured $measured MiB, below the MH formula's $mh MiB"
