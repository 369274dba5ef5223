#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_clear: one workgroup per page rendered this frame (indirect dispatch: the count vsm_assign
// appended), resetting its texels before the draws take the atomic minimum. Only the pages drawn this
// frame are touched; cached pages keep their depths. With the static layer (vsm.camera.w, the pool's
// second half holds each page's static twin):
//   - a page redrawn from its twin (ML_VSM_RENDER_FROM_STATIC: only dynamic casters moved over it) starts
//     as a copy of the twin, and only the dynamic casters are drawn into it: the minimum over every
//     caster, the same value a full redraw gives, since the static casters' depths are unchanged;
//   - any other rendered page is emptied together with its twin (both are drawn).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_CLEAR_GROUP) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Rendered { uint vsmRendered[]; };
layout(binding = 2, std430) buffer PagePool { uint vsmPool[]; };

void main() {
    uint texels = vsm.page.x * vsm.page.x;
    uint word = vsmRendered[gl_WorkGroupID.x];
    uint base = (word & ML_VSM_PHYS_MASK) * texels;
    uint twin = base + vsm.sizes.z * texels; // the static layer: pool pages further on
    bool layered = vsm.camera.w != 0.0;
    if ((word & ML_VSM_RENDER_FROM_STATIC) != 0u) {
        for (uint i = gl_LocalInvocationIndex; i < texels; i += ML_VSM_CLEAR_GROUP) vsmPool[base + i] = vsmPool[twin + i];
        return;
    }
    for (uint i = gl_LocalInvocationIndex; i < texels; i += ML_VSM_CLEAR_GROUP) {
        vsmPool[base + i] = 0xFFFFFFFFu;
        if (layered) vsmPool[twin + i] = 0xFFFFFFFFu;
    }
}
