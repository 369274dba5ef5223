// Push block of the dual depth bake (dual_depth.vert / .frag, shadows/gpu/dual_depth_gpu.cpp), defined
// once for C++ and GLSL; layout rules as in shaders/shared/gpu_types.h.
#ifndef ML_DUAL_DEPTH_PUSH_H
#define ML_DUAL_DEPTH_PUSH_H

#include "shaders/shared/gpu_types.h"

#ifdef __cplusplus
namespace ml::gpu {
#endif

// One tile of one light, 144 bytes: the vertex stage projects, the fragment stage quantises by far.
ML_STRUCT(DualDepthPush) {
    mat4 viewProj; // light view, then the projection of this tile
    mat4 view;
    vec4 params; // x far, y tile x0, z tile y0, w tile size
};

#ifdef __cplusplus
static_assert(sizeof(DualDepthPush) == 144);
static_assert(offsetof(DualDepthPush, params) == 128);
} // namespace ml::gpu
#endif

#endif
