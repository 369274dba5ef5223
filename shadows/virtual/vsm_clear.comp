#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_clear: one workgroup per page rendered this frame (indirect dispatch: the count vsm_assign
// appended), resetting its texels to empty before the draws take the atomic minimum. Only the pages
// drawn this frame are cleared; cached pages keep their depths.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_CLEAR_GROUP) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Rendered { uint vsmRendered[]; };
layout(binding = 2, std430) writeonly buffer PagePool { uint vsmPool[]; };

void main() {
    uint texels = vsm.page.x * vsm.page.x;
    uint base = vsmRendered[gl_WorkGroupID.x] * texels;
    for (uint i = gl_LocalInvocationIndex; i < texels; i += ML_VSM_CLEAR_GROUP) vsmPool[base + i] = 0xFFFFFFFFu;
}
