#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_invalidate (allocation 3/7): one thread per owned physical page (indirect: vsm_list sized it to the
// owned prefix, vsmOwnedPages; free pages have no entry to invalidate and their class is implicit).
// For the entry that owns the page:
//   - clears last frame's DIRTY bit (only owned entries are ever DIRTY: vsm_assign sets it with a page);
//   - invalidation: the page loses VALID when its light moved or its map became active (map flag), when
//     a moved caster's old or new projected bounds overlap it (the CPU's stale bits, one per entry), or
//     always with caching off; its static twin (ML_VSM_STATIC_VALID) survives the stale bits of dynamic
//     casters: it is lost only to the map flag, caching off, or a static caster's bits (the second
//     region of the stale bits, from word vsm.options.w).
// Then counts the pages of classes 1-8 (vsm_alloc_common.glsl) per block of ML_VSM_BLOCK pages, for
// vsm_alloc's prefix sum of the available-page list (class 0, the free pages past the prefix, stays 0).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_INVALIDATE_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_INVALIDATE_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_INVALIDATE_STALE, std430) readonly buffer Stale { uint vsmStale[]; };
layout(binding = ML_VSM_INVALIDATE_TABLE, std430) buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_INVALIDATE_MARKS, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_INVALIDATE_OWNERS, std430) readonly buffer Owner { uint vsmOwner[]; };
layout(binding = ML_VSM_INVALIDATE_LAST_USED, std430) readonly buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = ML_VSM_INVALIDATE_CLASS_COUNTS, std430) writeonly buffer ClassCounts { uint vsmClassCounts[]; }; // per block, class
layout(binding = ML_VSM_INVALIDATE_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };

#define VSM_PAGE_CLASSES
#define VSM_NO_RUNS
#define VSM_INVALIDATE
#include "shadows/virtual/vsm_alloc_common.glsl"

shared uint sClass[kVsmClasses];

void main() {
    uint p = gl_GlobalInvocationID.x, l = gl_LocalInvocationIndex;
    if (l < kVsmClasses) sClass[l] = 0u;
    barrier();
    if (p < vsm.sizes.z) {
        vsmInvalidatePage(p);
        uint c = vsmPageClass(p);
        if (c != 0u && c < kVsmClasses) atomicAdd(sClass[c], 1u); // counts: the same whatever the order
    }
    barrier();
    if (l < kVsmClasses) vsmClassCounts[gl_WorkGroupID.x * kVsmClasses + l] = sClass[l];
}
