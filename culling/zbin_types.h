// Z-binning (culling/zbin.h) structs, push block and bin function, defined once for C++ (zbin.cpp,
// the CPU reference) and GLSL (zbin_mask.comp, zbin_bins.comp, zbin_stats.comp); layout rules as in
// shaders/shared/gpu_types.h.
#ifndef ML_ZBIN_TYPES_H
#define ML_ZBIN_TYPES_H

#include "shaders/shared/gpu_types.h"
#ifdef __cplusplus
#include <cmath>
#include <cstddef>
#endif

#ifdef __cplusplus
namespace ml::gpu {
#define ML_ZB_FN inline
#define ML_ZB_PRECISE
#else
#define ML_ZB_FN
#define ML_ZB_PRECISE precise
#endif

// One light of the depth-sorted list (sorted index i = its bit in the tile masks), written by the host
// each frame: its footprint (lightFootprint) rectangle of tiles, the 64-bit mask of the cluster slices
// its depth range spans (the mask pass's optional test against the tile's occupied slices), its bin
// range (first | last << 16) and its visible-light index. 32 bytes.
ML_STRUCT(ZBinLight) {
    uvec4 tiles;     // x0, y0, x1, y1 (inclusive), never empty (off-screen lights are not sorted)
    uvec2 sliceMask; // slices 0-31, 32-63 of [sliceOf(depth near), sliceOf(depth far)]
    uint bins;       // first bin | last bin << 16
    uint light;      // visible-light index
};

// sorted: lights in the sorted list (the mask's bits); words: ceil(sorted / 32) per tile (<=
// ML_ZBIN_WORDS); wide: wide (directional) lights, kept out of the bins and masks and evaluated at
// every pixel; depthTest: 1 when the mask pass also needs a footprint slice in the tile's occupied
// slices (cluster_bounds' tile masks); binNear, binScale: bin b covers view depths [binNear + b /
// binScale, binNear + (b + 1) / binScale) (zbinOf). 32 bytes.
ML_STRUCT(ZBinPush) {
    uint sorted;
    uint words;
    uint wide;
    uint depthTest;
    float binNear;
    float binScale;
    uint bins; // ML_ZBIN_BINS
    uint pad;
};

// The bin of a linear view depth z: floor((z - near) * scale), clamped to [0, bins - 1]. Monotonic in
// z (subtraction and multiplication round monotonically), so a pixel whose depth lies in a light's
// [near, far] lands in a bin of [zbinOf(near), zbinOf(far)]: the bins are conservative. The same
// operations on both sides (precise), so CPU and GPU agree bit for bit.
ML_ZB_FN uint zbinOf(float z, float binNear, float binScale, uint bins) {
    ML_ZB_PRECISE float t = (z - binNear) * binScale;
    if (!(t > 0.0f)) return 0u;
    if (t >= float(bins)) return bins - 1u;
    return uint(t); // t > 0: truncation is floor
}

// Empty bin: min 0xFFFF, max 0 (lo > hi, so the range holds nothing).
#define ML_ZBIN_EMPTY 0x0000FFFFu

#ifdef __cplusplus
static_assert(sizeof(ZBinLight) == 32 && offsetof(ZBinLight, bins) == 24);
static_assert(sizeof(ZBinPush) == 32);
} // namespace ml::gpu
#endif
#undef ML_ZB_FN
#undef ML_ZB_PRECISE

#endif
