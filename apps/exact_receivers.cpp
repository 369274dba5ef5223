#include "apps/exact_receivers.h"

#include <algorithm>

namespace ml {

glm::dvec3 pixelRayDirection(const glm::dmat4& inv, uint32_t x, uint32_t y, uint32_t width, uint32_t height,
                             PixelConvention convention) {
    const bool gbuffer = convention == PixelConvention::GBuffer;
    const double nx = (x + 0.5) / width * 2.0 - 1.0;
    const double ny = gbuffer ? (y + 0.5) / height * 2.0 - 1.0 : 1.0 - (y + 0.5) / height * 2.0;
    const double nearZ = gbuffer ? 1.0 : 0.0, farZ = gbuffer ? 0.0 : 1.0;
    const glm::dvec4 a = inv * glm::dvec4(nx, ny, nearZ, 1.0), b = inv * glm::dvec4(nx, ny, farZ, 1.0);
    return glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w);
}

SurfaceHit traceSurface(const RayReference& rays, const glm::dvec3& eye, const glm::dvec3& dir,
                        float farDistance) {
    const RayHit h = rays.firstHit(glm::vec3(eye), glm::vec3(dir), 0.0f, farDistance);
    if (!h.hit) return {};
    SurfaceHit s;
    s.hit = true;
    s.p = glm::vec3(eye + dir * double(h.t));
    const glm::vec3 n = glm::normalize(h.ng);
    s.n = glm::dot(n, glm::vec3(dir)) > 0.0f ? -n : n;
    return s;
}

std::vector<std::pair<size_t, uint32_t>> rankStaticSpots(const Scene& scene,
                                                         const std::function<size_t(const Light&)>& reach) {
    std::vector<std::pair<size_t, uint32_t>> ranked;
    for (uint32_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        if (l.dynamic || l.type != LightKind::Spot) continue;
        if (const size_t n = reach(l)) ranked.push_back({n, i});
    }
    std::sort(ranked.rbegin(), ranked.rend());
    return ranked;
}

std::vector<uint32_t> firstLights(const std::vector<std::pair<size_t, uint32_t>>& ranked, uint32_t count) {
    std::vector<uint32_t> lights;
    for (size_t k = 0; k < ranked.size() && k < count; ++k) lights.push_back(ranked[k].second);
    return lights;
}

} // namespace ml
