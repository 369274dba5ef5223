// GLSL prelude for every manylights shader: version-independent extensions and the shared structs.
#ifndef ML_GLSL_COMMON_H
#define ML_GLSL_COMMON_H
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_scalar_block_layout : require
#include "shaders/shared/gpu_types.h"
#endif
