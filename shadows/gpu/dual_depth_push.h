// Push block and binding numbers of the dual depth bake (dual_depth.vert / .frag,
// shadows/gpu/dual_depth_gpu.cpp), defined once for C++ and GLSL; layout rules as in
// shaders/shared/gpu_types.h. The C++ binds each resource by its binding's name (ML_BIND, gpu/bindings.h).
#ifndef ML_DUAL_DEPTH_PUSH_H
#define ML_DUAL_DEPTH_PUSH_H

#include "shaders/shared/gpu_types.h"

#define ML_DUAL_DEPTH_VERTICES 0 // world-space caster triangles (vertex stage)
#define ML_DUAL_DEPTH_ENTER 1    // the three R32_UINT tile images (fragment stage)
#define ML_DUAL_DEPTH_CLOSED 2
#define ML_DUAL_DEPTH_EXIT 3

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
