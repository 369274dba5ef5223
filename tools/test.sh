#!/usr/bin/env bash
# The README's test command: installs what a fresh Debian 12 machine lacks (tools/setup.sh), builds
# Release, and runs every test with ctest (GPU tests on lavapipe with the validation layer on).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900
