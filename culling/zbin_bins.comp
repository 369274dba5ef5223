#version 460
#extension GL_GOOGLE_include_directive : require
// Z-binning, depth bins (culling/zbin.h): one thread per bin b writes (min | max << 16), the first and
// last sorted index of the lights whose bin range (first, last: the host's zbinOf of their footprint's
// near and far depth) holds b, or ML_ZBIN_EMPTY. Lights are sorted by the middle of their depth range,
// so the lights between min and max that do not overlap b are the Z-bin's false positives (they stay
// in a pixel's candidate set when their tile bit is set). Work: bins x sorted lights (4 M tests at 4096
// lights), no atomics, every word written (no clear).
#include "shaders/shared/glsl_common.glsl"
#include "culling/zbin_types.h"
#include "culling/zbin_bindings.h"

layout(local_size_x = ML_ZBIN_GROUP) in;
layout(push_constant) uniform Push { ZBinPush push; };

layout(binding = ML_ZBIN_BINS_SORTED, std430) readonly buffer Sorted { ZBinLight sorted[]; };
layout(binding = ML_ZBIN_BINS_OUT, std430) writeonly buffer Bins { uint bins[]; };

void main() {
    uint b = gl_GlobalInvocationID.x;
    if (b >= push.bins) return;
    uint lo = 0xFFFFu, hi = 0u;
    for (uint i = 0u; i < push.sorted; ++i) {
        uint r = sorted[i].bins;
        if ((r & 0xFFFFu) <= b && b <= (r >> 16u)) {
            lo = min(lo, i);
            hi = i;
        }
    }
    bins[b] = lo | (hi << 16u);
}
