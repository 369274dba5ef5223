#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_alloc (allocation 2/3), one workgroup:
//   1. exclusive prefix sum of the per-block request counts (vsm_scan) -> each block's first rank;
//   2. the ordered list of physical pages a request may take: free pages (no owner) by index, then
//      cached pages whose entry is not marked this frame, least recently used first (age buckets of
//      powers of two: 1, 2-3, 4-7, ... >= 128 frames), by index within a bucket.
// Rank r of vsm_assign takes avail[r]; ranks past the list are fallbacks (counted).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = 2, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = 3, std430) readonly buffer Owner { uint vsmOwner[]; };
layout(binding = 4, std430) readonly buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = 5, std430) buffer BlockCounts { uint vsmBlockCounts[]; }; // in: counts, out: first ranks
layout(binding = 6, std430) writeonly buffer Avail { uint vsmAvail[]; };
layout(binding = 7, std430) buffer Counters { VsmCounters vsmCounters; };

#include "shadows/virtual/vsm_alloc_common.glsl"

const uint kClasses = 9u; // 0 free, 1..8 evictable from oldest (age >= 128) to newest (age 1)

uint pageClass(uint p) {
    uint owner = vsmOwner[p];
    if (owner == ML_VSM_NO_OWNER) return 0u;
    if (vsmWanted(owner)) return kClasses; // in use this frame
    uint age = max(vsm.sizes.w - vsmLastUsed[p], 1u);
    return 8u - min(uint(findMSB(age)), 7u);
}

void main() {
    uint i = gl_LocalInvocationIndex;
    // 1. Block ranks: each thread sums a contiguous run of blocks, then one scan over the runs.
    uint entries = vsm.order.y;
    uint blocks = (entries + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    uint run = (blocks + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    uint first = min(i * run, blocks), last = min(first + run, blocks);
    uint local = 0u;
    for (uint b = first; b < last; ++b) local += vsmBlockCounts[b];
    uint requests;
    uint base = vsmBlockScan(local, requests);
    for (uint b = first; b < last; ++b) {
        uint c = vsmBlockCounts[b];
        vsmBlockCounts[b] = base;
        base += c;
    }
    // 2. Available pages, class by class, each in index order.
    uint pool = vsm.sizes.z;
    uint count = 0u, freePages = 0u, owned = 0u;
    for (uint c = 0u; c < kClasses; ++c) {
        for (uint p0 = 0u; p0 < pool; p0 += ML_VSM_BLOCK) {
            uint p = p0 + i;
            uint cls = p < pool ? pageClass(p) : kClasses + 1u;
            uint sum;
            uint rank = vsmBlockScan(cls == c ? 1u : 0u, sum);
            if (cls == c) vsmAvail[count + rank] = p;
            count += sum;
            if (c == 0u) freePages += sum;
        }
    }
    if (i == 0u) {
        vsmCounters.requests = requests;
        vsmCounters.available = count;
        vsmCounters.pressure = requests > count ? 1u : 0u;
        // Owned before assignment (pool minus free), plus the free pages that requests take.
        vsmCounters.pagesAllocated = (pool - freePages) + min(requests, freePages);
    }
}
