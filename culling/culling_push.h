// Push block of the footprint light assignment (light_footprint, light_alloc, light_fill), defined once
// for C++ (culling.cpp) and GLSL; layout rules as in shaders/shared/gpu_types.h.
#ifndef ML_CULLING_PUSH_H
#define ML_CULLING_PUSH_H

#include "shaders/shared/gpu_types.h"

#ifdef __cplusplus
namespace ml::gpu {
#endif

// The hit list's capacity (LightCulling::hitCapacity): hits past it are counted but not stored, and
// light_alloc then flags the clusters overflowed (their pixels test every visible light). 4 bytes.
ML_STRUCT(CullPush) {
    uint hitCapacity;
};

#ifdef __cplusplus
static_assert(sizeof(CullPush) == 4);
} // namespace ml::gpu
#endif

#endif
