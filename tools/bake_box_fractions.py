#!/usr/bin/env python3
"""bake_box_fractions.py FILE X0 Y0 Z0 X1 Y1 Z1: for each directional record of a bake file, of bake
format version 1, 2 (square maps, from before fitted directional maps) or 3 (fitted), the share of the map's texels
whose centres lie in the box's light-space rectangle and of its N depth slices (CPVS: from the stored
thresholds; depth methods: N equal parts of [near, far]) inside the box's slab along the light. The box
is the one the file was baked for (--bounds). For version 3 files `manylights inspect` prints the same
shares; this script exists to measure files written before that (docs/accuracy.md section 5)."""
import math, struct, sys
b = open(sys.argv[1], 'rb').read(); w = struct.unpack('<%dI' % (len(b) // 4), b)
f = lambda u: struct.unpack('<f', struct.pack('<I', u))[0]
lo = [float(v) for v in sys.argv[2:5]]; hi = [float(v) for v in sys.argv[5:8]]
H, n, method = w[3], w[6], w[4]
for r in range(n):
    rec = w[H + 32 * r: H + 32 * r + 32]
    if rec[29] == 0: continue
    N = rec[2]; oh = f(rec[29]); ohy = f(rec[30]) if w[1] == 3 else 0.0
    m = [f(x) for x in rec[3:19]]  # column-major
    near, far = f(rec[20]), f(rec[21])
    vs = []
    for i in range(8):
        c = [hi[k] if (i >> k) & 1 else lo[k] for k in range(3)]
        vs.append([sum(m[col * 4 + row] * (c[col] if col < 3 else 1.0) for col in range(4)) for row in range(3)])
    xs = [v[0] for v in vs]; ys = [v[1] for v in vs]; zs = [-v[2] for v in vs]
    rows = N if ohy == 0 else min(N, max(1, math.ceil(N * ohy / oh)))
    cen = lambda i: ((i + 0.5) / N * 2 - 1) * oh
    inx = sum(1 for i in range(N) if min(xs) <= cen(i) <= max(xs))
    iny = sum(1 for i in range(rows) if min(ys) <= cen(i) <= max(ys))
    tex = inx * iny / (N * rows)
    q = lambda z: 0 if z <= 0 else (0xFFFFFFFE if z >= far else int(z / far * 4294967294.0))
    if method == 5:  # CPVS: stored thresholds
        off = rec[22] | rec[23] << 32; d = w[off:]; T = d[d[8]: d[8] + N + 1]
        qa, qb = q(min(zs)), q(max(zs))
        sl = sum(1 for s in range(N) if T[s] >= qa and T[s + 1] <= qb) / N
    else:
        sl = sum(1 for s in range(N) if near + (far - near) * s / N >= min(zs) and near + (far - near) * (s + 1) / N <= max(zs)) / N
    print('%s: light %d %dx%d texels, %.1f%% texels in the box rectangle, %.1f%% depth slices in the slab' % (sys.argv[1].split('/')[-1], rec[0], N, rows, 100 * tex, 100 * sl))
