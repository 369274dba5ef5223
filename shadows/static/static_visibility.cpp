#include "shadows/static/static_visibility.h"

#include "shaders/shared/light_math.h"
#include "shaders/shared/shadow_record.h"
#include "shadows/static/mh.h"
#include "shadows/static/mmh.h"

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

uint32_t staticQuantizeFloat(float z, float farPlane) {
    float t = std::clamp(z / farPlane, 0.0f, 1.0f);
    return t >= 1.0f ? 0xFFFFFFFEu : uint32_t(t * 4294967040.0f);
}

namespace {

// The depth methods' mapping (SM, MH, MMH, DAG-MH): the receiver at view position vp with view normal vn,
// offset along the normal, to its centre tap t and quantised, biased depth; false when the offset
// receiver lies before the near plane (lit). With filtering by level (MH, MMH, DAG-MH), step is the level
// above the finest (shadowLevelStep: its texel at most a quarter of the pixel, footprint2), and t a texel
// of that level. The shader's lines, in its order.
static_assert(uint32_t(mhfmt::kLevels) == uint32_t(dagfmt::kLevels),
              "the levels L are the same header word in MH, MMH, DAG-MH");
bool depthMapTap(const gpu::GpuShadowRecord& rec, const uint32_t* data, glm::vec3 vp, glm::vec3 vn,
                 float footprint2, glm::ivec2& t, uint32_t& depth, uint32_t& step) {
    const StaticMethod method = StaticMethod(gpu::shadowRecordMethod(rec));
    const uint32_t res = gpu::shadowRecordResolution(rec);
    const int radius = int(gpu::shadowRecordRadius(rec));
    const float tanHalf = rec.frustum.x, farPlane = rec.frustum.z;
    const bool ortho = tanHalf < 0.0f;
    const float orthoHalf = -tanHalf;
    const float z = -vp.z;
    float texelWorld = ortho ? 2.0f * orthoHalf / float(res) : 2.0f * z * tanHalf / float(res);
    step = 0;
    if (gpu::shadowRecordByLevel(rec) &&
        (method == StaticMethod::MH || method == StaticMethod::MMH || method == StaticMethod::DAGMH))
        step = gpu::shadowLevelStep(texelWorld, footprint2, data[rec.info.y + mhfmt::kLevels]);
    texelWorld = texelWorld * float(1u << step);
    // Normal offset of (1 + radius) texels, as the shader (its comment says why).
    glm::vec3 q = vp + vn * (texelWorld * float(1 + radius) * rec.bias.y);
    float zq = -q.z;
    if (zq <= rec.frustum.y) return false;
    glm::vec2 ndc = ortho ? glm::vec2(q) / orthoHalf : glm::vec2(q) / (zq * tanHalf);
    t = glm::ivec2(glm::floor((ndc * 0.5f + 0.5f) * float(res))) >> int(step);
    depth = staticQuantizeFloat(std::max(zq - rec.bias.x * texelWorld, 0.0f), farPlane);
    return true;
}

} // namespace

uint32_t dagmhBoundsDecision(const gpu::GpuShadowRecord& rec, const uint32_t* data, glm::vec3 P,
                             glm::vec3 N) {
    if (StaticMethod(gpu::shadowRecordMethod(rec)) != StaticMethod::DAGMH) return 3;
    glm::vec3 vp = gpu::shadowViewPoint(rec, P);
    glm::vec3 vn = gpu::shadowViewVector(rec, N);
    if (-vp.z <= rec.frustum.y) return 3;
    glm::ivec2 t;
    uint32_t depth, step;
    if (!depthMapTap(rec, data, vp, vn, 0.0f, t, depth, step)) return 3;
    const int radius = int(gpu::shadowRecordRadius(rec)), res = int(gpu::shadowRecordResolution(rec));
    const glm::ivec2 lo = glm::max(t - radius, glm::ivec2(0)), hi = glm::min(t + radius, glm::ivec2(res - 1));
    if (lo.x > hi.x || lo.y > hi.y) return 3; // every tap outside the map
    return dagmhBoundsClass(data, dagmhHeader(data, rec.info.y), uint32_t(lo.x), uint32_t(lo.y),
                            uint32_t(hi.x), uint32_t(hi.y), depth);
}

