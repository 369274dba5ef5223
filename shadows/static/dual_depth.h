// Dual depth maps: the input of every static shadow method (SM, MH, MMH, DAG-MH, CPVS).
//
// A static light sees the scene through a square perspective frustum (a spotlight's cone, or one cube
// face of a point light). Each texel holds an interval [enter, exit] of light-space depth along the
// ray through the texel centre:
//   enter = depth of the first surface the ray meets;
//   exit  = depth where the ray leaves the closed object it entered there (the first back face after
//           enter that closes it). For open (not watertight) meshes exit = enter.
// "Lossless" for a compressed structure means: every value it returns for a texel lies in
// [enter, exit], so a shadow test of any receiver outside closed objects is unchanged.
//
// Depth is integer: linear light-space distance along the light's axis, quantised to 32 bits over
// [0, far] (quantizeDepth). Integer depth lets CPU and GPU decoders agree bit for bit.
// A texel whose ray meets nothing holds kDepthEmpty in both enter and exit.
//
// Texel (x, y) covers NDC [x/res*2-1, (x+1)/res*2-1] horizontally, row y = 0 at NDC y = -1; its
// sample point is the centre. Rasterisation uses a top-left rule on fixed-point edge functions
// (raster_dual.h): with a plain ">= 0" rule a centre on an edge shared by two front faces would be
// entered twice and left once, and its exit would run to far (StaticRaster.SharedEdgesCountedOnce).
#pragma once
#include "io/result.h"
#include "shadows/static/static_types.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace ml {

constexpr uint32_t kDepthEmpty = 0xFFFFFFFFu;
// Directional (orthographic) maps take each triangle's depth from its plane in fixed point, slopes in
// 1/64 units a texel (raster_dual.h step 4), so that DAG-MH's value planes reproduce it exactly
// (dagmh.h). 6 bits keep the plane within 2^-7 x 2^19 = 4096 units (1e-6 of the depth range) of the
// triangle at 262,144^2, and a slope within 64 / span steps of a least-squares fit over a span of texels.
constexpr uint32_t kOrthoSlopeFractionBits = 6;

// Linear distance z in [0, far] -> [0, 0xFFFFFFFE]; values past far clamp. kDepthEmpty stays free.
inline uint32_t quantizeDepth(float z, float farPlane) {
    double t = double(z) / double(farPlane);
    if (!(t > 0.0)) return 0u;
    if (t >= 1.0) return 0xFFFFFFFEu;
    return uint32_t(t * 4294967294.0);
}
inline float dequantizeDepth(uint32_t d, float farPlane) {
    return float(double(d) / 4294967294.0 * farPlane);
}

// A directional map's depth plane (raster_dual.h step 4): quantised depth at texel (x, y) = a + ((dx x +
// dy y + 32) >> 6) in int64. Plane ids are 1-based indices into a table of them; 0 names no plane.
// The slope part of such a plane at texel (x, y), rounded: (dx x + dy y + 32) >> 6. The one expression
// the rasteriser (DualRasterizer::Tri::depth), the table (DepthPlane::at) and DAG-MH's value encoder
// (dagmh_values.cpp) evaluate, so a plane value equals the rasterised depth bit for bit. |dx|, |dy| <
// 2^31 and x, y < 2^18 keep it within int64.
inline int64_t depthPlaneSlopeAt(int64_t dx, int64_t dy, int64_t x, int64_t y) {
    return (dx * x + dy * y + (int64_t(1) << (kOrthoSlopeFractionBits - 1))) >> kOrthoSlopeFractionBits;
}

struct DepthPlane {
    int64_t a = 0;
    int32_t dx = 0, dy = 0;
    bool operator==(const DepthPlane&) const = default;
    int64_t at(int64_t x, int64_t y) const { return a + depthPlaneSlopeAt(dx, dy, x, y); }
};

struct DualDepthMap {
    uint32_t resolution = 0; // width = height (the container every codec stores)
    // Rows in the light's volume (LightFrustum::mapRows): a directional map fitted to its box is
    // resolution x rows texels, the rows from `rows` on are outside the light (empty). 0 = resolution.
    // SM stores only these rows; the hierarchical codecs store the empty rest as homogeneous nodes.
    uint32_t rows = 0;
    // Rendered through an orthographic (directional) frustum: CPVS slices its depth linearly (cpvs.h).
    bool orthographic = false;
    std::vector<uint32_t> enter; // resolution * resolution, row-major, row 0 at NDC y = -1
    std::vector<uint32_t> exit;
    // Optional (orthographic maps from the CPU rasteriser; empty otherwise): per texel the id of the plane
    // its enter depth lies on (0: none), and the planes. DAG-MH evaluates such planes per texel (dagmh.h).
    std::vector<uint32_t> enterPlane;
    std::vector<DepthPlane> planes;
    uint32_t at(uint32_t x, uint32_t y) const { return enter[size_t(y) * resolution + x]; }
};

} // namespace ml
