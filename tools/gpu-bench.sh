#!/usr/bin/env bash
# One GPU benchmark run: builds Release (unless --no-build), records the device and its memory types,
# then runs the culling, virtual-shadow-map, static-evaluation and CPU benchmarks at 1920x1080 with 256
# and 4096 lights. Writes DIR/summary.json and DIR/summary.csv (one row per figure) beside each
# benchmark's own output. Meant for a desktop GPU (about 8 minutes there); on a CPU device (lavapipe)
# the full run takes hours, so there use --smoke: the same steps at 160x90 with 32 and 128 lights and
# small bakes, a few minutes, run by ctest (GpuBenchSmoke) so the script keeps working.
#
#   tools/gpu-bench.sh [--smoke] [--out DIR] [--bin PATH] [--no-build]
#
# Timing: on a GPU the passes are timed with timestamps (--timing timestamps: one command buffer per
# frame, as an engine runs it); with --smoke fenced (lavapipe's timestamps do not bracket compute).
set -euo pipefail
cd "$(dirname "$0")/.."

smoke=0 out="" bin=build/manylights build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --smoke) smoke=1 ;;
    --out) out="$2"; shift ;;
    --bin) bin="$2"; shift ;;
    --no-build) build=0 ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu-bench.sh: unknown argument '$1' (see --help)" >&2; exit 1 ;;
  esac
  shift
done

if [ "$smoke" = 1 ]; then
  size=160x90 lights=(32 128) frames=2 staticres=128 timing=fenced instances=2000
  out=${out:-out/gpu-bench-smoke}
else
  size=1920x1080 lights=(256 4096) frames=10 staticres=1024 timing=timestamps instances=10000
  out=${out:-out/gpu-bench-$(date -u +%Y%m%dT%H%M%SZ)}
fi

if [ "$build" = 1 ]; then
  bash tools/setup.sh
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j"$(nproc)" --target manylights
fi
[ -x "$bin" ] || { echo "gpu-bench.sh: no executable at $bin (build first, or --bin)" >&2; exit 1; }
mkdir -p "$out"
log() { echo "gpu-bench: $*" >&2; }
start=$(date +%s)

# The device and its memory types (vulkaninfo from vulkan-tools, when present).
if command -v vulkaninfo >/dev/null; then vulkaninfo --summary >"$out/device.txt" 2>&1 || true
  vulkaninfo 2>/dev/null | sed -n '/^VkPhysicalDeviceMemoryProperties/,/^VkPhysicalDevice[A-LN-Z]/p' \
    >"$out/memory.txt" || true
else echo "vulkaninfo not installed" >"$out/device.txt"; fi

# Each step: its command in DIR/NAME.cmd, stdout in NAME.txt, stderr in NAME.log; the last stdout line
# when it is JSON goes into the summary.
jsonl="$out/summary.jsonl"
: >"$jsonl"
step() {
  local name=$1; shift
  log "$name: $*"
  printf '%q ' "$@" >"$out/$name.cmd"; echo >>"$out/$name.cmd"
  local t0; t0=$(date +%s)
  "$@" >"$out/$name.txt" 2>"$out/$name.log" || { echo "gpu-bench.sh: step $name failed (see $out/$name.log)" >&2; tail -5 "$out/$name.log" >&2; exit 1; }
  local last; last=$(tail -n 1 "$out/$name.txt")
  case "$last" in \{*) ;; *) last='{}' ;; esac
  printf '{"step": "%s", "seconds": %d, "result": %s}\n' "$name" $(( $(date +%s) - t0 )) "$last" >>"$jsonl"
}

csvlist=$(IFS=,; echo "${lights[*]}")
step culling "$bin" bench culling --size "$size" --lights "$csvlist" --frames "$frames" \
  --culling clustered,tiled --csv "$out/culling.csv"
for n in "${lights[@]}"; do
  step "vsm-$n" "$bin" bench vsm --size "$size" --lights "$n" --frames "$frames" --vsm-raster auto \
    --kinds static-spot,point,directional --out "$out/vsm-$n"
  # Static evaluation: the evaluation pass unshadowed, then with in-module DAG-MH bakes (one tap and 3x3).
  step "eval-unshadowed-$n" "$bin" demo --size "$size" --lights "$n" --frames "$frames" --no-stats \
    --dynamic off --timing "$timing" --out "$out/eval-unshadowed-$n"
  step "eval-dagmh-$n" "$bin" demo --size "$size" --lights "$n" --frames "$frames" --no-stats \
    --dynamic off --static dagmh --static-res "$staticres" --timing "$timing" --out "$out/eval-dagmh-$n"
  step "cpu-$n" "$bin" bench cpu --lights "$n" --instances "$instances" --moving 0.01 --frames "$frames"
done

# The summary: every step's last JSON line, and each demo's per-pass means (its stats.json).
python3 - "$out" <<'EOF'
import csv, json, os, sys
out = sys.argv[1]
steps = [json.loads(l) for l in open(os.path.join(out, "summary.jsonl"))]
rows = []
for s in steps:
    for k, v in s["result"].items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            rows.append((s["step"], k, v))
    stats = os.path.join(out, s["step"], "stats.json")  # the demo steps: per-pass means
    if os.path.exists(stats):
        d = json.load(open(stats))
        s["device"] = d.get("device", "")
        s["pass_gpu_ms_mean"] = d.get("pass_gpu_ms_mean", {})
        for k, v in s["pass_gpu_ms_mean"].items():
            rows.append((s["step"], k + "_ms_mean", v))
        rows.append((s["step"], "frame_gpu_ms_median", d.get("frame_gpu_ms_median", 0)))
culling = os.path.join(out, "culling.csv")  # bench culling: one row per (lights, mode)
if os.path.exists(culling):
    with open(culling) as f:
        for r in csv.DictReader(f):
            for k in ("cull_ms", "evaluate_ms", "evaluated_per_pixel", "reaching_per_pixel"):
                rows.append(("culling-%s-%s" % (r["lights"], r["culling"]), k, float(r[k])))
device = open(os.path.join(out, "device.txt")).read()
json.dump({"device_summary": device, "steps": steps}, open(os.path.join(out, "summary.json"), "w"), indent=1)
with open(os.path.join(out, "summary.csv"), "w") as f:
    f.write("step,figure,value\n")
    for r in rows:
        f.write("%s,%s,%s\n" % r)
print("gpu-bench: %d figures in %s/summary.csv" % (len(rows), out))
EOF
log "done in $(( $(date +%s) - start )) s: $out/summary.json"
