#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_merge (static layer only, VsmSettings::staticLayer with caching): one workgroup per page rendered
// this frame (the clear pass's indirect dispatch), after the draws. The draws put the static casters'
// depths into the page's static twin (the pool's second half; only where the twin is rendered this frame)
// and the dynamic casters' into the page itself; the page becomes the minimum of both. That is the
// minimum over every caster, the value a single layer's draws give bit for bit (the atomic minimum is
// order-independent, and a kept twin holds the unchanged static casters' depths). Cost: 2 reads and a
// write per texel of a rendered page, against a second atomic per static fragment were the static casters
// drawn into both layers.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_CLEAR_GROUP) in;

layout(binding = ML_VSM_MERGE_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_MERGE_RENDERED, std430) readonly buffer Rendered { uint vsmRendered[]; };
layout(binding = ML_VSM_MERGE_PAGE_POOL, std430) buffer PagePool { uint vsmPool[]; };

void main() {
    uint texels = vsm.page.x * vsm.page.x;
    uint base = (vsmRendered[gl_WorkGroupID.x] & ML_VSM_PHYS_MASK) * texels;
    uint twin = base + vsm.sizes.z * texels;
    for (uint i = gl_LocalInvocationIndex; i < texels; i += ML_VSM_CLEAR_GROUP) {
        uint t = vsmPool[twin + i];
        if (t < vsmPool[base + i]) vsmPool[base + i] = t;
    }
}
