// Shared by the allocation passes (vsm_scan, vsm_alloc, vsm_assign): the priority order of page-table
// entries and the block prefix sum.
//
// Priority order over the active maps' entries (maps of visible lights; inactive maps get no marks, and
// are invalidated whole when they become active again): coarsest mip first, then active map, then page
// row-major. When the pool cannot hold every marked page, the ones left without a page are the finest
// ones, and every lookup still finds a coarser page (each receiver also marks its fallback page).
// The includer declares vsmActive[] (active map slots) and vsmMarks[].
#ifndef ML_VSM_ALLOC_COMMON_GLSL
#define ML_VSM_ALLOC_COMMON_GLSL

#include "shadows/virtual/vsm_math.h"

// Entries of the active maps in priority order: k -> entry; false past the end.
bool vsmEntryOfOrder(uint k, VsmConstants c, out uint entry, out uint map, out uint mip) {
    uint s0 = c.page.z, mips = c.page.w, maps = c.sizes.y;
    for (int m = int(mips) - 1; m >= 0; --m) {
        uint side = s0 >> uint(m);
        uint n = maps * side * side;
        if (k < n) {
            uint a = k / (side * side);
            map = vsmActive[a];
            uint page = k - a * side * side;
            mip = uint(m);
            entry = map * c.sizes.x + vsmMipOffset(s0, uint(m)) + page;
            return true;
        }
        k -= n;
    }
    entry = 0u;
    map = 0u;
    mip = 0u;
    return false;
}

// Marked: a lookup reads the page. Wanted: marked, or reserved as a fallback page; wanted pages get memory
// and are not evicted. The includer declares `vsm` (VsmConstants).
bool vsmMarked(uint entry) { return (vsmMarks[entry >> 5u] & (1u << (entry & 31u))) != 0u; }
bool vsmWanted(uint entry) {
    return vsmMarked(entry) || (vsmMarks[vsm.options.w + (entry >> 5u)] & (1u << (entry & 31u))) != 0u;
}

shared uint sScan[ML_VSM_BLOCK];

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
