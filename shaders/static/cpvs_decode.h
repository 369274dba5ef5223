// The CPVS decoder proper (paper section 5): a depth's slice, a voxel's bit, and the normal bias and PCF
// kernel around them, at the finest level or a coarser one. One source text for the
// C++ decoder (shadows/static/cpvs.h) and the GLSL one (shaders/static/cpvs_lookup.glsl), as
// shaders/static/mh_descent.h is for MH: the same integer operations in the same order on both sides.
// The layout is in docs/cpvs-layout.md and shadows/static/cpvs_layout.cpp.
//
// The languages differ only in how the decoder reaches its words: C++ passes the buffer, GLSL reads the
// array named CPVS_DATA. The includer defines, before including this file:
//   CPVS_FN          `inline` in C++, nothing in GLSL
//   CPVS_DATA_PARAM  the leading parameter: `const uint32_t* data,` in C++, nothing in GLSL
//   CPVS_DATA_ARG    the leading argument of a call to a function of this file: `data,` or nothing
//   CPVS_WORD(i)     word i: `data[i]` or `CPVS_DATA[i]`
// and `uint` must name a 32-bit unsigned integer, `int` be 32 bits (`>>` of a negative int shifts in its
// sign: GLSL and C++20), bitCount(uint) count the set bits (a GLSL built-in). This file undefines the four
// at its end; its includers guard it.

// Header word indices and grid entries (CpvsHeader and kCpvsLit / kCpvsShadowed in shadows/static/cpvs.h,
// which asserts them equal).
const uint CPVS_H_RESOLUTION = 2u;
const uint CPVS_H_LOG2_RESOLUTION = 3u;
const uint CPVS_H_GRID_LOG2 = 4u;
const uint CPVS_H_THRESHOLDS = 8u;
const uint CPVS_H_GRID = 9u;
const uint CPVS_LIT = 0u;
const uint CPVS_SHADOWED = 1u;

// Slice of a quantised depth: the number of s in [1, N-1] with T[s] < depth (binary search).
CPVS_FN uint cpvsSliceOfDepth(CPVS_DATA_PARAM uint base, uint depth) {
    uint n = CPVS_WORD(base + CPVS_H_RESOLUTION);
    uint t = base + CPVS_WORD(base + CPVS_H_THRESHOLDS);
    uint lo = 1u; // first s in [1, N) with T[s] >= depth, N if none
    uint count = n - 1u;
    while (count > 0u) {
        uint step = count >> 1u;
        uint mid = lo + step;
        if (CPVS_WORD(t + mid) < depth) {
            lo = mid + 1u;
            count -= step + 1u;
        } else {
            count = step;
        }
    }
    return lo - 1u;
}

// The bit of the child of a node whose children are half_ voxels a side that holds voxel (ux, uy, us).
CPVS_FN uint cpvsChildBit(uint ux, uint uy, uint us, uint half_) {
    return 1u << (((ux & half_) != 0u ? 1u : 0u) | ((uy & half_) != 0u ? 2u : 0u) |
                  ((us & half_) != 0u ? 4u : 0u));
}

// The descent below a grid cell's node: from inner node `ptr` whose children are half_ voxels a side
// (half_ >= 4; a leaf block of 4^3 voxels once half_ < 4) to the voxel (ux, uy, us) of the cell.
CPVS_FN bool cpvsShadowedBelow(CPVS_DATA_PARAM uint base, uint ptr, uint half_, uint ux, uint uy, uint us) {
    while (half_ >= 4u) {
        uint h = CPVS_WORD(base + ptr);
        uint bit = cpvsChildBit(ux, uy, us, half_);
        if ((h & bit) == 0u) return ((h >> 8u) & bit) != 0u;
        ptr = CPVS_WORD(base + ptr + 1u + uint(bitCount(h & (bit - 1u))));
        half_ >>= 1u;
    }
    uint b = (ux & 3u) + 4u * (uy & 3u) + 16u * (us & 3u);
    return ((CPVS_WORD(base + ptr + (b >> 5u)) >> (b & 31u)) & 1u) != 0u;
}

// The grid entry of the cell that holds voxel (ux, uy, us) of the map: CPVS_LIT, CPVS_SHADOWED or the
// word offset of the cell's root node, whose children are half a cell a side. The grid is 2^gridLog2
// cells a side, a cell 2^cellLog2 voxels (header words the caller has read).
CPVS_FN uint cpvsCellEntry(CPVS_DATA_PARAM uint base, uint ux, uint uy, uint us, uint gridLog2,
                           uint cellLog2) {
    uint cell = (((us >> cellLog2) << gridLog2 | (uy >> cellLog2)) << gridLog2) | (ux >> cellLog2);
    return CPVS_WORD(base + CPVS_WORD(base + CPVS_H_GRID) + cell);
}

