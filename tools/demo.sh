#!/usr/bin/env bash
# The README's demo command: setup, build, bake the night city's static shadows (DAG-MH, 1024^2 per
# static spot light, Vulkan-rendered dual depth maps; the moon, light 239, at 16384^2 in 512^2 tiles on
# the CPU rasteriser: about a minute and under 1 GiB; both reused when present), then render the night
# city headless with them (the moon's 16384^2 record replaces its 1024^2 one). Extra arguments go to `manylights demo` (e.g. --frames 10 --size 640x360) and
# replace the defaults below of the same flags.
# Output: out/demo/ (frames, profile.json, frames.csv, stats.json), out/night-city-dagmh-1024.mlbk and
# out/night-city-moon-dagmh-16384.mlbk.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target manylights
mkdir -p out
bake=out/night-city-dagmh-1024.mlbk
if ! ./build/manylights inspect "$bake" >/dev/null 2>&1; then
  ./build/manylights bake --scene night-city --method dagmh --res 1024 --lights all --out "$bake"
fi
moon=out/night-city-moon-dagmh-16384.mlbk
if ! ./build/manylights inspect "$moon" >/dev/null 2>&1; then
  ./build/manylights bake --scene night-city --method dagmh --res 16384 --tile 512 --lights 239 --out "$moon"
fi
# Defaults the extra arguments may replace (demo refuses a flag given twice).
args=()
given() { local f; for f in "${extra[@]}"; do [ "$f" = "$1" ] && return 0; done; return 1; }
extra=("$@")
given --scene || args+=(--scene night-city)
given --frames || args+=(--frames 3)
given --bake || given --static || args+=(--bake "$bake,$moon")
given --pcf || args+=(--pcf 1)
given --out || args+=(--out out/demo)
./build/manylights demo "${args[@]}" "$@"
