// Push block of the footprint light assignment (light_footprint, light_alloc, light_fill), defined once
// for C++ (culling.cpp) and GLSL; layout rules as in shaders/shared/gpu_types.h.
#ifndef ML_CULLING_PUSH_H
#define ML_CULLING_PUSH_H

#include "shaders/shared/gpu_types.h"
#ifdef __cplusplus
#include <cstddef>
#endif

#ifdef __cplusplus
namespace ml::gpu {
#endif

// hitCapacity: the hit list's capacity (LightCulling::hitCapacity): hits past it are counted but not
// stored, and light_alloc then flags the clusters overflowed (their pixels test every visible light).
// wideCount, wideThreads: wide lights this frame and the wide pass's threads (the sum of their
// footprints' tiles; directional lights, config.h). 12 bytes.
ML_STRUCT(CullPush) {
    uint hitCapacity;
    uint wideCount;
    uint wideThreads;
};

// One wide light for the wide pass, written by the host (LightCulling::wideLights): its footprint
// as the host computed it (lightFootprint), so host and shader agree on its tiles exactly, and its
// first thread: the wide pass's thread t works on tile t - first of the light whose range holds t.
// 48 bytes.
ML_STRUCT(WideLight) {
    uvec4 tiles; // footprint rectangle x0, y0, x1, y1 (inclusive)
    vec4 depth;  // footprint depth range (x near, y far), zw unused
    uint light;  // visible-light index
    uint first;  // first thread (prefix sum of the earlier wide lights' tile counts)
    uint count;  // tiles of the rectangle
    uint pad;
};

#ifdef __cplusplus
static_assert(sizeof(CullPush) == 12);
static_assert(sizeof(WideLight) == 48 && offsetof(WideLight, light) == 32);
} // namespace ml::gpu
#endif

#endif
