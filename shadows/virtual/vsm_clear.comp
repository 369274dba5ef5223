#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_clear: one workgroup per page rendered this frame (indirect dispatch: the count vsm_assign
// appended), resetting its texels to empty before the draws take the atomic minimum. Only the pages drawn
// this frame are touched; cached pages keep their depths. With the static layer (vsm.camera.w; the pool's
// second half holds each page's static twin) the twin is emptied too unless it is kept
// (ML_VSM_RENDER_FROM_STATIC: only dynamic casters moved over the page). The draws then put static
// casters into the twin only and dynamic casters into the page, and vsm_merge takes the minimum of both:
// one atomic per fragment, as without the layer.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_CLEAR_GROUP) in;

layout(binding = ML_VSM_CLEAR_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_CLEAR_RENDERED, std430) readonly buffer Rendered { uint vsmRendered[]; };
layout(binding = ML_VSM_CLEAR_PAGE_POOL, std430) writeonly buffer PagePool { uint vsmPool[]; };

void main() {
    uint texels = vsm.page.x * vsm.page.x;
    uint word = vsmRendered[gl_WorkGroupID.x];
    uint base = (word & ML_VSM_PHYS_MASK) * texels;
    uint twin = base + vsm.sizes.z * texels; // the static layer: pool pages further on
    bool clearTwin = vsm.camera.w != 0.0 && (word & ML_VSM_RENDER_FROM_STATIC) == 0u;
    for (uint i = gl_LocalInvocationIndex; i < texels; i += ML_VSM_CLEAR_GROUP) {
        vsmPool[base + i] = 0xFFFFFFFFu;
        if (clearTwin) vsmPool[twin + i] = 0xFFFFFFFFu;
    }
}
