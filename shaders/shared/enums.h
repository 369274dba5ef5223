// The enums shared by the API, the CPU code and the shaders: the values are the ML_* macros of config.h
// (what GLSL sees) and the public C++ enums, asserted equal here, so the two cannot drift. Values of
// StaticMethod are stored in bake files and LightKind in GpuLight.info.x: never renumber.
#ifndef ML_ENUMS_H
#define ML_ENUMS_H
#include "shaders/shared/config.h"

#ifdef __cplusplus
// The C++ enums are the public ones (manylights/enums.h, which includes nothing of the module); these
// asserts keep their values equal to the constants GLSL sees.
#include "manylights/enums.h"

namespace ml {
static_assert(uint32_t(LightKind::Spot) == ML_LIGHT_SPOT && uint32_t(LightKind::Point) == ML_LIGHT_POINT &&
              uint32_t(LightKind::Directional) == ML_LIGHT_DIRECTIONAL);
static_assert(uint32_t(StaticMethod::SM) == ML_STATIC_SM && uint32_t(StaticMethod::MH) == ML_STATIC_MH &&
              uint32_t(StaticMethod::MMH) == ML_STATIC_MMH &&
              uint32_t(StaticMethod::DAGMH) == ML_STATIC_DAGMH &&
              uint32_t(StaticMethod::CPVS) == ML_STATIC_CPVS);
static_assert(uint32_t(CullingMode::Clustered) == ML_CULL_CLUSTERED &&
              uint32_t(CullingMode::Tiled) == ML_CULL_TILED && uint32_t(CullingMode::None) == ML_CULL_NONE &&
              uint32_t(CullingMode::ClusteredBrute) == ML_CULL_CLUSTERED_BRUTE);
} // namespace ml
#endif // __cplusplus
#endif // ML_ENUMS_H