// Voxel (x, y, s): x, y outside [0, N) are lit (outside the light's frustum); s is clamped to [0, N-1].
CPVS_FN bool cpvsShadowedVoxel(CPVS_DATA_PARAM uint base, int x, int y, int s) {
    int n = int(CPVS_WORD(base + CPVS_H_RESOLUTION));
    if (x < 0 || y < 0 || x >= n || y >= n) return false;
    s = s < 0 ? 0 : (s >= n ? n - 1 : s);
    uint ux = uint(x), uy = uint(y), us = uint(s);
    uint gridLog2 = CPVS_WORD(base + CPVS_H_GRID_LOG2);
    uint cellLog2 = CPVS_WORD(base + CPVS_H_LOG2_RESOLUTION) - gridLog2;
    uint ptr = cpvsCellEntry(CPVS_DATA_ARG base, ux, uy, us, gridLog2, cellLog2);
    if (ptr == CPVS_LIT) return false;
    if (ptr == CPVS_SHADOWED) return true;
    return cpvsShadowedBelow(CPVS_DATA_ARG base, ptr, 1u << (cellLog2 - 1u), ux, uy, us);
}

// Normal bias of one axis (section 5): the lookup point moves along the voxel-space normal (nx, ny, nz),
// any integer scale (e.g. quantised to +-1024; m = its largest absolute component), until its largest
// component is h voxels; n's share rounds half away from 0. |n| <= 1024 and h <= 5 keep 2 |n| h < 2^31.
CPVS_FN int cpvsBiasAxis(int n, int m, int h) {
    int a = n < 0 ? -n : n;
    int o = m == 0 ? 0 : (2 * a * h + m) / (2 * m); // non-negative: rounds half up
    return n < 0 ? -o : o;
}

// Lit taps of a (2 radius + 1)^2 PCF kernel (radius 0..4, up to 9x9) around the biased receiver, on the
// map `step` levels above the finest (step 0: the voxels themselves). A level voxel is 2^step texels a
// side; it answers with the voxel at the centre of its texel block, at the receiver's own slice (the
// slices stay the finest: depth keeps its precision), so a receiver's taps move only when it crosses a
// level texel, not with every finest texel. The bias is radius + 1 level voxels (the kernel's reach, as at
// the finest level), laterally in level texels and in depth 2^step slices each. (x, y, s): the receiver's
// finest texel and slice; taps outside the map are lit. Visibility = float(count) / float((2 radius + 1)^2)
// on the caller's side. Step 0 is exactly the finest-level kernel: X = x + ox, centre offset 0.
CPVS_FN uint cpvsPcfLitLevel(CPVS_DATA_PARAM uint base, int x, int y, int s, int nx, int ny, int nz,
                             int radius, uint step) {
    int ax = nx < 0 ? -nx : nx, ay = ny < 0 ? -ny : ny, az = nz < 0 ? -nz : nz;
    int m = ax > ay ? ax : ay;
    m = m > az ? m : az;
    int h = radius + 1;
    int st = int(step);
    int side = 1 << st;
    int X = (x >> st) + cpvsBiasAxis(nx, m, h);
    int Y = (y >> st) + cpvsBiasAxis(ny, m, h);
    int S = s + cpvsBiasAxis(nz, m, h) * side;
    int c = side >> 1;
    uint taps = uint((2 * radius + 1) * (2 * radius + 1));
    // When every tap lies in the map and in one grid cell, the taps share the descent while they all take
    // the same child: while the extreme taps x0, x1 (and y0, y1) agree in every bit from half_'s up.
    int n = int(CPVS_WORD(base + CPVS_H_RESOLUTION));
    int x0 = (X - radius) * side + c, x1 = (X + radius) * side + c;
    int y0 = (Y - radius) * side + c, y1 = (Y + radius) * side + c;
    uint gridLog2 = CPVS_WORD(base + CPVS_H_GRID_LOG2);
    uint cellLog2 = CPVS_WORD(base + CPVS_H_LOG2_RESOLUTION) - gridLog2;
    uint spread = uint(x0 ^ x1) | uint(y0 ^ y1);
    if (x0 >= 0 && y0 >= 0 && x1 < n && y1 < n && (spread >> cellLog2) == 0u) {
        uint us = uint(S < 0 ? 0 : (S >= n ? n - 1 : S));
        uint ptr = cpvsCellEntry(CPVS_DATA_ARG base, uint(x0), uint(y0), us, gridLog2, cellLog2);
        if (ptr == CPVS_LIT) return taps;
        if (ptr == CPVS_SHADOWED) return 0u;
        uint half_ = 1u << (cellLog2 - 1u);
        while (half_ >= 4u && spread < half_) {
            uint hw = CPVS_WORD(base + ptr);
            uint bit = cpvsChildBit(uint(x0), uint(y0), us, half_);
            if ((hw & bit) == 0u) return ((hw >> 8u) & bit) != 0u ? 0u : taps;
            ptr = CPVS_WORD(base + ptr + 1u + uint(bitCount(hw & (bit - 1u))));
            half_ >>= 1u;
        }
        uint litShared = 0u;
        for (int dy = -radius; dy <= radius; ++dy)
            for (int dx = -radius; dx <= radius; ++dx)
                if (!cpvsShadowedBelow(CPVS_DATA_ARG base, ptr, half_, uint((X + dx) * side + c),
                                       uint((Y + dy) * side + c), us))
                    litShared += 1u;
        return litShared;
    }
    uint lit = 0u;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx)
            if (!cpvsShadowedVoxel(CPVS_DATA_ARG base, (X + dx) * side + c, (Y + dy) * side + c, S))
                lit += 1u;
    return lit;
}

#undef CPVS_FN
#undef CPVS_DATA_PARAM
#undef CPVS_DATA_ARG
#undef CPVS_WORD
