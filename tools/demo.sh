#!/usr/bin/env bash
# The README's demo command: setup, build, then the night city headless. Extra arguments go to
# `manylights demo` (e.g. --frames 10 --size 640x360 --lights 1024). Output: out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target manylights
./build/manylights demo --scene night-city --frames 3 --out out/demo "$@"
