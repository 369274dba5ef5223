#version 460
#extension GL_GOOGLE_include_directive : require
// Dual depth bake, one of three passes over the same triangles (kSpecPass), all order-independent
// integer atomics on R32_UINT storage images of the tile:
//   0 enter:  atomicMin of every fragment's depth.
//   1 closed: a closed front face at exactly the enter depth marks the texel (the ray enters a closed mesh).
//   2 exit:   atomicMin of closed back faces at or behind enter (only read where marked).
// The CPU turns them into [enter, exit]: marked ? exit (or far when no back face) : enter. The nearest
// back face behind a closed entry always lies inside closed geometry, so the interval never claims
// space outside it (it may end earlier than the CPU reference's counting rule where closed meshes nest).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/gpu/dual_depth_push.h"

layout(constant_id = 0) const uint kSpecPass = 0;
layout(binding = ML_DUAL_DEPTH_ENTER, r32ui) uniform coherent uimage2D enterImage;
layout(binding = ML_DUAL_DEPTH_CLOSED, r32ui) uniform coherent uimage2D closedImage;
layout(binding = ML_DUAL_DEPTH_EXIT, r32ui) uniform coherent uimage2D exitImage;
layout(push_constant) uniform Push { DualDepthPush push; };
layout(location = 0) in float inDepth;
layout(location = 1) flat in uint inClosed;

void main() {
    float t = clamp(inDepth / push.params.x, 0.0, 1.0);
    uint depth = t >= 1.0 ? 0xFFFFFFFEu : uint(t * 4294967040.0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (kSpecPass == 0u) {
        imageAtomicMin(enterImage, p, depth);
    } else if (kSpecPass == 1u) {
        if (inClosed == 1u && gl_FrontFacing && depth == imageLoad(enterImage, p).x) imageAtomicOr(closedImage, p, 1u);
    } else {
        if (inClosed == 1u && !gl_FrontFacing && depth >= imageLoad(enterImage, p).x) imageAtomicMin(exitImage, p, depth);
    }
}
