#!/usr/bin/env bash
# The README's demo command: setup, build, bake the night city's static shadows (DAG-MH, 1024^2 per
# static spot light, Vulkan-rendered dual depth maps; reused when present), then render the night city
# headless with them. Extra arguments go to `manylights demo` (e.g. --frames 10 --size 640x360).
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
./build/manylights demo --scene night-city --frames 3 --bake "$bake" --pcf 1 --out out/demo "$@"
