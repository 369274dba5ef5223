#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_allocate_short_list: the whole allocation of a short request list in one workgroup, one dispatch:
// it closes the list (vsm_list), and when it holds at most push.shortList entries (ML_VSM_ONE_GROUP_LIST
// at most; 0: never) it invalidates the owned pages (vsm_scan), sorts the list in shared memory,
// refreshes last use and ranks the requests (vsm_scan), ranks the free and evictable pages by class
// (vsm_alloc, vsm_avail), assigns pages (vsm_assign) and, recorded alone, sets the HPB bits (vsm_hpb),
// with the same functions of vsm_alloc_common.glsl, so the page table, owners, last use and HPB equal the
// multi-dispatch path's and the CPU references' (vsmAllocateReference) bit for bit. Longer lists are left to the multi-dispatch passes: it writes
// their dispatch sizes, which are 0 groups after a short list. vsm_passes.cpp records those passes only
// when the slot's previous list was long (or unknown); otherwise it records this dispatch alone and sets
// ML_VSM_ANY_LENGTH, and a list that outgrew the limit since is sorted here in the two list buffers
// instead of shared memory (slower, one core, but the same order), so no frame is left unallocated.
// Word 1 of vsmSortArgs says which: 1 shared memory, 2 the list buffers, 0 the multi-dispatch passes.
//
// Threads own contiguous chunks (list entries and pool pages in index order), so a chunk's prefix over the
// threads before it keeps the multi-dispatch path's order: the ranks of requests by list position, and the
// available-page list by class, then page index. The pool walks cover the owned prefix only (vsmOwnedPages):
// free pages need no invalidation and take the first places by index without a list. Barriers: lavapipe runs
// each as a pass over the group's invocations; the sort takes at most 9 of them, the rest about 15.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_alloc_bindings.h"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_SHORT_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_SHORT_RUNS, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = ML_VSM_SHORT_COUNTERS, std430) coherent buffer Counters { VsmCounters vsmCounters; };
// The requests; also the second merge buffer of a list sorted in the list buffers.
layout(binding = ML_VSM_SHORT_REQUESTS, std430) coherent buffer ListA { uint vsmListA[]; };
layout(binding = ML_VSM_SHORT_SORTED, std430) coherent buffer ListB { uint vsmListB[]; }; // merge buffer
layout(binding = ML_VSM_SHORT_SORT_ARGS, std430) writeonly buffer SortArgs { uint vsmSortArgs[]; };
layout(binding = ML_VSM_SHORT_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_SHORT_STALE, std430) readonly buffer Stale { uint vsmStale[]; };
// Written by one thread and read by another across barriers: coherent, with memoryBarrierBuffer().
layout(binding = ML_VSM_SHORT_TABLE, std430) coherent buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_SHORT_MARKS, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_SHORT_OWNERS, std430) coherent buffer Owner { uint vsmOwner[]; };
layout(binding = ML_VSM_SHORT_LAST_USED, std430) coherent buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = ML_VSM_SHORT_AVAIL, std430) coherent buffer Avail { uint vsmAvail[]; };
layout(binding = ML_VSM_SHORT_RENDERED, std430) writeonly buffer Rendered { uint vsmRendered[]; };
layout(binding = ML_VSM_SHORT_DIRTY_MIPS, std430) buffer MapMips { uint vsmDirtyMips[]; };
layout(binding = ML_VSM_SHORT_DIRTY_MAPS, std430) writeonly buffer DirtyMaps { uint vsmDirtyMaps[]; };
layout(binding = ML_VSM_SHORT_HPB, std430) buffer Hpb { uint vsmHpb[]; }; // cleared at the frame's start
// width: vsm_sort's merge passes at most; shortList: the longest list taken here (0: none).
layout(push_constant) uniform Push { VsmSortPush push; };

#define VSM_CLOSE_LIST
#define VSM_PAGE_CLASSES
#define VSM_INVALIDATE
#define VSM_ASSIGN
#define VSM_HPB
#include "shadows/virtual/vsm_alloc_common.glsl"

shared uint sKeys[ML_VSM_ONE_GROUP_LIST]; // the list (16 KiB at 4,096)
shared uint sCount, sShort, sOwned; // sShort: the path, vsmSortArgs word 1's values

// A list past the shared keys (ML_VSM_ANY_LENGTH) is sorted in the list buffers: runs of this many keys
// sorted by insertion, then pairwise merges between list B and list A, one barrier each: at 8,192
// entries 9 merges over 32 entries a thread.
const uint kGlobalRun = 16u;
// The merges of the list-buffer sort for n entries; the sorted list ends in list B after an even count.
uint globalMerges(uint n) {
    uint merges = 0u;
    for (uint w = kGlobalRun; w < n; w *= 2u) ++merges;
    return merges;
}

