#!/usr/bin/env python3
"""Layer check: lists the #include edges between top-level folders and fails on any edge that runs
back up the declared layers (a cycle needs one), naming file and line; also fails on a source file
over 800 lines. Run by ctest (LayerCheck); `--edges` prints the edge table; LayerCheckCatchesCycle runs it on
tests/packaging/layer_fixture, whose shadows/ header includes engine/.

Layers, lowest first (a folder may include its own folder and any folder of a lower layer):
  0 include           the public API, include/manylights/ (included as "manylights/..."): includes
                      nothing of the module, so it is installed alone
  1 io, shaders       safe file IO; shaders/shared: GPU definitions only
  2 gpu               Vulkan base: device, resources, programs + dispatch, profiler; knows no feature
  3 culling, shadows  features on the base and the shared definitions
  4 lights            the evaluation pass: reads cluster lists (culling) and shadow decoders (shadows)
  5 engine            the module facade: the public API's implementation, the frame as a list of passes
  6 scenes            scene data, glTF and procedural scenes (consumers of the module API)
  7 bake, host        the bake driver (scene -> bake file), the shared host code of the commands
  8 apps, examples    the command line, the example host
  9 tests             tests and benchmarks
"""
import os, re, sys
from collections import defaultdict

LAYERS = {"include": 0, "io": 1, "shaders": 1, "gpu": 2, "culling": 3, "shadows": 3, "lights": 4, "engine": 5,
          "scenes": 6, "bake": 7, "host": 7, "apps": 8, "examples": 8, "tests": 9}
# The folder an include's first component names, where it is not the folder itself: the public headers
# are included as "manylights/..." (include/ is on the include path).
ALIASES = {"manylights": "include"}
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
                    target = ALIASES.get(target, target)
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
