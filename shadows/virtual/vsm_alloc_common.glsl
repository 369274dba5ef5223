// Shared by the allocation passes (vsm_list, vsm_sort, vsm_scan, vsm_alloc, vsm_avail,
// vsm_assign, vsm_hpb; vsm_allocate_short_list does list to assignment in one workgroup with the same
// functions): the priority order of page-table entries, the classes of physical pages and the
// block prefix sum. The passes walk the request list (the wanted entries, sorted by priority rank) and
// the physical pool, never every entry of every map.
//
// Priority order over the entries of the maps in use (only active maps, those of visible lights, get
// marks; inactive ones keep their ranks as gaps, so a light entering view shifts no rank, and are
// invalidated whole when they become active again): every light's coarsest level first (a perspective
// map's last mip, a directional light's last clip level), then one level finer, and so on; within a
// level the maps in slot order, pages row-major. When the pool cannot hold every wanted page,
// the ones left without a page are the finest, and every lookup still finds a coarser one (receivers
// reserve fallback pages near pressure: VsmSettings::fallbacksOnDemand) as long as the pool holds one
// page per light's coarsest level.
// The CPU lays the order out as runs (uvec4: first rank, map, mip, entries), sorted by first rank, and
// the first rank per (map slot, mip) for vsm_mark; the includer declares vsmRuns[], vsmMarks[] and `vsm`
// (VsmConstants; order.x runs, order.y entries).
#ifndef ML_VSM_ALLOC_COMMON_GLSL
#define ML_VSM_ALLOC_COMMON_GLSL

#include "shadows/virtual/vsm_math.h"

#ifndef VSM_NO_RUNS
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
#endif

#ifdef VSM_LISTS
// Entry i of the sorted request list: the includer declares vsmListA[], vsmListB[] (the sort's two
// buffers) and vsmSorted (which of them holds the sorted list, written by vsm_list).
uint vsmListRank(uint i) { return vsmSorted == 0u ? vsmListA[i] : vsmListB[i]; }
#endif

#ifdef VSM_HPB
// vsm_hpb's step for one wanted entry (the includer declares vsmTable[], vsmHpb[] and `vsm`): a DIRTY
// entry sets the bit of every HPB cell above it, level 1 (2x2 pages) to the mip's last level (one cell).
void vsmHpbMarkEntry(uint entry, uint map, uint mip) {
    if ((vsmTable[entry] & ML_VSM_DIRTY) == 0u) return;
    uint s0 = vsm.page.z, side = s0 >> mip;
    uint page = entry - map * vsm.sizes.x - vsmMipOffset(s0, mip);
    uint x = page % side, y = page / side;
    for (uint level = 1u; (side >> level) != 0u; ++level) {
        uint bit = map * vsm.order.w * 32u + vsmHpbBit(s0, mip, level, x >> level, y >> level);
        uint mask = 1u << (bit & 31u);
        if ((vsmHpb[bit >> 5u] & mask) == 0u) atomicOr(vsmHpb[bit >> 5u], mask);
    }
}
#endif

