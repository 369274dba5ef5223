#!/usr/bin/env python3
"""CliVsmStepTimers: the demo's outputs report each VSM step as its own scope (manylights/pass_times.h).
Runs `manylights demo` (fenced timing, the default on lavapipe) and checks that
  - stats.json's pass_gpu_ms_mean holds every step (vsm_mark, vsm_sort, vsm_alloc, vsm_hpb,
    vsm_group_cull, vsm_cull or vsm_expand, vsm_draw), each >= 0;
  - the bookkeeping steps' means add up to vsm_bookkeeping_gpu_ms_mean, and all passes' means to
    frame_gpu_ms_mean, within the printed rounding (%.6g);
  - frames.csv has a row per step and frame, each >= 0;
  - tools/vsm_bookkeeping.py reads the folder and prints the per-step table.
Usage: vsm_steps_check.py EXE OUT_DIR SOURCE_DIR"""
import csv
import json
import os
import subprocess
import sys

STEPS = ("vsm_mark", "vsm_sort", "vsm_alloc", "vsm_hpb", "vsm_group_cull", "vsm_draw")
CULLING = ("vsm_cull", "vsm_expand")  # one per raster path
FRAMES = 3


def fail(message):
    sys.exit("vsm_steps_check: " + message)


def close(a, b):
    # Both sides printed with 6 significant digits: a few units of the 6th digit per summed term.
    return abs(a - b) <= 1e-5 * max(abs(a), abs(b)) * 8 + 1e-9


def main(exe, out, source):
    cmd = [exe, "demo", "--frames", str(FRAMES), "--size", "160x90", "--out", out]
    run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if run.returncode != 0:
        fail(f"{' '.join(cmd)} exited with {run.returncode}:\n{run.stdout[-3000:]}")
    with open(os.path.join(out, "stats.json")) as f:
        stats = json.load(f)
    passes = stats["pass_gpu_ms_mean"]
    culling = [k for k in CULLING if k in passes]
    if len(culling) != 1:
        fail(f"want exactly one of {CULLING} in pass_gpu_ms_mean, got {culling}")
    steps = STEPS + tuple(culling)
    for k in steps:
        if k not in passes:
            fail(f"stats.json pass_gpu_ms_mean lacks {k}: {sorted(passes)}")
        if passes[k] < 0:
            fail(f"stats.json pass_gpu_ms_mean.{k} = {passes[k]} < 0")
    if "vsm_bookkeeping_gpu_ms_mean" not in stats:
        fail("stats.json lacks vsm_bookkeeping_gpu_ms_mean")
    total = stats["vsm_bookkeeping_gpu_ms_mean"]
    parts = sum(passes[k] for k in steps if k != "vsm_draw")
    if not close(parts, total):
        fail(f"bookkeeping steps sum to {parts} ms, vsm_bookkeeping_gpu_ms_mean is {total}")
    if not close(sum(passes.values()), stats["frame_gpu_ms_mean"]):
        fail(f"pass means sum to {sum(passes.values())} ms, frame_gpu_ms_mean is {stats['frame_gpu_ms_mean']}")
    seen = {}
    with open(os.path.join(out, "frames.csv"), newline="") as f:
        for r in csv.DictReader(f):
            if r["pass"] in steps:
                if float(r["gpu_ms"]) < 0:
                    fail(f"frames.csv: frame {r['frame']} {r['pass']} = {r['gpu_ms']} < 0")
                seen.setdefault(r["pass"], set()).add(int(r["frame"]))
    for k in steps:
        if seen.get(k) != set(range(FRAMES)):
            fail(f"frames.csv: {k} in frames {sorted(seen.get(k, ()))}, want 0..{FRAMES - 1}")
    tool = subprocess.run([sys.executable, os.path.join(source, "tools", "vsm_bookkeeping.py"), out],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if tool.returncode != 0 or "| sort ms |" not in tool.stdout or "| group_cull ms |" not in tool.stdout:
        fail(f"tools/vsm_bookkeeping.py {out}: exit {tool.returncode}, no per-step table:\n{tool.stdout}")
    print(tool.stdout)
    print(f"vsm_steps_check: {len(steps)} steps, bookkeeping {total} ms = sum of its steps")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 4:
        fail(__doc__)
    sys.exit(main(*sys.argv[1:]))
