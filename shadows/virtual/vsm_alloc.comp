#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_alloc (allocation 4/6), one workgroup, over per-block counts only (list blocks and pool blocks):
//   1. exclusive prefix sum of the request list's per-block request counts (vsm_scan) -> each block's
//      first rank;
//   2. exclusive prefix sum of the owned blocks' class counts (vsm_scan) in class-major order ->
//      where each block's pages of each class start in the available-page list (vsm_avail writes it):
//      after the free pages (the pool past the owned prefix, by index: places 0 .. free - 1), cached
//      pages whose entry is not wanted, least recently used first;
//   3. vsm_avail's dispatch size: the owned blocks when the requests exceed the free pages, else none.
// Rank r of vsm_assign takes the r-th available page; ranks past them are fallbacks (counted).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_ALLOC_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_ALLOC_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_ALLOC_BLOCK_COUNTS, std430) buffer BlockCounts { uint vsmBlockCounts[]; }; // in: counts, out: first ranks
layout(binding = ML_VSM_ALLOC_CLASS_COUNTS, std430) buffer ClassCounts { uint vsmClassCounts[]; }; // in: counts, out: first slots
layout(binding = ML_VSM_ALLOC_SORT_ARGS, std430) buffer SortArgs { uint vsmSortArgs[]; }; // vsm_types.h

#define VSM_NO_RUNS
#define VSM_NO_MARKS
#include "shadows/virtual/vsm_alloc_common.glsl"

const uint kClasses = 9u;

void main() {
    uint i = gl_LocalInvocationIndex;
    // 1. Block ranks: each thread sums a contiguous run of blocks, then one scan over the runs.
    uint blocks = (vsmCounters.listCount + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
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
    // 2. Class bases over the owned blocks (class 0 counts 0 there; the free pages come first): item
    // k = class * poolBlocks + block, stored at block * kClasses + class.
    uint owned = vsmSortArgs[ML_VSM_ARGS_OWNED], freePages = vsm.sizes.z - owned;
    uint poolBlocks = (owned + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    uint items = kClasses * poolBlocks;
    run = (items + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    first = min(i * run, items);
    last = min(first + run, items);
    local = 0u;
    for (uint k = first; k < last; ++k) local += vsmClassCounts[(k % poolBlocks) * kClasses + k / poolBlocks];
    uint count;
    base = freePages + vsmBlockScan(local, count);
    for (uint k = first; k < last; ++k) {
        uint at = (k % poolBlocks) * kClasses + k / poolBlocks;
        uint c = vsmClassCounts[at];
        vsmClassCounts[at] = base;
        base += c;
    }
    if (i == 0u) {
        uint available = freePages + count;
        vsmCounters.requests = requests;
        vsmCounters.available = available;
        vsmCounters.pressure = requests > available ? 1u : 0u;
        // Owned before assignment, plus the free pages that requests take.
        vsmCounters.pagesAllocated = owned + min(requests, freePages);
        // 3. Only requests past the free pages read the list vsm_avail writes.
        vsmSortArgs[ML_VSM_ARGS_AVAIL] = requests > freePages ? poolBlocks : 0u;
    }
}
