#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_sort (allocation 2/6): sorts the request list by priority rank, so that the allocation is the same
// whatever order the atomics of vsm_mark appended in (and a CPU reference reproduces it bit for bit).
// Ranks are unique (one per wanted entry). Indirect over the list (vsm_list), ping-ponging two buffers:
//   width 0: each block of ML_VSM_BLOCK entries is sorted in shared memory (rank by counting);
//   width w: runs of w sorted entries are merged k = 2^ML_VSM_MERGE_WAYS_LOG2 at a time; an entry's place
//            in the merged run is its index in its own run plus the number of smaller keys in each of
//            the k - 1 sibling runs (a binary search each).
// ceil(log_k(capacity / ML_VSM_BLOCK)) merge passes follow the block sort (4 at k = 8 and 2^18 entries),
// each a dispatch behind a barrier: n ML_VSM_BLOCK + (k - 1) n log^2 n / log k work for n wanted pages.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_SORT_COUNTERS, std430) readonly buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_SORT_SRC, std430) readonly buffer Src { uint src[]; };
layout(binding = ML_VSM_SORT_DST, std430) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform Push { VsmSortPush push; };

shared uint sKeys[ML_VSM_BLOCK];

void main() {
    uint n = vsmCounters.listCount;
    uint i = gl_GlobalInvocationID.x, l = gl_LocalInvocationIndex;
    if (push.width == 0u) {
        // The block's keys are unique (padding aside, which sorts last and is not written): a key's place
        // is the number of keys below it. Three barriers where a bitonic network takes 37 (lavapipe runs
        // each barrier as a pass over the group); 256 shared reads per thread.
        uint key = i < n ? src[i] : 0xFFFFFFFFu;
        sKeys[l] = key;
        barrier();
        uint place = 0u;
        for (uint k = 0u; k < ML_VSM_BLOCK; ++k) place += sKeys[k] < key ? 1u : 0u;
        barrier();
        if (i < n) sKeys[place] = key;
        barrier();
        if (i < n) dst[i] = sKeys[l];
        return;
    }
    if (i >= n) return;
    const uint ways = 1u << ML_VSM_MERGE_WAYS_LOG2;
    uint w = push.width, run = i / w, first = run & ~(ways - 1u), key = src[i];
    uint place = first * w + (i - run * w); // the merged run's start plus the index in its own run
    for (uint sibling = first; sibling < first + ways; ++sibling) {
        uint lo = sibling * w;
        if (sibling == run || lo >= n) continue; // (siblings past the list hold no keys)
        uint a = lo, b = min(lo + w, n); // the sibling's keys below `key` (keys are unique)
        while (a < b) {
            uint mid = (a + b) / 2u;
            if (src[mid] < key) a = mid + 1u;
            else b = mid;
        }
        place += a - lo;
    }
    dst[place] = key;
}
