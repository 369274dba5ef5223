#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_scan (allocation 3/6): one dispatch (indirect, sized by vsm_list or vsm_allocate_short_list) of two
// independent parts, so that they share one barrier:
//   - the first ceil(owned / ML_VSM_BLOCK) workgroups, one thread per owned physical page (the owned
//     prefix, vsmOwnedPages; free pages have no entry to invalidate and their class is implicit): for
//     the entry that owns the page, clears last frame's DIRTY bit (only owned entries are ever DIRTY:
//     vsm_assign sets it with a page) and invalidates it: the page loses VALID when its light moved or
//     its map became active (map flag), when a moved caster's old or new projected bounds overlap it
//     (the CPU's stale bits, one per entry), or always with caching off; its static twin
//     (ML_VSM_STATIC_VALID) survives the stale bits of dynamic casters: it is lost only to the map flag,
//     caching off, or a static caster's bits (the second region of the stale bits, from word
//     vsm.options.w). Then counts the pages of classes 1-8 (vsm_alloc_common.glsl) per block, for
//     vsm_alloc's prefix sum of the available-page list (class 0, the free pages, stays 0);
//   - the rest, one thread per entry of the sorted request list: a wanted entry (marked, or reserved as
//     a fallback) that has a physical page refreshes its last use (LRU); one without is a request,
//     counted per block for vsm_alloc's prefix sum.
// The parts touch different words but for the page table: the invalidation clears VALID and DIRTY bits
// (an atomic AND), the scan reads ALLOCATED and the page index, which the invalidation never changes
// (an atomic read, so the two are not a data race). The scan refreshes the last use of wanted pages
// only, whose class is 9 whatever their last use, so the class counts do not depend on the order.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_SCAN_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_SCAN_RUNS, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = ML_VSM_SCAN_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_SCAN_LIST_A, std430) readonly buffer ListA { uint vsmListA[]; }; // vsm_sort's buffers: priority ranks
layout(binding = ML_VSM_SCAN_TABLE, std430) buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_SCAN_MARKS, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_SCAN_LAST_USED, std430) buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = ML_VSM_SCAN_BLOCK_COUNTS, std430) writeonly buffer BlockCounts { uint vsmBlockCounts[]; };
layout(binding = ML_VSM_SCAN_LIST_B, std430) readonly buffer ListB { uint vsmListB[]; };
layout(binding = ML_VSM_SCAN_SORT_ARGS, std430) readonly buffer Sorted { uint vsmSortArgs[]; }; // vsm_types.h
layout(binding = ML_VSM_SCAN_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_SCAN_STALE, std430) readonly buffer Stale { uint vsmStale[]; };
layout(binding = ML_VSM_SCAN_OWNERS, std430) readonly buffer Owner { uint vsmOwner[]; };
layout(binding = ML_VSM_SCAN_CLASS_COUNTS, std430) writeonly buffer ClassCounts { uint vsmClassCounts[]; }; // per block, class
#define vsmSorted vsmSortArgs[0]
#define VSM_LISTS
#define VSM_PAGE_CLASSES
#define VSM_INVALIDATE
#include "shadows/virtual/vsm_alloc_common.glsl"

shared uint sClass[kVsmClasses];

void main() {
    uint l = gl_LocalInvocationIndex, group = gl_WorkGroupID.x;
    uint owned = vsmSortArgs[ML_VSM_ARGS_OWNED];
    uint pageGroups = (owned + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    if (group < pageGroups) { // uniform over the workgroup: its barriers are allowed
        uint p = group * ML_VSM_BLOCK + l;
        if (l < kVsmClasses) sClass[l] = 0u;
        barrier();
        if (p < owned) {
            vsmInvalidatePage(p);
            uint c = vsmPageClass(p);
            if (c < kVsmClasses) atomicAdd(sClass[c], 1u); // counts: the same whatever the order
        }
        barrier();
        if (l < kVsmClasses) vsmClassCounts[group * kVsmClasses + l] = sClass[l];
        return;
    }
    uint block = group - pageGroups, i = block * ML_VSM_BLOCK + l;
    uint request = 0u, entry, map, mip;
    if (i < vsmCounters.listCount && vsmEntryOfOrder(vsmListRank(i), vsm, entry, map, mip)) {
        uint pt = atomicOr(vsmTable[entry], 0u); // (an atomic read: see above)
        if (vsmMarked(entry)) atomicAdd(vsmCounters.pagesMarked, 1u);
        if ((pt & ML_VSM_ALLOCATED) != 0u) vsmLastUsed[pt & ML_VSM_PHYS_MASK] = vsm.sizes.w;
        else request = 1u;
    }
    uint sum;
    vsmBlockScan(request, sum);
    if (l == 0u) vsmBlockCounts[block] = sum;
}
