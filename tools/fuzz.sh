#!/usr/bin/env bash
# Long fuzz run of the bake-file reader and the glTF loader (tests/fuzz/fuzz_inputs_test.cpp).
#   tools/fuzz.sh [SECONDS per target, default 600] [bake|gltf|all, default all] [first SEED, default 1]
# Runs each target in 60-second chunks with successive seeds (ctest runs seed 1 for 5 s). On a finding
# it stops and prints how to reproduce and dump the input. BUILD_DIR (default build) is configured and
# fuzz_inputs built there if missing; use BUILD_DIR=build-asan after tools/sanitize.sh for ASan/UBSan.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-600}
TARGETS=${2:-all}
SEED=${3:-1}
BUILD_DIR=${BUILD_DIR:-build}
[ "$TARGETS" = all ] && TARGETS="bake gltf"
if [ ! -x "$BUILD_DIR/fuzz_inputs" ]; then
  [ -f "$BUILD_DIR/CMakeCache.txt" ] || cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$BUILD_DIR" -j2 --target fuzz_inputs >/dev/null
fi
for target in $TARGETS; do
  start=$(date +%s)
  seed=$SEED
  while :; do
    elapsed=$(( $(date +%s) - start ))
    left=$(( SECONDS_PER_TARGET - elapsed ))
    [ "$left" -le 0 ] && break
    chunk=$(( left < 60 ? left : 60 ))
    if ! "$BUILD_DIR/fuzz_inputs" "$target" --seconds "$chunk" --seed "$seed"; then
      echo "fuzz.sh: FINDING in $target with seed $seed. Reproduce: $BUILD_DIR/fuzz_inputs $target --seed $seed" \
           "--seconds $chunk; the failing iteration I is printed above (or is the last one reached):" \
           "dump it with --dump-at I --dump-dir DIR." >&2
      exit 1
    fi
    seed=$(( seed + 1 ))
  done
  echo "fuzz.sh: $target ran $(( $(date +%s) - start )) s, seeds $SEED..$(( seed - 1 )), no findings"
done