float staticVisibility(const gpu::GpuShadowRecord& rec, const uint32_t* data, glm::vec3 P, glm::vec3 N,
                       float footprint2) {
    const StaticMethod method = StaticMethod(gpu::shadowRecordMethod(rec));
    const uint32_t base = rec.info.y, res = gpu::shadowRecordResolution(rec);
    const int radius = int(gpu::shadowRecordRadius(rec));
    const float tanHalf = rec.frustum.x, farPlane = rec.frustum.z;
    const bool ortho = tanHalf < 0.0f;
    const float orthoHalf = -tanHalf;
    glm::vec3 vp = gpu::shadowViewPoint(rec, P);
    glm::vec3 vn = gpu::shadowViewVector(rec, N);
    float z = -vp.z;
    if (z <= rec.frustum.y) return 1.0f;
    const float taps = float((2 * radius + 1) * (2 * radius + 1));
    if (method == StaticMethod::CPVS) {
        glm::vec2 ndc = ortho ? glm::vec2(vp) / orthoHalf : glm::vec2(vp) / (z * tanHalf);
        glm::ivec2 t = glm::ivec2(glm::floor((ndc * 0.5f + 0.5f) * float(res)));
        uint32_t s = cpvsSliceOfDepth(data, base, staticQuantizeFloat(z, farPlane));
        float nView[3] = {vn.x, vn.y, vn.z};
        int32_t nq[3];
        // Orthographic, linear slices: du = N dx / (2 h), dw = N dz / (far - near): the perspective
        // formula with ndc = 0, tan = h and frustum.w = far - near (cpvs.h).
        if (ortho)
            cpvsVoxelNormal(nView, 0.0f, 0.0f, orthoHalf, rec.frustum.w, nq);
        else
            cpvsVoxelNormal(nView, ndc.x, ndc.y, tanHalf, rec.frustum.w, nq);
        uint32_t step = 0;
        if (gpu::shadowRecordByLevel(rec)) {
            float texelWorld = ortho ? 2.0f * orthoHalf / float(res) : 2.0f * z * tanHalf / float(res);
            step = gpu::shadowLevelStep(texelWorld, footprint2, data[base + kCpvsHLog2Resolution]);
        }
        return float(cpvsPcfLitLevel(data, base, t.x, t.y, int32_t(s), nq[0], nq[1], nq[2], radius, step)) /
               taps;
    }
    glm::ivec2 t;
    uint32_t depth, step;
    if (!depthMapTap(rec, data, vp, vn, footprint2, t, depth, step)) return 1.0f;
    // Hierarchical PCF for DAG-MH: the taps share the traversal down to the node that holds them all.
    glm::ivec2 lo = glm::clamp(t - radius, glm::ivec2(0), glm::ivec2(int(res) - 1));
    glm::ivec2 hi = glm::clamp(t + radius, glm::ivec2(0), glm::ivec2(int(res) - 1));
    bool usePrefix = false;
    DagmhState prefix{};
    const DagmhHeader dh = method == StaticMethod::DAGMH ? dagmhHeader(data, base) : DagmhHeader{};
    if (method == StaticMethod::DAGMH && radius > 0 && step == 0) {
        prefix = dagmhPcfPrefix(data, dh, uint32_t(lo.x), uint32_t(lo.y), uint32_t(hi.x), uint32_t(hi.y));
        usePrefix = prefix.kind != kDagNoPrefix;
    }
    // DAG-MH taps in the node of the previous tap's value reuse its decoded value (the shader, in
    // dagmhPcfLit, also shares a prefix treelet's words and a chunk's words between taps: same values).
    uint32_t memoIndex = 0xFFFFFFFFu, memoDepth = 0u;
    uint32_t lit = 0;
    // With filtering by level (step > 0: MH, MMH, DAG-MH), the taps are texels of that level's map.
    const int levelRes = int((res + (1u << step) - 1u) >> step);
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            int x = t.x + dx, y = t.y + dy;
            if (x < 0 || y < 0 || x >= levelRes || y >= levelRes) {
                ++lit;
                continue;
            }
            uint32_t d;
            if (step > 0) {
                const uint32_t steps = data[base + mhfmt::kLevels] - step;
                d = method == StaticMethod::MH ? mhLookupLevel(data, base, uint32_t(x), uint32_t(y), steps)
                    : method == StaticMethod::MMH
                        ? mmhLookupLevel(data, base, uint32_t(x), uint32_t(y), steps)
                        : dagmhLookupLevel(data, base, uint32_t(x), uint32_t(y), steps);
            } else if (method == StaticMethod::DAGMH) {
                const uint32_t ux = uint32_t(x), uy = uint32_t(y);
                DagmhState st =
                    dagmhLocate(data, dh, ux, uy, usePrefix ? prefix : dagmhStart(data, dh, ux, uy));
                if (st.vlast != memoIndex) {
                    memoIndex = st.vlast;
                    memoDepth = dagmhLocatedValue(data, dh, ux, uy, st);
                }
                d = memoDepth;
            } else {
                d = lookupStaticDepth(method, data, base, uint32_t(x), uint32_t(y));
            }
            if (depth <= d) ++lit;
        }
    return float(lit) / taps;
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
