// Shared by the allocation passes (vsm_scan, vsm_alloc, vsm_assign): the priority order of page-table
// entries and the block prefix sum.
//
// Priority order over the active maps' entries (maps of visible lights; inactive maps get no marks, and
// are invalidated whole when they become active again): every light's coarsest level first (a
// perspective map's last mip, a directional light's last clip level), then one level finer, and so on;
// within a level the active maps in order, pages row-major. When the pool cannot hold every wanted page,
// the ones left without a page are the finest, and every lookup still finds a coarser one (each receiver
// reserves its fallback pages) as long as the pool holds one page per light's coarsest level.
// The CPU lays the order out as runs (uvec4: first rank, map, mip, entries), sorted by first rank;
// the includer declares vsmRuns[], vsmMarks[] and `vsm` (VsmConstants; order.x runs, order.y entries).
#ifndef ML_VSM_ALLOC_COMMON_GLSL
#define ML_VSM_ALLOC_COMMON_GLSL

#include "shadows/virtual/vsm_math.h"

// Entries in priority order: rank k -> entry (binary search over the runs); false past the end.
bool vsmEntryOfOrder(uint k, VsmConstants c, out uint entry, out uint map, out uint mip) {
    entry = 0u;
    map = 0u;
    mip = 0u;
    if (k >= c.order.y) return false;
    uint lo = 0u, hi = c.order.x; // the run holding k is the last with first rank <= k
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (vsmRuns[mid].x <= k) lo = mid;
        else hi = mid;
    }
    uvec4 run = vsmRuns[lo];
    map = run.y;
    mip = run.z;
    entry = map * c.sizes.x + vsmMipOffset(c.page.z, mip) + (k - run.x);
    return true;
}

// Marked: a lookup reads the page. Wanted: marked, or reserved as a fallback page; wanted pages get memory
// and are not evicted. The includer declares `vsm` (VsmConstants).
bool vsmMarked(uint entry) { return (vsmMarks[entry >> 5u] & (1u << (entry & 31u))) != 0u; }
bool vsmWanted(uint entry) {
    return vsmMarked(entry) || (vsmMarks[vsm.options.w + (entry >> 5u)] & (1u << (entry & 31u))) != 0u;
}

shared uint sScan[ML_VSM_BLOCK];

// The block (workgroup) index of vsm_scan / vsm_assign: their blocks are dispatched as a 2-D grid of
// at most maxComputeWorkGroupCount[0] per row (16384^2 maps of 64^2 pages, 256 lights: 88,235 blocks,
// past 65,535 in one dimension), linearised row-major. Blocks of the last row past `vsm.order.y`
// entries are padding: whole groups with nothing to do (the caller returns before its barriers).
uint vsmBlockIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }
bool vsmPaddingBlock(uint block) { return block * ML_VSM_BLOCK >= max(vsm.order.y, 1u); }

// Exclusive prefix sum of `value` over the workgroup (Hillis-Steele in shared memory); total in `sum`.
// Deterministic: the same inputs give the same ranks whatever the scheduling.
uint vsmBlockScan(uint value, out uint sum) {
    uint i = gl_LocalInvocationIndex;
    sScan[i] = value;
    barrier();
    for (uint offset = 1u; offset < ML_VSM_BLOCK; offset <<= 1u) {
        uint add = i >= offset ? sScan[i - offset] : 0u;
        barrier();
        sScan[i] += add;
        barrier();
    }
    sum = sScan[ML_VSM_BLOCK - 1u];
    uint inclusive = sScan[i];
    barrier();
    return inclusive - value;
}

#endif
