#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_avail (allocation 6/7): one thread per physical page writes the page into the available-page list
// at its class's place (vsm_alloc's bases, then the index order within the block: one block prefix sum
// per class). Pages wanted this frame (class 9) are not listed.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = 2, std430) readonly buffer Owner { uint vsmOwner[]; };
layout(binding = 3, std430) readonly buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = 4, std430) readonly buffer ClassBases { uint vsmClassBases[]; }; // per block, class
layout(binding = 5, std430) writeonly buffer Avail { uint vsmAvail[]; };

#define VSM_PAGE_CLASSES
#define VSM_NO_RUNS
#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint p = gl_GlobalInvocationID.x;
    // Classes do not change between vsm_invalidate and here: owners change only in vsm_assign, and the
    // last-use refresh of vsm_scan touches wanted pages only (class 9 either way).
    uint cls = p < vsm.sizes.z ? vsmPageClass(p) : kVsmClasses + 1u;
    for (uint c = 0u; c < kVsmClasses; ++c) {
        uint sum;
        uint rank = vsmBlockScan(cls == c ? 1u : 0u, sum);
        if (cls == c) vsmAvail[vsmClassBases[gl_WorkGroupID.x * kVsmClasses + c] + rank] = p;
    }
}