#ifdef VSM_CLOSE_LIST
// vsm_list's step: clamps the list to its capacity (VsmConstants.order.z; the rest counted in listOverflow),
// writes the list passes' dispatch (ML_VSM_BLOCK entries per group) and each vsm_sort pass's dispatch from
// word ML_VSM_ARGS_SORT of vsmSortArgs (vsm_types.h has the words): the block sort, then merge pass p of runs
// of width w = ML_VSM_BLOCK x 8^(p - 1) only while w < n, so the passes run follow the list's length.
// `passes` is the merge passes at most; with `skip` every sort pass gets 0 groups (the one-workgroup
// allocation sorted the list). Returns the closed length; word 0 (which buffer ends sorted) is the caller's.
uint vsmCloseList(uint passes, bool skip, out uint lastWritten) {
    uint n = vsmCounters.listCount;
    uint capacity = vsm.order.z;
    if (n > capacity) {
        vsmCounters.listOverflow = n - capacity;
        n = capacity;
        vsmCounters.listCount = n;
    }
    uint groups = (n + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    vsmCounters.listGroupsX = groups;
    vsmCounters.listGroupsY = 1u;
    vsmCounters.listGroupsZ = 1u;
    uint run = 1u;
    for (uint pass = 0u; pass <= passes; ++pass) {
        bool needed = pass == 0u || (uint(ML_VSM_BLOCK) << (ML_VSM_MERGE_WAYS_LOG2 * (pass - 1u))) < n;
        uint at = ML_VSM_ARGS_SORT + 3u * pass;
        vsmSortArgs[at] = needed && !skip ? groups : 0u;
        vsmSortArgs[at + 1u] = 1u;
        vsmSortArgs[at + 2u] = 1u;
        if (needed && pass > 0u) ++run;
    }
    lastWritten = run % 2u; // pass p writes list[(p + 1) % 2]
    return n;
}

// Physical pages are taken free ones first, in index order (vsmPageClass: class 0 by index), and never
// given back (eviction hands an owned page to another entry), so the owned pages are a prefix of the
// pool and the free ones its rest: the allocation walks the prefix only, and the free pages' places in
// the available-page list are their indices minus the prefix's length (vsmAssignEntry). A binary search
// over the owners finds the length (log2 of the pool's pages: 12 reads at 4,096). vsmCheckInvariants
// checks the prefix every frame of the GPU tests. The includer declares vsmOwner[] and `vsm`.
uint vsmOwnedPages() {
    uint lo = 0u, hi = vsm.sizes.z;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (vsmOwner[mid] != ML_VSM_NO_OWNER) lo = mid + 1u;
        else hi = mid;
    }
    return lo;
}

