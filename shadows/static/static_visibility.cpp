#include "shadows/static/static_visibility.h"

#include "shaders/shared/light_math.h"
#include "shaders/shared/shadow_record.h"
#include "shadows/static/static_method.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace ml {

gpu::GpuShadowRecord makeShadowRecord(StaticMethod method, const LightFrustum& f, uint32_t base,
                                      uint32_t resolution, uint32_t pcfRadius) {
    gpu::GpuShadowRecord r{};
    // The lookAt view as a unit quaternion and a translation (GpuShadowRecord; setStaticShadow refuses
    // views that are not rigid). quat_cast takes the largest of w, x, y, z first, so it is well
    // conditioned for every rotation.
    const glm::quat q = glm::normalize(glm::quat_cast(glm::mat3(f.view)));
    r.rotation = glm::vec4(q.x, q.y, q.z, q.w);
    r.translation = glm::vec4(glm::vec3(f.view[3]), 0.0f);
    // x: tan(fov / 2) for perspective maps, -orthoHalf for orthographic ones (the sign tells them apart).
    // w: CPVS's depth-slice scale for the voxel normal: far - near for orthographic maps (linear slices),
    // log(far / near) for perspective ones (eq. 1).
    r.frustum = glm::vec4(f.orthographic() ? -f.orthoHalf : std::tan(f.fov * 0.5f), f.nearPlane, f.farPlane,
                          f.orthographic() ? f.farPlane - f.nearPlane : std::log(f.farPlane / f.nearPlane));
    static_assert(uint32_t(StaticMethod::CPVS) < 16 && ML_MAX_PCF_RADIUS < 16,
                  "GpuShadowRecord.info.x's fields");
    r.info = glm::uvec4(
        gpu::shadowRecordInfo(uint32_t(method), std::min<uint32_t>(pcfRadius, ML_MAX_PCF_RADIUS), resolution),
        base, 0u, 0u);
    r.bias = glm::vec4(kDefaultShadowDepthBias, kDefaultShadowNormalBias, 0.0f, 0.0f);
    return r;
}

bool rigidView(const glm::mat4& view, float tolerance) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(view[c][r])) return false;
    if (view[0][3] != 0.0f || view[1][3] != 0.0f || view[2][3] != 0.0f || view[3][3] != 1.0f) return false;
    const glm::mat3 R(view);
    const glm::mat3 I = glm::transpose(R) * R;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!(std::abs(I[c][r] - (c == r ? 1.0f : 0.0f)) <= tolerance)) return false;
    return glm::determinant(R) > 0.0f;
}

// The shader's text (shaders/static/static_pcf.h) compiled as C++: the decoders of mh.h, mmh.h, dagmh.h
// and cpvs.h take the buffer as their first argument, and GLSL's vector types and built-ins are glm's
// or written out below with the same results on the values the text passes them.
namespace svtwin {
using namespace gpu;
using namespace mhtwin;
using namespace dagtwin;
using namespace cpvstwin;
using uint = uint32_t;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using ivec2 = glm::ivec2;
using ivec3 = glm::ivec3;
using glm::floor;
inline float clamp(float v, float lo, float hi) {
    return std::clamp(v, lo, hi);
}
inline float max(float a, float b) {
    return std::max(a, b);
}
inline uint min(uint a, uint b) {
    return std::min(a, b);
}
inline ivec2 max(ivec2 a, ivec2 b) {
    return glm::max(a, b);
}
inline ivec2 min(ivec2 a, ivec2 b) {
    return glm::min(a, b);
}
inline ivec3 cpvsVoxelNormal(vec3 nView, float ndcX, float ndcY, float tanHalfFov, float depthScale) {
    const float n[3] = {nView.x, nView.y, nView.z};
    int32_t q[3];
    ml::cpvsVoxelNormal(n, ndcX, ndcY, tanHalfFov, depthScale, q);
    return ivec3(q[0], q[1], q[2]);
}
// GLSL's `out`/`inout` parameters are references here.
#define ML_SV_FN inline
#define ML_SV_DATA_PARAM const uint32_t *data,
#define ML_SV_DATA_ARG data,
#define ML_SV_WORD(i) data[i]
#define ML_SV_INOUT(T) T&
#include "shaders/static/static_pcf.h"
// The text reads the SM header words by index and the levels L at the same word for MH, MMH and DAG-MH.
static_assert(smfmt::kVersion == 1 && smfmt::kResolution == 2 && smfmt::kRows == 5 &&
                  smfmt::kHeaderWords == 6 && kDepthEmpty == 0xFFFFFFFFu,
              "staticDepthAt's SM words and empty texel");
static_assert(ML_MH_LEVELS == mhfmt::kLevels && uint32_t(mhfmt::kLevels) == uint32_t(dagfmt::kLevels),
              "the levels L are the same header word in MH, MMH, DAG-MH");
} // namespace svtwin

uint32_t staticQuantizeFloat(float z, float farPlane) {
    return svtwin::staticQuantize(z, farPlane);
}

uint32_t dagmhBoundsDecision(const gpu::GpuShadowRecord& rec, const uint32_t* data, glm::vec3 P,
                             glm::vec3 N) {
    if (StaticMethod(gpu::shadowRecordMethod(rec)) != StaticMethod::DAGMH) return 3;
    glm::vec3 vp = gpu::shadowViewPoint(rec, P);
    glm::vec3 vn = gpu::shadowViewVector(rec, N);
    if (-vp.z <= rec.frustum.y) return 3;
    const svtwin::StaticDepthTap tap = svtwin::staticDepthTap(data, rec, vp, vn, 0.0f);
    if (tap.lit) return 3;
    const int radius = int(gpu::shadowRecordRadius(rec)), res = int(gpu::shadowRecordResolution(rec));
    const glm::ivec2 lo = glm::max(tap.t - radius, glm::ivec2(0));
    const glm::ivec2 hi = glm::min(tap.t + radius, glm::ivec2(res - 1));
    if (lo.x > hi.x || lo.y > hi.y) return 3; // every tap outside the map
    return dagmhBoundsClass(data, dagmhHeader(data, rec.info.y), uint32_t(lo.x), uint32_t(lo.y),
                            uint32_t(hi.x), uint32_t(hi.y), tap.depth);
}

float staticVisibility(const gpu::GpuShadowRecord& rec, const uint32_t* data, glm::vec3 P, glm::vec3 N,
                       float footprint2) {
    return svtwin::staticVisibility(data, rec, P, N, footprint2);
}

float lightStaticVisibility(const gpu::GpuLight& L, const gpu::GpuShadowRecord* records, const uint32_t* data,
                            glm::vec3 P, glm::vec3 N, float footprint2) {
    if (L.info.z == ML_NO_SHADOW) return 1.0f;
    uint32_t r = L.info.z;
    if (L.info.x == ML_LIGHT_POINT) r += gpu::pointLightFace(P - glm::vec3(L.positionRange));
    if (gpu::shadowRecordMethod(records[r]) == 0u) return 1.0f;
    return staticVisibility(records[r], data, P, N, footprint2);
}

} // namespace ml
