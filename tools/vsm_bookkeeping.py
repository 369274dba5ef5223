#!/usr/bin/env python3
"""The VSM bookkeeping table of docs/virtual-shadow-maps.md: for each demo output folder (one per light
count), the mean over frames 1.. of the bookkeeping steps (vsm_mark, vsm_sort, vsm_alloc, vsm_hpb,
vsm_group_cull, vsm_cull, vsm_expand), of vsm_draw and of evaluate (frames.csv, fenced timing), and the
last frame's page counts (stats.json); then each step's mean on its own. Outputs from before the steps
were split (vsm_alloc then held the sort, vsm_cull / vsm_expand the group culling) sum the same way.
Usage:
  for n in 256 1024 4096; do build/manylights demo --lights $n --frames 4 --size 640x360 --path drive --out out/bk$n; done
  python3 tools/vsm_bookkeeping.py out/bk256 out/bk1024 out/bk4096
Prints two Markdown tables.

The allocation, one workgroup against the multi-dispatch passes (vsm_allocate_short_list.comp):
  python3 tools/vsm_bookkeeping.py --compare-alloc [--binary build/manylights] [--scene night-city]
      [--lights 256] [--frames 8] [--rounds 3] [--size 640x360] [--out DIR]
runs the demo (drive path, fenced timing) alternately with ML_VSM_ALLOC_SHORT_LIST=0 (the multi-dispatch
passes alone) and without it (lists up to ML_VSM_ONE_GROUP_LIST in one workgroup), the order swapped
each round, and prints per round the median over frames 1.. of vsm_sort + vsm_alloc (the allocation's
two scopes; medians, not means: on a shared machine one stalled frame of a one-workgroup dispatch, which
runs on one core, moves a mean by several times) for each, their ratio, the last frame's pages marked and
allocated (equal in both: the allocation is the same), then the median over every round's frames.

The allocation of two builds at several pool sizes (the pool walks: the invalidation, vsm_avail):
  python3 tools/vsm_bookkeeping.py --compare-pool OLD NEW [--pools 4096,16384] [--short-list 0]
      [--scene night-city] [--lights 256] [--frames 8] [--rounds 3] [--size 640x360] [--out DIR]
runs the demo of binary OLD and NEW alternately (the order swapped each round) at each --vsm-pool size,
with ML_VSM_ALLOC_SHORT_LIST set to --short-list when given (0: the multi-dispatch passes, timed in
vsm_alloc), and prints per pool the median over every round's frames 1.. of vsm_sort and of vsm_alloc
for each binary (apart: the sort's scope stalls for tens of ms on a loaded machine and would hide the
rest; with --short-list 0 vsm_alloc holds every pool-walking pass, without it a short list's whole
allocation is in vsm_sort), the ratio of the medians of their per-frame sum, and the last frame's
pages allocated (equal in both, or it stops).

The bookkeeping of two builds against the evaluation pass:
  python3 tools/vsm_bookkeeping.py --compare-builds OLD NEW [--scene night-city] [--lights 256]
      [--mark pixel] [--frames 8] [--rounds 3] [--size 640x360] [--out DIR]
runs the demo of binary OLD and NEW alternately (the order swapped each round; drive path, fenced
timing, --vsm-mark pixel or cluster) and prints per build the median over every round's frames 1.. of
the bookkeeping (the sum of its steps per frame), of the allocation (vsm_sort + vsm_alloc), of the
evaluation pass and of the per-frame ratio bookkeeping / evaluate, then NEW / OLD of each median and
the last frame's pages marked and allocated (equal in both, or it stops); then each step's median per
build. Medians: on a shared machine one stalled frame moves a mean by several times."""
import collections
import csv
import json
import os
import sys

# The bookkeeping steps, in frame order (the passes of group kVsmBookkeeping, manylights/pass_times.h).
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


def frame_sums(folder, names):
    """Per frame from 1 on, the sum of the named passes' fenced times."""
    sums = collections.defaultdict(float)
    with open(os.path.join(folder, "frames.csv"), newline="") as f:
        for r in csv.DictReader(f):
            if int(r["frame"]) >= 1 and r["pass"] in names:
                sums[int(r["frame"])] += float(r["gpu_ms"])
    return [sums[k] for k in sorted(sums)]