// Word ML_VSM_ARGS_OWNED and the multi-dispatch allocation passes' dispatch sizes (vsm_types.h), for n
// list entries and `owned` pages; with `skip` (one workgroup allocated) every pass gets 0 groups.
// vsm_avail gets 0 here: vsm_alloc sizes it once it knows whether any request must evict.
void vsmAllocArgs(uint n, uint owned, bool skip) {
    vsmSortArgs[ML_VSM_ARGS_OWNED] = owned;
    uint pageGroups = (owned + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    uint listGroups = (n + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    // vsm_scan (owned pages, then list entries), vsm_assign (list entries), vsm_alloc, vsm_avail.
    uint sizes[4] = uint[4](pageGroups + listGroups, listGroups, 1u, 0u);
    for (uint k = 0u; k < 4u; ++k) {
        vsmSortArgs[ML_VSM_ARGS_SCAN + 3u * k] = skip ? 0u : sizes[k];
        vsmSortArgs[ML_VSM_ARGS_SCAN + 3u * k + 1u] = 1u;
        vsmSortArgs[ML_VSM_ARGS_SCAN + 3u * k + 2u] = 1u;
    }
}
#endif

#ifndef VSM_NO_MARKS
// Marked: a lookup reads the page. Wanted: marked, or reserved as a fallback page; wanted pages get memory
// and are not evicted. The includer declares `vsm` (VsmConstants).
bool vsmMarked(uint entry) { return (vsmMarks[entry >> 5u] & (1u << (entry & 31u))) != 0u; }
bool vsmWanted(uint entry) { // the third mark region: lookup or fallback mark (vsm_common.glsl's vsmWant)
    return (vsmMarks[2u * vsm.options.w + (entry >> 5u)] & (1u << (entry & 31u))) != 0u;
}

#ifdef VSM_PAGE_CLASSES
// The order in which requests take physical pages: class 0 free (no owner), then cached pages whose entry
// is not wanted this frame, least recently used first (age buckets of powers of two: >= 128 frames is
// class 1, ..., 1 frame class 8), by index within a class; class 9 (wanted this frame) is never taken.
// The free pages are the pool past the owned prefix (vsmOwnedPages), so the passes count and list
// classes 1-8 over the prefix only; rank r below the free pages takes page owned + r (vsmAssignEntry).
// The includer declares vsmOwner[] and vsmLastUsed[].
const uint kVsmClasses = 9u;
uint vsmPageClass(uint p) {
    uint owner = vsmOwner[p];
    if (owner == ML_VSM_NO_OWNER) return 0u;
    if (vsmWanted(owner)) return kVsmClasses;
    uint age = max(vsm.sizes.w - vsmLastUsed[p], 1u);
    return 8u - min(uint(findMSB(age)), 7u);
}
#endif

#ifdef VSM_INVALIDATE
// vsm_scan's invalidation step for owned physical page p (the includer declares vsmOwner[], vsmTable[],
// vsmMaps[], vsmStale[], vsmCounters): for the entry that owns the page, clears last frame's DIRTY bits
// and takes VALID away when its light moved or its map became active (map flag), when a moved caster's
// bounds overlap it (the CPU's stale bits), or always with caching off; the static twin survives dynamic
// casters' stale bits (the second region, from word vsm.options.w, holds static casters').
void vsmInvalidatePage(uint p) {
    uint entry = vsmOwner[p];
    if (entry == ML_VSM_NO_OWNER) return;
    uint pt = vsmTable[entry];
    uint before = pt;
    pt &= ~(ML_VSM_DIRTY | ML_VSM_DIRTY_STATIC);
    uint map = entry / vsm.sizes.x, bit = 1u << (entry & 31u);
    bool whole = vsm.options.y == 0u || (vsmMaps[map].info.y & ML_VSM_MAP_INVALIDATE) != 0u;
    bool staticStale = whole || (vsmStale[vsm.options.w + (entry >> 5u)] & bit) != 0u;
    bool stale = staticStale || (vsmStale[entry >> 5u] & bit) != 0u;
    if (staticStale) pt &= ~ML_VSM_STATIC_VALID;
    if ((pt & ML_VSM_VALID) != 0u && stale) {
        pt &= ~ML_VSM_VALID;
        atomicAdd(vsmCounters.pagesInvalidated, 1u);
        if (!whole) atomicAdd(vsmCounters.pagesInvalidatedCaster, 1u);
    }
    // Only clears bits: an atomic AND, as vsm_scan's list groups read the same words in the same dispatch.
    if (pt != before) atomicAnd(vsmTable[entry], pt);
}
#endif

#ifdef VSM_ASSIGN
// vsm_assign's step for one wanted entry of the sorted list (pt: its table word after invalidation; request:
// it had no page; rank: its place among the requests; available, pressure: vsm_alloc's; owned: the owned
// prefix's length). A request of rank r takes the r-th available page: free page owned + r while r is below
// the free pages (pool - owned), else vsmAvail[r] (an evictable page), evicting that page's previous entry;
// past `available` it is a fallback (counted). Then every marked entry with a page that is not valid is
// rendered this frame (under pressure every reserved fallback page too). Only wanted entries are written and
// no wanted entry is ever evicted, so the writes of different entries do not race. The includer declares the
// buffers.
void vsmAssignEntry(uint entry, uint map, uint mip, uint pt, bool request, uint rank, uint available,
                    bool pressure, uint owned) {
    bool marked = vsmMarked(entry);
    if (request) {
        if (rank >= available) {
            atomicAdd(vsmCounters.fallbacks, 1u);
            return;
        }
        uint p = rank < vsm.sizes.z - owned ? owned + rank : vsmAvail[rank];
        uint old = vsmOwner[p];
        if (old != ML_VSM_NO_OWNER) {
            vsmTable[old] = 0u;
            atomicAdd(vsmCounters.pagesEvicted, 1u);
        }
        vsmOwner[p] = entry;
        vsmLastUsed[p] = vsm.sizes.w;
        pt = ML_VSM_ALLOCATED | p;
    }
    if ((pt & ML_VSM_VALID) == 0u && (marked || pressure)) {
        // With the static layer, a page whose twin is still valid is redrawn from it (dynamic casters
        // only); otherwise both are rendered.
        bool fromStatic = (pt & ML_VSM_STATIC_VALID) != 0u;
        pt |= ML_VSM_VALID | ML_VSM_DIRTY;
        if (vsm.camera.w != 0.0 && !fromStatic) pt |= ML_VSM_STATIC_VALID | ML_VSM_DIRTY_STATIC;
        uint slot = atomicAdd(vsmCounters.dispatchX, 1u);
        vsmRendered[slot] = (pt & ML_VSM_PHYS_MASK) | (fromStatic ? ML_VSM_RENDER_FROM_STATIC : 0u);
        if (request) atomicAdd(vsmCounters.pagesNew, 1u);
        if (fromStatic) atomicAdd(vsmCounters.pagesRenderedDynamic, 1u);
        // The first dirty page of a map lists it for the culling passes (their dispatch's y size).
        if (atomicOr(vsmDirtyMips[map], 1u << mip) == 0u)
            vsmDirtyMaps[atomicAdd(vsmCounters.cullGroupsY, 1u)] = map;
        atomicAdd(vsmCounters.pagesRendered, 1u);
    } else if (marked && (pt & ML_VSM_VALID) != 0u) {
        atomicAdd(vsmCounters.pagesCached, 1u);
    }
    vsmTable[entry] = pt;
}
#endif
#endif // VSM_NO_MARKS

// Block prefix sums in three barriers, not the 18 of a Hillis-Steele scan over 256 (lavapipe runs each
// barrier as a pass over every invocation of the group, so barriers, not adds, were their cost): the
// block is a square of ML_VSM_SCAN_ROW rows of ML_VSM_SCAN_ROW entries; one thread per row scans its row
// in place and stores the row's total, then every thread adds the totals of the rows before its own.
// Integer sums: the same ranks whatever the scheduling.
#define ML_VSM_SCAN_ROW 16u
#if ML_VSM_BLOCK != 256
#error "the block scans take ML_VSM_BLOCK as ML_VSM_SCAN_ROW x ML_VSM_SCAN_ROW entries"
#endif
shared uvec3 sScan[ML_VSM_BLOCK];
shared uvec3 sScanRows[ML_VSM_SCAN_ROW];

// Exclusive prefix sum of three words at once over the workgroup (vsm_avail ranks nine class counts,
// three to a word); total in `sum`.
uvec3 vsmBlockScan3(uvec3 value, out uvec3 sum) {
    uint i = gl_LocalInvocationIndex;
    sScan[i] = value;
    barrier();
    if (i < ML_VSM_SCAN_ROW) {
        uvec3 acc = uvec3(0u);
        for (uint k = i * ML_VSM_SCAN_ROW; k < (i + 1u) * ML_VSM_SCAN_ROW; ++k) {
            uvec3 v = sScan[k];
            sScan[k] = acc;
            acc += v;
        }
        sScanRows[i] = acc;
    }
    barrier();
    uint row = i / ML_VSM_SCAN_ROW;
    uvec3 before = sScan[i];
    sum = uvec3(0u);
    for (uint r = 0u; r < ML_VSM_SCAN_ROW; ++r) {
        if (r == row) before += sum;
        sum += sScanRows[r];
    }
    barrier(); // the next scan may overwrite sScan
    return before;
}

// The same for one word (the request and block ranks).
uint vsmBlockScan(uint value, out uint sum) {
    uvec3 total;
    uint before = vsmBlockScan3(uvec3(value, 0u, 0u), total).x;
    sum = total.x;
    return before;
}

#endif
