#!/usr/bin/env python3
"""The VSM bookkeeping table of docs/virtual-shadow-maps.md: for each demo output folder (one per light
count), the mean over frames 1.. of the bookkeeping passes (vsm_mark, vsm_alloc, vsm_hpb, vsm_cull,
vsm_expand), of vsm_draw and of evaluate (frames.csv, fenced timing), and the last frame's page counts
(stats.json). Usage:
  for n in 256 1024 4096; do build/manylights demo --lights $n --frames 4 --size 640x360 --path drive --out out/bk$n; done
  python3 tools/vsm_bookkeeping.py out/bk256 out/bk1024 out/bk4096
Prints a Markdown table."""
import collections
import csv
import json
import os
import sys

BOOKKEEPING = ("vsm_mark", "vsm_alloc", "vsm_hpb", "vsm_cull", "vsm_expand")


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
            book / evaluate if evaluate else float("nan"))


def main(folders):
    if not folders or folders[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if folders else 1
    print("| lights | pages marked | lights with pages | mark ms | bookkeeping ms | draw ms | evaluate ms | bookkeeping / evaluate |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for folder in folders:
        l, marked, with_pages, mark, book, draw, ev, ratio = row(folder)
        print(f"| {l} | {marked} | {with_pages} | {mark:.1f} | {book:.1f} | {draw:.1f} | {ev:.1f} | {ratio:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
