// The enums shared by the API, the CPU code and the shaders, each defined once: the values are the
// ML_* macros of config.h (what GLSL sees), and the C++ enums take them from there, so the two cannot
// drift. Values of StaticMethod are stored in bake files and LightKind in GpuLight.info.x: never renumber.
#ifndef ML_ENUMS_H
#define ML_ENUMS_H
#include "shaders/shared/config.h"

#ifdef __cplusplus
#include <cstdint>

namespace ml {

// A light's kind: the API (LightDesc::kind), scenes (Light::type) and the GPU (GpuLight.info.x).
enum class LightKind : uint32_t {
    Spot = ML_LIGHT_SPOT,
    Point = ML_LIGHT_POINT,
    Directional = ML_LIGHT_DIRECTIONAL,
};

// A static shadow's encoding (bake files, GpuShadowRecord.method); None: no static shadow.
enum class StaticMethod : uint32_t {
    None = 0,
    SM = ML_STATIC_SM,
    MH = ML_STATIC_MH,
    MMH = ML_STATIC_MMH,
    DAGMH = ML_STATIC_DAGMH,
    CPVS = ML_STATIC_CPVS,
};

// Clustered: per-light footprint assignment; ClusteredBrute: the same lists from every light against
// every occupied cluster (kept for comparison); Tiled: one depth slice; None: every light everywhere
// (culling/culling.h). The shaders see the value as ML_CULL_*.
enum class CullingMode : uint32_t {
    Clustered = ML_CULL_CLUSTERED,
    Tiled = ML_CULL_TILED,
    None = ML_CULL_NONE,
    ClusteredBrute = ML_CULL_CLUSTERED_BRUTE,
};

} // namespace ml
#endif // __cplusplus
#endif // ML_ENUMS_H