// Both barriers: global writes of this workgroup (table, owners, last use, avail) -> its next reads.
void allBarrier() {
    memoryBarrierBuffer();
    memoryBarrierShared();
    barrier();
}

// Entry i of the sorted list: the shared keys, or the list buffer the last merge wrote.
uint sortedKey(uint i, bool inShared, bool inB) {
    return inShared ? sKeys[i] : inB ? vsmListB[i] : vsmListA[i];
}

void main() {
    uint t = gl_LocalInvocationIndex;
    if (t == 0u) {
        uint sorted;
        uint n = vsmCloseList(push.width, false, sorted);
        uint limit = push.shortList & ~ML_VSM_ANY_LENGTH;
        bool isShort = limit != 0u && n <= limit;
        bool here = isShort || (push.shortList & ML_VSM_ANY_LENGTH) != 0u;
        if (here) vsmCloseList(push.width, true, sorted); // the same sizes, the sort passes empty
        // Shared memory: the sorted copy goes to list B; list buffers: B after an even number of merges.
        vsmSortArgs[0] = isShort ? 1u : here ? 1u - globalMerges(n) % 2u : sorted;
        vsmSortArgs[1] = isShort ? 1u : here ? 2u : 0u;
        vsmSortArgs[2] = n;
        // The multi-dispatch passes' sizes, where they are recorded (0 groups after a list allocated here).
        uint owned = vsmOwnedPages();
        vsmAllocArgs(n, owned, here);
        sCount = n;
        sShort = isShort ? 1u : here ? 2u : 0u;
        sOwned = owned;
    }
    allBarrier();
    if (sShort == 0u) return; // uniform: the multi-dispatch passes allocate
    bool inShared = sShort == 1u; // uniform: shared memory or the list buffers
    uint n = sCount, pool = vsm.sizes.z, owned = sOwned, freePages = pool - owned;
    uint pageRun = (owned + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    uint listRun = (n + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    uint pageFirst = min(t * pageRun, owned), pageLast = min(pageFirst + pageRun, owned);
    uint listFirst = min(t * listRun, n), listLast = min(listFirst + listRun, n);

    // 1. vsm_scan's invalidation: per owned page, and the class counts of this thread's pages (classes 1-9).
    uint counts[kVsmClasses];
    for (uint c = 0u; c < kVsmClasses; ++c) counts[c] = 0u;
    for (uint p = pageFirst; p < pageLast; ++p) {
        vsmInvalidatePage(p);
        uint c = vsmPageClass(p);
        if (c < kVsmClasses) ++counts[c];
    }

    // 2. vsm_sort: each thread sorts its own run of the list (insertion sort, at most 16 keys), then runs
    // merge pairwise, alternating between the shared keys and list B: a key's place in the merged run is
    // its index in its own run plus the sibling run's keys below it (binary search), as in vsm_sort. At
    // most log2(ML_VSM_BLOCK) = 8 merges, one barrier each, where a bitonic network over 4,096 keys takes
    // 78 (lavapipe runs each barrier as a pass over the group's invocations: 78 were about half of this
    // pass's time). Ranks are unique, so any sort gives the multi-dispatch path's order.
    bool inB = false; // list buffers: which holds the runs
    if (inShared) {
        for (uint i = listFirst; i < listLast; ++i) {
            uint key = vsmListA[i], j = i;
            while (j > listFirst && sKeys[j - 1u] > key) {
                sKeys[j] = sKeys[j - 1u];
                --j;
            }
            sKeys[j] = key;
        }
        allBarrier(); // also: the invalidated table -> the scan's reads
        for (uint w = max(listRun, 1u); w < n; w *= 2u) {
            for (uint i = t; i < n; i += ML_VSM_BLOCK) {
                uint run = i / w, sibling = run ^ 1u, key = inShared ? sKeys[i] : vsmListB[i];
                uint lo = sibling * w, a = lo, b = min(lo + w, n);
                while (a < b) {
                    uint mid = (a + b) / 2u;
                    if ((inShared ? sKeys[mid] : vsmListB[mid]) < key) a = mid + 1u;
                    else b = mid;
                }
                uint at = min(run, sibling) * w + (i - run * w) + (a > lo ? a - lo : 0u);
                if (inShared) vsmListB[at] = key;
                else sKeys[at] = key;
            }
            allBarrier();
            inShared = !inShared;
        }
        // The sorted list in both: list B for vsm_hpb, the shared keys for the steps below.
        for (uint i = t; i < n; i += ML_VSM_BLOCK) {
            if (inShared) vsmListB[i] = sKeys[i];
            else sKeys[i] = vsmListB[i];
        }
        inShared = true;
    } else {
        // Runs of kGlobalRun keys sorted from list A into list B, then merged between B and A.
        for (uint first = t * kGlobalRun; first < n; first += ML_VSM_BLOCK * kGlobalRun) {
            uint last = min(first + kGlobalRun, n);
            for (uint i = first; i < last; ++i) {
                uint key = vsmListA[i], j = i;
                while (j > first && vsmListB[j - 1u] > key) {
                    vsmListB[j] = vsmListB[j - 1u];
                    --j;
                }
                vsmListB[j] = key;
            }
        }
        inB = true;
        allBarrier(); // the runs in list B -> the merges (also: the invalidated table -> the scan's reads)
        for (uint w = kGlobalRun; w < n; w *= 2u) {
            for (uint i = t; i < n; i += ML_VSM_BLOCK) {
                uint run = i / w, sibling = run ^ 1u, key = inB ? vsmListB[i] : vsmListA[i];
                uint lo = sibling * w, a = lo, b = min(lo + w, n);
                while (a < b) {
                    uint mid = (a + b) / 2u;
                    if ((inB ? vsmListB[mid] : vsmListA[mid]) < key) a = mid + 1u;
                    else b = mid;
                }
                uint at = min(run, sibling) * w + (i - run * w) + (a > lo ? a - lo : 0u);
                if (inB) vsmListA[at] = key;
                else vsmListB[at] = key;
            }
            allBarrier(); // this merge's runs -> the next merge's reads
            inB = !inB;
        }
    }
    allBarrier();

    // 3. vsm_scan: last use of wanted pages that have one; the rest are requests, ranked by list place.
    uint requests = 0u;
    for (uint i = listFirst; i < listLast; ++i) {
        uint entry, map, mip;
        if (!vsmEntryOfOrder(sortedKey(i, inShared, inB), vsm, entry, map, mip)) continue;
        uint pt = vsmTable[entry];
        if (vsmMarked(entry)) atomicAdd(vsmCounters.pagesMarked, 1u);
        if ((pt & ML_VSM_ALLOCATED) != 0u) vsmLastUsed[pt & ML_VSM_PHYS_MASK] = vsm.sizes.w;
        else ++requests;
    }
    uint requestTotal;
    uint requestBase = vsmBlockScan(requests, requestTotal);

    // 4. vsm_alloc: where each class's pages of this thread start in the available-page list (after the
    // free pages, class major, then page index).
    uvec3 total[3];
    uvec3 before[3];
    for (uint w = 0u; w < 3u; ++w)
        before[w] = vsmBlockScan3(uvec3(counts[3u * w], counts[3u * w + 1u], counts[3u * w + 2u]), total[w]);
    uint bases[kVsmClasses];
    uint available = freePages; // class 0's count over the owned pages is 0
    for (uint c = 0u; c < kVsmClasses; ++c) {
        bases[c] = available + before[c / 3u][c % 3u];
        available += total[c / 3u][c % 3u];
    }
    if (t == 0u) {
        vsmCounters.requests = requestTotal;
        vsmCounters.available = available;
        vsmCounters.pressure = requestTotal > available ? 1u : 0u;
        vsmCounters.pagesAllocated = owned + min(requestTotal, freePages);
    }

    // 5. vsm_avail: only the first `requests` places are read, so a thread whose nine first places all
    // lie at or past them skips its pages (with enough free pages, every thread: the free pages' places
    // need no list).
    // Classes are those of step 1: owners change only in step 6, and step 3 refreshed wanted pages only
    // (class 9 either way).
    bool needed = false;
    for (uint c = 1u; c < kVsmClasses; ++c) needed = needed || bases[c] < requestTotal; // (no class 0)
    if (needed) {
        for (uint p = pageFirst; p < pageLast; ++p) {
            uint c = vsmPageClass(p);
            if (c >= kVsmClasses) continue;
            uint rank = bases[c]++;
            if (rank < requestTotal) vsmAvail[rank] = p;
        }
    }
    allBarrier(); // avail, last use -> the assignment

    // 6. vsm_assign.
    uint rank = requestBase;
    for (uint i = listFirst; i < listLast; ++i) {
        uint entry, map, mip;
        if (!vsmEntryOfOrder(sortedKey(i, inShared, inB), vsm, entry, map, mip)) continue;
        uint pt = vsmTable[entry];
        bool request = (pt & ML_VSM_ALLOCATED) == 0u;
        vsmAssignEntry(entry, map, mip, pt, request, rank, available, requestTotal > available, owned);
        if (request) ++rank;
    }

    // 7. vsm_hpb, when recorded alone (vsm_passes.cpp then records no vsm_hpb dispatch): the DIRTY
    // entries of this thread's run set the HPB cells above them. Uniform (a push constant).
    if ((push.shortList & ML_VSM_ANY_LENGTH) == 0u) return;
    allBarrier(); // the assignment's DIRTY bits -> their reads here
    for (uint i = listFirst; i < listLast; ++i) {
        uint entry, map, mip;
        if (vsmEntryOfOrder(sortedKey(i, inShared, inB), vsm, entry, map, mip)) vsmHpbMarkEntry(entry, map, mip);
    }
}
