#include "lights/lights.h"

#include "manylights/vsm_settings.h"

#include <cmath>
#include <string>
#include <utility>

namespace ml {

namespace {
bool finite3(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
} // namespace

Result<void> validateLight(const LightDesc& desc) {
    const GlmLight l(desc);
    if (uint32_t(l.kind) > uint32_t(LightKind::Directional))
        return fail("light kind is not spot, point or directional");
    if (!finite3(l.position)) return fail("light position is not finite");
    if (!finite3(l.direction)) return fail("light direction is not finite");
    if (!finite3(l.color)) return fail("light colour is not finite");
    if (l.color.x < 0 || l.color.y < 0 || l.color.z < 0) return fail("light colour is negative");
    if (!std::isfinite(l.intensity) || l.intensity < 0)
        return fail("light intensity is negative or not finite");
    if (l.kind != LightKind::Directional) {
        if (!std::isfinite(l.range) || l.range <= 0) return fail("light range must be finite and > 0");
    }
    if (l.kind != LightKind::Point) {
        float len = glm::length(l.direction);
        if (!(len > 1e-6f)) return fail("light direction has zero length");
    }
    if (uint32_t(l.unit) > uint32_t(LightUnit::Lumen)) return fail("light unit is not candela or lumen");
    if (l.unit == LightUnit::Lumen && l.kind == LightKind::Directional)
        return fail(
            "light unit: a directional light's intensity is illuminance in lux (unit candela), not lumen");
    for (auto [value, name] :
         {std::pair{l.shadowDepthBias, "shadowDepthBias"}, std::pair{l.shadowNormalBias, "shadowNormalBias"}})
        if (!std::isfinite(value) || value < 0 || value > kMaxShadowBias)
            return fail(std::string("light ") + name + " " + std::to_string(value) + " is not in [0, " +
                        std::to_string(int(kMaxShadowBias)) + "] texels");
    if (l.shadowResolution != 0 && (l.shadowResolution < 8 || l.shadowResolution > 16384))
        return fail("light shadowResolution " + std::to_string(l.shadowResolution) +
                    " is not 0 (the bake's) or in 8..16384");
    if (!validTexelsPerPixel(l.shadowTexelScale))
        return fail("light shadowTexelScale " + std::to_string(l.shadowTexelScale) +
                    " is not a power of two in 1/4..8");
    if (l.kind == LightKind::Spot) {
        if (!std::isfinite(l.outerAngle) || l.outerAngle <= 0 || l.outerAngle >= 1.5707963f)
            return fail("spot outer half angle must be in (0, pi/2) radians");
        if (!std::isfinite(l.innerAngle) || l.innerAngle < 0 || l.innerAngle > l.outerAngle)
            return fail("spot inner half angle must be in [0, outer]");
    }
    return {};
}

gpu::GpuLight toGpuLight(const LightDesc& desc, uint32_t id) {
    const GlmLight l(desc);
    gpu::GpuLight g{};
    glm::vec3 dir = l.kind == LightKind::Point ? glm::vec3(0, -1, 0) : glm::normalize(l.direction);
    float outer = l.kind == LightKind::Spot ? l.outerAngle : 3.14159265f;
    float inner = l.kind == LightKind::Spot ? l.innerAngle : 3.14159265f;
    g.positionRange = glm::vec4(l.position, l.range);
    g.directionCosOuter = glm::vec4(dir, std::cos(outer));
    g.colorSinOuter = glm::vec4(l.color * lightIntensityCandela(l), std::sin(outer));
    g.params = glm::vec4(std::cos(inner), 1.0f / (l.range * l.range), 0, 0);
    g.info = glm::uvec4(uint32_t(l.kind), ML_VSM_NO_MAP, ML_NO_SHADOW, id);
    return g;
}

float lightIntensityCandela(const LightDesc& l) {
    if (l.unit != LightUnit::Lumen) return l.intensity; // candela (lux for a directional light): as given
    const float pi = 3.14159265f;
    return l.kind == LightKind::Point ? l.intensity / (4.0f * pi) : l.intensity / pi;
}

float exposureFromEV100(float ev100) {
    return 1.0f / (1.2f * std::exp2(ev100));
}

float ev100FromCamera(float aperture, float shutterSeconds, float iso) {
    return std::log2(aperture * aperture / shutterSeconds * 100.0f / iso);
}

glm::vec4 lightBoundingSphere(const LightDesc& desc) {
    const GlmLight l(desc);
    if (l.kind == LightKind::Point) return glm::vec4(l.position, l.range);
    glm::vec3 dir = glm::normalize(l.direction);
    float a = l.outerAngle;
    if (a > 0.78539816f) return glm::vec4(l.position, l.range); // wide cone: the range sphere is smaller
    // Sphere through the apex and the cap's rim: radius r / (2 cos a), centre along the axis.
    float radius = l.range / (2.0f * std::cos(a));
    return glm::vec4(l.position + dir * radius, radius);
}

std::array<glm::vec4, 6> frustumPlanes(const glm::mat4& vp) {
    glm::mat4 m = glm::transpose(vp);
    std::array<glm::vec4, 6> p = {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[2], m[3] - m[2]};
    for (auto& plane : p) plane /= glm::length(glm::vec3(plane));
    return p;
}

bool sphereInFrustum(const std::array<glm::vec4, 6>& planes, glm::vec4 s) {
    for (const auto& p : planes)
        if (glm::dot(glm::vec3(p), glm::vec3(s)) + p.w < -s.w) return false;
    return true;
}

} // namespace ml
