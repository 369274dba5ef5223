#!/usr/bin/env bash
# The README's demo command: setup, build, bake the night city's static shadows (DAG-MH, 1024^2 per
# static spot light, Vulkan-rendered dual depth maps; reused when present), then render the night city
# headless with them. Extra arguments go to `manylights demo` (e.g. --frames 10 --size 640x360) and
# replace the defaults below of the same flags.
# Output: out/demo/ (frames, profile.json, frames.csv, stats.json) and out/night-city-dagmh-1024.mlbk.
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
# Defaults the extra arguments may replace (demo refuses a flag given twice).
args=()
given() { local f; for f in "${extra[@]}"; do [ "$f" = "$1" ] && return 0; done; return 1; }
extra=("$@")
given --scene || args+=(--scene night-city)
given --frames || args+=(--frames 3)
given --bake || given --static || args+=(--bake "$bake")
given --pcf || args+=(--pcf 1)
given --out || args+=(--out out/demo)
./build/manylights demo "${args[@]}" "$@"