def median(values):
    v = sorted(values)
    return (v[len(v) // 2] + v[(len(v) - 1) // 2]) / 2 if v else float("nan")


def compare_alloc(argv):
    import argparse
    import subprocess
    import tempfile
    ap = argparse.ArgumentParser(prog="vsm_bookkeeping.py --compare-alloc")
    ap.add_argument("--binary", default="build/manylights")
    ap.add_argument("--scene", default="night-city")
    ap.add_argument("--lights", type=int, default=256)
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", default="640x360")
    ap.add_argument("--out")
    a = ap.parse_args(argv)
    if a.frames < 2 or a.rounds < 1:
        sys.exit("vsm_bookkeeping: --frames must be >= 2, --rounds >= 1")
    out = a.out or tempfile.mkdtemp(prefix="vsm_alloc_")
    names = ("vsm_sort", "vsm_alloc")
    paths = (("multi", "0"), ("one", None))
    print(f"{a.scene}, {a.lights} lights, {a.size}, drive path, frames 1..{a.frames - 1} of {a.frames}, fenced; "
          f"outputs in {out}")
    print()
    print("| round | multi-dispatch sort + alloc ms (median) | one workgroup sort + alloc ms (median) | one / multi | "
          "pages marked | pages allocated |")
    print("|---:|---:|---:|---:|---:|---:|")
    sums = {"multi": [], "one": []}
    for r in range(a.rounds):
        got, pages = {}, {}
        for name, limit in (paths if r % 2 == 0 else paths[::-1]):
            folder = os.path.join(out, f"{name}_round{r}")
            env = dict(os.environ)
            env.pop("ML_VSM_ALLOC_SHORT_LIST", None)
            if limit is not None:
                env["ML_VSM_ALLOC_SHORT_LIST"] = limit
            cmd = [a.binary, "demo", "--scene", a.scene, "--lights", str(a.lights), "--frames", str(a.frames),
                   "--size", a.size, "--path", "drive", "--out", folder]
            run = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if run.returncode != 0:
                sys.exit(f"vsm_bookkeeping: {name}: {' '.join(cmd)} failed:\n{run.stderr[-2000:]}")
            frames = frame_sums(folder, names)
            got[name] = median(frames)
            with open(os.path.join(folder, "stats.json")) as f:
                vsm = json.load(f).get("vsm", {})
            pages[name] = (vsm.get("pages_marked"), vsm.get("pages_allocated"))
            sums[name] += frames
        if pages["multi"] != pages["one"]:
            sys.exit(f"vsm_bookkeeping: round {r}: the two paths' page counts differ: {pages}")
        print(f"| {r + 1} | {got['multi']:.3f} | {got['one']:.3f} | {got['one'] / got['multi']:.2f} | "
              f"{pages['one'][0]} | {pages['one'][1]} |")
    multi, one = (median(sums[k]) for k in ("multi", "one"))
    print(f"| all frames (median) | {multi:.3f} | {one:.3f} | {one / multi:.2f} | | |")
    return 0


def compare_parser(mode):
    """The arguments the two-build comparisons share: two binaries, the scene, the frames and rounds."""
    import argparse
    ap = argparse.ArgumentParser(prog=f"vsm_bookkeeping.py {mode}")
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--scene", default="night-city")
    ap.add_argument("--lights", type=int, default=256)
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", default="640x360")
    ap.add_argument("--out")
    return ap


def parse_compare(ap, argv):
    a = ap.parse_args(argv)
    if a.frames < 2 or a.rounds < 1:
        sys.exit("vsm_bookkeeping: --frames must be >= 2, --rounds >= 1")
    return a


def compare_pool(argv):
    import subprocess
    import tempfile
    ap = compare_parser("--compare-pool")
    ap.add_argument("--pools", default="4096,16384")
    ap.add_argument("--short-list")
    a = parse_compare(ap, argv)
    out = a.out or tempfile.mkdtemp(prefix="vsm_pool_")
    env = dict(os.environ)
    env.pop("ML_VSM_ALLOC_SHORT_LIST", None)
    if a.short_list is not None:
        env["ML_VSM_ALLOC_SHORT_LIST"] = a.short_list
    print(f"{a.scene}, {a.lights} lights, {a.size}, drive path, frames 1..{a.frames - 1} of {a.frames}, "
          f"{a.rounds} rounds, ML_VSM_ALLOC_SHORT_LIST={a.short_list if a.short_list is not None else '(unset)'}, "
          f"fenced; outputs in {out}")
    print()
    print("| pool pages | old sort ms | new sort ms | old alloc ms | new alloc ms | alloc new / old | "
          "sort + alloc new / old | pages allocated |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for pool in a.pools.split(","):
        scopes = ("vsm_sort", "vsm_alloc", "both")
        sums, pages = {(b, s): [] for b in ("old", "new") for s in scopes}, {}
        for r in range(a.rounds):
            order = (("old", a.old), ("new", a.new))
            for name, binary in (order if r % 2 == 0 else order[::-1]):
                folder = os.path.join(out, f"pool{pool}_{name}_round{r}")
                cmd = [binary, "demo", "--scene", a.scene, "--lights", str(a.lights), "--frames", str(a.frames),
                       "--size", a.size, "--path", "drive", "--vsm-pool", pool, "--out", folder]
                run = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                if run.returncode != 0:
                    sys.exit(f"vsm_bookkeeping: {' '.join(cmd)} failed:\n{run.stderr[-2000:]}")
                for scope in ("vsm_sort", "vsm_alloc"):
                    sums[(name, scope)] += frame_sums(folder, (scope,))
                sums[(name, "both")] += frame_sums(folder, ("vsm_sort", "vsm_alloc"))
                with open(os.path.join(folder, "stats.json")) as f:
                    vsm = json.load(f).get("vsm", {})
                pages.setdefault(name, (vsm.get("pages_marked"), vsm.get("pages_allocated")))
        if pages["old"] != pages["new"]:
            sys.exit(f"vsm_bookkeeping: pool {pool}: the two builds' page counts differ: {pages}")
        m = {k: median(v) for k, v in sums.items()}
        print(f"| {pool} | {m[('old', 'vsm_sort')]:.3f} | {m[('new', 'vsm_sort')]:.3f} | "
              f"{m[('old', 'vsm_alloc')]:.3f} | {m[('new', 'vsm_alloc')]:.3f} | "
              f"{m[('new', 'vsm_alloc')] / m[('old', 'vsm_alloc')]:.2f} | "
              f"{m[('new', 'both')] / m[('old', 'both')]:.2f} | {pages['new'][1]} |")
    return 0


def per_frame(folder, names):
    """Per frame from 1 on: the sum of the named passes' times, and the evaluation pass's."""
    book = frame_sums(folder, names)
    ev = frame_sums(folder, ("evaluate",))
    return book, ev


def compare_builds(argv):
    import subprocess
    import tempfile
    ap = compare_parser("--compare-builds")
    ap.add_argument("--mark", default="pixel", choices=("pixel", "cluster"))
    a = parse_compare(ap, argv)
    out = a.out or tempfile.mkdtemp(prefix="vsm_builds_")
    env = dict(os.environ)
    env.pop("ML_VSM_ALLOC_SHORT_LIST", None)
    keys = ("book", "alloc", "eval", "ratio") + BOOKKEEPING
    got = {(b, k): [] for b in ("old", "new") for k in keys}
    pages = {}
    for r in range(a.rounds):
        order = (("old", a.old), ("new", a.new))
        for name, binary in (order if r % 2 == 0 else order[::-1]):
            folder = os.path.join(out, f"{name}_round{r}")
            cmd = [binary, "demo", "--scene", a.scene, "--lights", str(a.lights), "--frames", str(a.frames),
                   "--size", a.size, "--path", "drive", "--vsm-mark", a.mark, "--out", folder]
            run = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if run.returncode != 0:
                sys.exit(f"vsm_bookkeeping: {' '.join(cmd)} failed:\n{run.stderr[-2000:]}")
            book, ev = per_frame(folder, BOOKKEEPING)
            got[(name, "book")] += book
            got[(name, "alloc")] += frame_sums(folder, ("vsm_sort", "vsm_alloc"))
            got[(name, "eval")] += ev
            got[(name, "ratio")] += [b / e for b, e in zip(book, ev) if e > 0]
            for step in BOOKKEEPING:
                got[(name, step)] += frame_sums(folder, (step,))
            with open(os.path.join(folder, "stats.json")) as f:
                vsm = json.load(f).get("vsm", {})
            pages.setdefault(name, (vsm.get("pages_marked"), vsm.get("pages_allocated")))
    if pages["old"] != pages["new"]:
        sys.exit(f"vsm_bookkeeping: the two builds' page counts differ: {pages}")
    m = {k: median(v) for k, v in got.items()}
    print(f"{a.scene}, {a.lights} lights, --vsm-mark {a.mark}, {a.size}, drive path, frames 1..{a.frames - 1} "
          f"of {a.frames}, {a.rounds} rounds alternated, fenced, medians; outputs in {out}")
    print()
    print("| build | bookkeeping ms | sort + alloc ms | evaluate ms | bookkeeping / evaluate | pages marked | "
          "pages allocated |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for b in ("old", "new"):
        print(f"| {b} | {m[(b, 'book')]:.3f} | {m[(b, 'alloc')]:.3f} | {m[(b, 'eval')]:.2f} | "
              f"{m[(b, 'ratio')]:.3f} | {pages[b][0]} | {pages[b][1]} |")
    print(f"| new / old | {m[('new', 'book')] / m[('old', 'book')]:.2f} | "
          f"{m[('new', 'alloc')] / m[('old', 'alloc')]:.2f} | {m[('new', 'eval')] / m[('old', 'eval')]:.2f} | "
          f"{m[('new', 'ratio')] / m[('old', 'ratio')]:.2f} | | |")
    ran = [k for k in BOOKKEEPING if got[("old", k)] or got[("new", k)]]
    print()
    print("| build | " + " | ".join(k.replace("vsm_", "") + " ms" for k in ran) + " |")
    print("|---|" + "---:|" * len(ran))
    for b in ("old", "new"):
        print(f"| {b} | " + " | ".join(f"{m[(b, k)]:.3f}" for k in ran) + " |")
    return 0


def main(folders):
    if folders and folders[0] == "--compare-builds":
        return compare_builds(folders[1:])
    if folders and folders[0] == "--compare-alloc":
        return compare_alloc(folders[1:])
    if folders and folders[0] == "--compare-pool":
        return compare_pool(folders[1:])
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
