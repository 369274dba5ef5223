// Push block and binding numbers of the static decode test program (test_static_decode.comp,
// tests/gpu/static_test.cpp), defined once for C++ and GLSL; layout rules as in
// shaders/shared/gpu_types.h. The test binds each buffer by its binding's name (ML_BIND, gpu/bindings.h).
#ifndef ML_STATIC_DECODE_PUSH_H
#define ML_STATIC_DECODE_PUSH_H

#include "shaders/shared/gpu_types.h"

#define ML_DECODE_WORDS 0 // the encoding, at push.base
#define ML_DECODE_OUT 1   // the decoded texels or voxel columns

#ifdef __cplusplus
namespace ml::gpu {
#endif

// 16 bytes: the encoding (StaticMethod), its first word in the bound buffer, its resolution.
ML_STRUCT(StaticDecodePush) {
    uint method;
    uint base;
    uint res;
    uint pad;
};

#ifdef __cplusplus
static_assert(sizeof(StaticDecodePush) == 16);
} // namespace ml::gpu
#endif

#endif
