// Push block of the lookup timing pass (bench_lookup.comp, shadows/tools/lookup_timer.cpp), defined once
// for C++ and GLSL; layout rules as in shaders/shared/gpu_types.h.
#ifndef ML_LOOKUP_PUSH_H
#define ML_LOOKUP_PUSH_H

#include "shaders/shared/gpu_types.h"

#ifdef __cplusplus
namespace ml::gpu {
#endif

// 16 bytes: pairs, lookups per pair, the PCF radius every record is given.
ML_STRUCT(LookupPush) {
    uint count;
    uint lookups;
    uint radius;
    uint pad;
};

#ifdef __cplusplus
static_assert(sizeof(LookupPush) == 16);
} // namespace ml::gpu
#endif

#endif
