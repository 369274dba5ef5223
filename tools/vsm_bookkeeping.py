#!/usr/bin/env python3
"""The VSM bookkeeping table of docs/virtual-shadow-maps.md: for each demo output folder (one per light
count), the mean over frames 1.. of the bookkeeping steps (vsm_mark, vsm_sort, vsm_alloc, vsm_hpb,
vsm_group_cull, vsm_cull, vsm_expand), of vsm_draw and of evaluate (frames.csv, fenced timing), and the
last frame's page counts (stats.json); then each step's mean on its own. Outputs from before the steps
were split (vsm_alloc then held the sort, vsm_cull / vsm_expand the group culling) sum the same way.
Usage:
  for n in 256 1024 4096; do build/manylights demo --lights $n --frames 4 --size 640x360 --path drive --out out/bk$n; done
  python3 tools/vsm_bookkeeping.py out/bk256 out/bk1024 out/bk4096
Prints two Markdown tables."""
import collections
import csv
import json
import os
import sys

# The bookkeeping steps, in frame order (manylights/pass_times.h: Pass::VsmMark..VsmExpand).
BOOKKEEPING = ("vsm_mark", "vsm_sort", "vsm_alloc", "vsm_hpb", "vsm_group_cull", "vsm_cull", "vsm_expand")
STEPS = BOOKKEEPING + ("vsm_draw",)


def row(folder):
    times = collections.defaultdict(list)
    with open(os.path.join(folder, "frames.csv"), newline="") as f:
        for r in csv.DictReader(f):
            if int(r["frame"]) >= 1:  # frame 0 renders every page: reported apart
                times[r["pass"]].append(float(r["gpu_ms"]))
    mean = {k: sum(v) / len(v) for k, v in times.items()}
    with open(os.path.join(folder, "stats.json")) as f:
        stats = json.load(f)
    vsm = stats.get("vsm", {})
    book = sum(mean.get(k, 0.0) for k in BOOKKEEPING)
    evaluate = mean.get("evaluate", 0.0)
    return (stats.get("lights_total", "?"), vsm.get("pages_marked", "?"), vsm.get("lights_with_pages", "?"),
            mean.get("vsm_mark", 0.0), book, mean.get("vsm_draw", 0.0), evaluate,
            book / evaluate if evaluate else float("nan")), [mean.get(k, 0.0) for k in STEPS]


def main(folders):
    if not folders or folders[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if folders else 1
    print("| lights | pages marked | lights with pages | mark ms | bookkeeping ms | draw ms | evaluate ms | bookkeeping / evaluate |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    steps = []
    for folder in folders:
        (l, marked, with_pages, mark, book, draw, ev, ratio), per_step = row(folder)
        print(f"| {l} | {marked} | {with_pages} | {mark:.1f} | {book:.1f} | {draw:.1f} | {ev:.1f} | {ratio:.2f} |")
        steps.append((l, per_step))
    # Each step's scope (ms; a raster path runs vsm_cull or vsm_expand, the other reads 0).
    print()
    print("| lights | " + " | ".join(k.replace("vsm_", "") + " ms" for k in STEPS) + " |")
    print("|---:|" + "---:|" * len(STEPS))
    for l, per_step in steps:
        print(f"| {l} | " + " | ".join(f"{v:.2f}" for v in per_step) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
