#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_avail (allocation 5/6): one thread per owned physical page writes the page into the available-page
// list at its class's place (vsm_alloc's bases, then the index order within the block: one block prefix
// sum of the nine classes packed together). Pages wanted this frame (class 9) are not listed, nor free
// ones: they fill the first places, page owned + r at place r (vsmAssignEntry), with no list. Only the
// first `requests` places are ever read (vsm_assign's rank r < requests takes place r), so only those
// are written: vsm_alloc gives this pass no groups unless some request must evict (requests past the
// free pages), and a block whose nine first places all lie at or past `requests` returns before its scan.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_AVAIL_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_AVAIL_MARKS, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_AVAIL_OWNERS, std430) readonly buffer Owner { uint vsmOwner[]; };
layout(binding = ML_VSM_AVAIL_LAST_USED, std430) readonly buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = ML_VSM_AVAIL_CLASS_BASES, std430) readonly buffer ClassBases { uint vsmClassBases[]; }; // per block, class
layout(binding = ML_VSM_AVAIL_AVAIL, std430) writeonly buffer Avail { uint vsmAvail[]; };
layout(binding = ML_VSM_AVAIL_COUNTERS, std430) readonly buffer Counters { VsmCounters vsmCounters; };

#define VSM_PAGE_CLASSES
#define VSM_NO_RUNS
#include "shadows/virtual/vsm_alloc_common.glsl"

// The nine per-class ranks in one prefix sum: class c counts in bits 9 * (c % 3) of word c / 3. A block
// holds ML_VSM_BLOCK = 256 pages, so a class's count (at most 256) fits its 9 bits and never carries
// into the next. One scan instead of nine: each scan's barriers cost a pass over every invocation of
// the group on a CPU device (lavapipe), where nine scans were most of the allocation's time (the
// figures: docs/results/log.md).
#if ML_VSM_BLOCK > 511
#error "vsm_avail packs a block's class counts in 9 bits each"
#endif

void main() {
    uint p = gl_GlobalInvocationID.x;
    // Uniform over the workgroup (the same nine words for every thread), so returning before the scan's
    // barriers is allowed. A class with no page in this block still has a first place; counting it
    // only makes the test conservative (a block scanned for nothing), never skips a needed page.
    uint requests = vsmCounters.requests;
    bool needed = false;
    for (uint c = 0u; c < kVsmClasses; ++c)
        needed = needed || vsmClassBases[gl_WorkGroupID.x * kVsmClasses + c] < requests;
    if (!needed) return;
    // Classes do not change between vsm_scan and here: owners change only in vsm_assign, and the
    // last-use refresh of vsm_scan touches wanted pages only (class 9 either way).
    uint cls = p < vsm.sizes.z ? vsmPageClass(p) : kVsmClasses + 1u;
    if (cls == 0u) cls = kVsmClasses + 1u; // free: a place below the prefix's free count, not listed
    uvec3 one = uvec3(0u);
    if (cls < kVsmClasses) one[cls / 3u] = 1u << (9u * (cls % 3u));
    uvec3 total;
    uvec3 ranks = vsmBlockScan3(one, total);
    if (cls < kVsmClasses) {
        uint rank = (ranks[cls / 3u] >> (9u * (cls % 3u))) & 511u;
        uint at = vsmClassBases[gl_WorkGroupID.x * kVsmClasses + cls] + rank;
        if (at < requests) vsmAvail[at] = p;
    }
}
