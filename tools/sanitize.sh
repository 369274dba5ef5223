#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/) and the whole ctest under it.
#   tools/sanitize.sh [extra ctest arguments, e.g. -R Hostile]     (release check: ~35 min cold here)
#   tools/sanitize.sh --cpu [FUZZ_SECONDS, default 20]               (CI, .ci/run: a few minutes)
# --cpu builds only the CPU-side libraries that read untrusted bytes or encode (io/, the bake-file reader
# and writer and the encoders in shadows/static/, the glTF loader in scenes/, the bake driver) with their
# gtest areas (static_tests, scenes_tests) and the fuzz targets, in build-asan-cpu/, and runs them:
# every test (each gtest binary in JOBS shards at once, default 2), then the fuzz targets side by side
# for FUZZ_SECONDS each from seed 1. No Vulkan device is involved.
# Any ASan report or UBSan finding fails the test that hit it (-fno-sanitize-recover). Leak checking
# is off by default: the Vulkan loader and lavapipe keep allocations alive until exit (set
# ASAN_OPTIONS yourself to turn it on). allocator_may_return_null=1 lets a huge allocation throw
# bad_alloc as in a normal build (a test feeds a 4 TiB sparse file). Times are printed at the end (build, ctest).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build-asan}
JOBS=${JOBS:-2}
FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g1"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
configure() {
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
    -DCMAKE_CXX_FLAGS="$FLAGS" -DCMAKE_C_FLAGS="$FLAGS" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
}

if [ "${1:-}" = --cpu ]; then
  FUZZ_SECONDS=${2:-20}
  case "$FUZZ_SECONDS" in ''|*[!0-9]*) echo "sanitize.sh: --cpu takes seconds per fuzz target, got '$FUZZ_SECONDS'" >&2; exit 1 ;; esac
  BUILD_DIR=${BUILD_DIR_CPU:-build-asan-cpu}
  t0=$(date +%s)
  configure
  cmake --build "$BUILD_DIR" -j"$JOBS" --target static_tests scenes_tests fuzz_inputs
  t1=$(date +%s)
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:halt_on_error=1:allocator_may_return_null=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  status=0
  # JOBS processes at once (the CI machine has 2 cores; the instrumented tests were half of CI's time
  # when run one after another): each gtest binary split into JOBS shards (GTEST_SHARD_INDEX), then the
  # fuzz targets side by side. Each job's output goes to its own log, printed when it ends.
  logs=$(mktemp -d)
  run_jobs() { # each argument "NAME|COMMAND": the commands run at once; status=1 when one fails
    local pids=() names=() i
    for job in "$@"; do
      names+=("${job%%|*}")
      bash -c "${job#*|}" >"$logs/${#pids[@]}.log" 2>&1 &
      pids+=($!)
    done
    for i in "${!pids[@]}"; do
      if ! wait "${pids[$i]}"; then
        echo "sanitize.sh: ${names[$i]} failed under ASan/UBSan" >&2
        status=1
      fi
      cat "$logs/$i.log"
    done
  }
  for t in static_tests scenes_tests; do
    shards=()
    for ((i = 0; i < JOBS; ++i)); do
      shards+=("$t shard $i of $JOBS|GTEST_TOTAL_SHARDS=$JOBS GTEST_SHARD_INDEX=$i '$BUILD_DIR/$t' --gtest_brief=1")
    done
    run_jobs "${shards[@]}"
  done
  fuzz=()
  for target in bake gltf; do
    fuzz+=("fuzz target $target (seed 1)|'$BUILD_DIR/fuzz_inputs' $target --seconds $FUZZ_SECONDS --seed 1")
  done
  run_jobs "${fuzz[@]}"
  rm -rf "$logs"
  t2=$(date +%s)
  echo "sanitize.sh --cpu: build $((t1 - t0)) s, tests and fuzzers $((t2 - t1)) s, exit $status"
  exit $status
fi

t0=$(date +%s)
configure
cmake --build "$BUILD_DIR" -j"$JOBS"
t1=$(date +%s)
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:halt_on_error=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
ctest --test-dir "$BUILD_DIR" --output-on-failure "$@" || status=$?
t2=$(date +%s)
echo "sanitize.sh: build $((t1 - t0)) s, ctest $((t2 - t1)) s, exit $status"
exit $status
