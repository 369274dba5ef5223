#!/usr/bin/env python3
"""The static scale table of docs/static-shadows.md: one light baked by each method at each resolution,
each bake a process of its own (so its measured peak memory is its own), then optionally verified.

Usage:
  python3 tools/static_scale.py [--exe build/manylights] [--methods mh,mmh,dagmh] [--res 4096,8192,16384]
                                [--light 239] [--scene S] [--tile T] [--verify] [--out DIR] [--csv FILE]
Defaults: the night city's moon (light 239 of the default 256-light scene; --scene night-city-closed is the
city with its open sheets closed), mh,mmh,dagmh at
4096,8192,16384. Resolutions past 16384 (up to 262144) bake in tiles (bake --tile); --tile forces tiles at
every resolution. Prints CSV: method, resolution, bytes, bytes against the 32-bit map (4 B a texel),
render+tree seconds, encode seconds, tree nodes, tiles, measured peak MiB, and with --verify the texels
checked, mismatches, verify seconds and verify peak MiB. A bake that fails prints its one-line error in
the last column ("error") and the table goes on. Exit status: 0, or 1 when a bake or verify failed or
found a mismatch."""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

LIGHT_LINE = re.compile(r"light (\d+): (\d+)\^2, render ([0-9.]+) s, encode ([0-9.]+) s, [0-9.]+% covered, "
                        r"(\d+) bytes(?: \((\d+) tiles, \d+ empty; render includes building the (\d+)-node tree\))?")
PEAK = re.compile(r"measured peak memory (\d+) MiB")
VERIFY = re.compile(r'\{"checked": (\d+), "mismatches": (\d+)\}')


def last_error(text):
    lines = [l for l in text.splitlines() if "error" in l.lower() or "refus" in l.lower()]
    return (lines[-1] if lines else text.strip().splitlines()[-1] if text.strip() else "no output").replace(",", ";")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--exe", default="build/manylights")
    ap.add_argument("--methods", default="mh,mmh,dagmh")
    ap.add_argument("--res", default="4096,8192,16384")
    ap.add_argument("--light", default="239")
    ap.add_argument("--scene", default="night-city")
    ap.add_argument("--tile", default="")
    ap.add_argument("--verify", action="store_true")
    ap.add_argument("--out", default="")
    ap.add_argument("--csv", default="")
    a = ap.parse_args()
    if not os.path.isfile(a.exe):
        sys.exit(f"static_scale: {a.exe}: no such executable (build first, or pass --exe)")
    try:
        resolutions = [int(r) for r in a.res.split(",")]
    except ValueError:
        sys.exit(f"static_scale: --res: '{a.res}' is not a comma-separated list of integers")
    methods = a.methods.split(",")
    out = a.out or tempfile.mkdtemp(prefix="static_scale_")
    os.makedirs(out, exist_ok=True)
    header = ("method,resolution,bytes,fraction_of_32bit_map,render_tree_s,encode_s,tree_nodes,tiles,peak_mib,"
              "verify_texels,verify_mismatches,verify_s,verify_peak_mib,error")
    rows = [header]
    print(header, flush=True)
    status = 0
    for m in methods:
        for r in resolutions:
            path = os.path.join(out, f"{m}_{r}.mlbk")
            cmd = [a.exe, "bake", "--method", m, "--res", str(r), "--lights", a.light, "--quiet", "--out", path]
            if a.scene != "night-city":
                cmd += ["--scene", a.scene]
            if a.tile:
                cmd += ["--tile", a.tile]
            p = subprocess.run(cmd, capture_output=True, text=True)
            text = p.stdout + p.stderr
            lm, pk = LIGHT_LINE.search(text), PEAK.search(text)
            if p.returncode != 0 or not lm:
                status = 1
                row = f"{m},{r},,,,,,,,,,,,{last_error(text)}"
            else:
                size = int(lm.group(5))
                cells = [m, str(r), str(size), f"{size / (4.0 * r * r):.3g}", lm.group(3), lm.group(4),
                         lm.group(7) or "", lm.group(6) or "0", pk.group(1) if pk else ""]
                if a.verify:
                    t0 = time.time()
                    vcmd = [a.exe, "verify", path, "--quiet"] + (["--tile", a.tile] if a.tile else [])
                    v = subprocess.run(vcmd, capture_output=True, text=True)
                    vt = v.stdout + v.stderr
                    vm, vp = VERIFY.search(vt), PEAK.search(vt)
                    if not vm or v.returncode != 0:
                        status = 1
                    cells += [vm.group(1) if vm else "", vm.group(2) if vm else "", f"{time.time() - t0:.1f}",
                              vp.group(1) if vp else "", "" if vm and v.returncode == 0 else last_error(vt)]
                else:
                    cells += ["", "", "", "", ""]
                row = ",".join(cells)
            rows.append(row)
            print(row, flush=True)
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("\n".join(rows) + "\n")
    return status


if __name__ == "__main__":
    sys.exit(main())
