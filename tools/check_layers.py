#!/usr/bin/env python3
"""Layer check: lists the #include edges between top-level folders and fails on any edge that runs
back up the declared layers (a cycle needs one), naming file and line; also fails on a source file
over 800 lines. Run by ctest (LayerCheck); `--edges` prints the edge table; LayerCheckCatchesCycle runs it on
tests/packaging/layer_fixture, whose shadows/ header includes engine/.

Layers, lowest first (a folder may include its own folder and any folder of a lower layer):
  0 io, shaders       safe file IO and Result; shaders/shared: GPU definitions only
  1 gpu               Vulkan base: device, resources, programs + dispatch, profiler; knows no feature
  2 culling, shadows  features on the base and the shared definitions
  3 lights            the evaluation pass: reads cluster lists (culling) and shadow decoders (shadows)
  4 engine            the module facade: manylights.h, the frame as a list of passes
  5 scenes            scene data, glTF and procedural scenes (consumers of the module API)
  6 bake, host        the bake driver (scene -> bake file), the shared host code of the commands
  7 apps, examples    the command line, the example host
  8 tests             tests and benchmarks
"""
import os, re, sys
from collections import defaultdict

LAYERS = {"io": 0, "shaders": 0, "gpu": 1, "culling": 2, "shadows": 2, "lights": 3, "engine": 4,
          "scenes": 5, "bake": 6, "host": 6, "apps": 7, "examples": 7, "tests": 8}
SOURCE = re.compile(r"\.(h|hpp|cpp|c|glsl|comp|vert|frag|mesh|task)$")
INCLUDE = re.compile(r'\s*#\s*include\s*"([^"]+)"')
MAX_LINES = 800

def main():
    args = sys.argv[1:]
    if any(a in ("-h", "--help") for a in args):
        print(__doc__ + "\nusage: check_layers.py [--edges] [--root DIR]   (DIR: the tree to check, default the repo)")
        return 0
    root = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
    if "--root" in args:
        i = args.index("--root")
        if i + 1 >= len(args): print("check_layers: --root needs a folder", file=sys.stderr); return 2
        root = os.path.abspath(args[i + 1]); del args[i:i + 2]
    show_edges = "--edges" in args
    unknown = [a for a in args if a != "--edges"]
    if unknown: print(f"check_layers: unknown argument '{unknown[0]}' (see --help)", file=sys.stderr); return 2
    edges = defaultdict(list)
    errors, files = [], 0
    for top in sorted(LAYERS):
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames.sort()
            for name in sorted(filenames):
                if not SOURCE.search(name): continue
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, root)
                files += 1
                with open(path, errors="replace") as f: lines = f.readlines()
                if len(lines) > MAX_LINES:
                    errors.append(f"{rel}: {len(lines)} lines (at most {MAX_LINES})")
                for i, line in enumerate(lines, 1):
                    m = INCLUDE.match(line)
                    if not m: continue
                    target = m.group(1).split("/")[0]
                    if target == top or target not in LAYERS: continue
                    edges[(top, target)].append(f"{rel}:{i}")
                    if LAYERS[target] >= LAYERS[top]:
                        errors.append(f"{rel}:{i}: {top} (layer {LAYERS[top]}) includes {m.group(1)} "
                                      f"({target}, layer {LAYERS[target]}): runs back up or across a layer")
    if show_edges:
        for (a, b), where in sorted(edges.items()):
            print(f"{a} -> {b}: {len(where)} includes, first {where[0]}")
    for e in errors: print("check_layers: " + e, file=sys.stderr)
    print(f"check_layers: {files} files, {len(edges)} folder edges, {len(errors)} errors")
    return 1 if errors else 0

if __name__ == "__main__":
    sys.exit(main())
