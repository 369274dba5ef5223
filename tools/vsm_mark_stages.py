#!/usr/bin/env python3
"""Where the VSM mark pass's time goes: runs the demo once per profiling stage of vsm_mark.comp
(ML_VSM_MARK_STAGE, see the shader's kStage), the stages alternating for --rounds rounds, and prints a
Markdown table of the pass's mean time (frames 1.., fenced timing from frames.csv) at each stage, the
part each stage adds, and each as a fraction of the evaluation pass of the full (stage 0) runs.
Stages 1-5 mark nothing, so only stage 0's frames are real ones.
With --cluster the runs mark per cluster (--vsm-mark cluster) and the stages are vsm_mark_cluster.comp's.

Usage: python3 tools/vsm_mark_stages.py [--binary build/manylights] [--scene night-city] [--lights 256]
       [--frames 8] [--rounds 3] [--size 640x360] [--cluster] [--out DIR]"""
import argparse
import collections
import csv
import os
import subprocess
import sys
import tempfile

STAGES = (
    (1, "dispatch only (returns at once)"),
    (2, "+ depth read"),
    (3, "+ normal, world position, cluster lookup"),
    (4, "+ light loop: reach and facing tests"),
    (5, "+ marking, local lights"),
    (0, "+ marking, directional light (the full pass)"),
)
CLUSTER_STAGES = (
    (1, "tile mask, receiver bounds, light range"),
    (2, "+ light loop: reach and facing tests"),
    (3, "+ counting the whole box's pages"),
    (4, "+ counting the halves' pages"),
    (5, "+ marking the boxes (no per-pixel refinement)"),
    (0, "+ per-pixel refinement (the full pass)"),
)


def mean_ms(folder, name):
    values = []
    with open(os.path.join(folder, "frames.csv"), newline="") as f:
        for r in csv.DictReader(f):
            if int(r["frame"]) >= 1 and r["pass"] == name:  # frame 0 renders every page
                values.append(float(r["gpu_ms"]))
    if not values:
        sys.exit(f"vsm_mark_stages: {folder}/frames.csv has no '{name}' rows past frame 0")
    return sum(values) / len(values)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="build/manylights")
    ap.add_argument("--scene", default="night-city", help="the demo's --scene (night-city, indoor, a file)")
    ap.add_argument("--lights", type=int, default=256)
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", default="640x360")
    ap.add_argument("--cluster", action="store_true", help="time vsm_mark_cluster.comp (--vsm-mark cluster)")
    ap.add_argument("--out", help="folder for the runs' outputs (default: a temporary folder)")
    a = ap.parse_args()
    if a.frames < 2 or a.rounds < 1 or a.lights < 1:
        sys.exit("vsm_mark_stages: --frames must be >= 2, --rounds and --lights >= 1")
    out = a.out or tempfile.mkdtemp(prefix="vsm_mark_stages_")
    stages = CLUSTER_STAGES if a.cluster else STAGES
    mark = collections.defaultdict(list)
    evaluate = []
    for r in range(a.rounds):
        for stage, _ in stages:
            folder = os.path.join(out, f"stage{stage}_round{r}")
            env = dict(os.environ, ML_VSM_MARK_STAGE=str(stage))
            cmd = [a.binary, "demo", "--scene", a.scene, "--lights", str(a.lights), "--frames", str(a.frames), "--size", a.size,
                   "--path", "drive", "--out", folder] + (["--vsm-mark", "cluster"] if a.cluster else [])
            run = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if run.returncode != 0:
                sys.exit(f"vsm_mark_stages: stage {stage}: {' '.join(cmd)} failed:\n{run.stderr[-2000:]}")
            mark[stage].append(mean_ms(folder, "vsm_mark"))
            if stage == 0:
                evaluate.append(mean_ms(folder, "evaluate"))
    ev = sum(evaluate) / len(evaluate)
    print(f"{'vsm_mark_cluster' if a.cluster else 'vsm_mark'}: {a.scene}, {a.lights} lights, {a.size}, {a.frames} frames x {a.rounds} rounds; evaluate (stage 0 runs) "
          f"{ev:.2f} ms; outputs in {out}")
    print()
    print("| stage | the pass runs up to | mark ms | added ms | mark / evaluate |")
    print("|---:|---|---:|---:|---:|")
    previous = 0.0
    for stage, what in stages:
        ms = sum(mark[stage]) / len(mark[stage])
        print(f"| {stage} | {what} | {ms:.2f} | {ms - previous:+.2f} | {ms / ev:.2f} |")
        previous = ms
    return 0


if __name__ == "__main__":
    sys.exit(main())
