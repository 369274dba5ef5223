#include "bake/reference/error_classes.h"

#include "shadows/static/static_visibility.h"

#include <cmath>

namespace ml {

const char* errorClassName(ErrorClass c) {
    switch (c) {
    case ErrorClass::Inside:
        return "inside";
    case ErrorClass::Contact:
        return "contact";
    case ErrorClass::Resolution:
        return "resolution";
    case ErrorClass::ThinOpen:
        return "thin-open";
    default:
        return "other";
    }
}

ErrorClass classifyDisagreement(const ErrorContext& ctx, glm::vec3 p, glm::vec3 n) {
    const RayReference& rays = *ctx.rays;
    glm::vec3 nl = glm::dot(n, ctx.lightPos - p) < 0.0f ? -n : n; // the rays' rule: towards the light
    glm::vec3 origin = p + nl * ctx.rayBias;
    glm::vec3 toLight = ctx.lightPos - origin;
    float dist = glm::length(toLight);
    if (!(dist > ctx.rayBias)) return ErrorClass::Other;
    glm::vec3 dir = toLight / dist;
    RayHit first = rays.firstHit(origin, dir, 0.0f, dist - ctx.rayBias);
    if (first.hit && first.closed && glm::dot(first.ng, dir) > 0.0f) return ErrorClass::Inside;

    // The texel footprint at the receiver's light-space depth.
    const gpu::GpuShadowRecord& rec = ctx.record;
    glm::vec3 vp = gpu::shadowViewPoint(rec, p);
    float z = -vp.z;
    float texel = (rec.frustum.x < 0.0f ? -2.0f * rec.frustum.x : 2.0f * z * rec.frustum.x) /
                  float(gpu::shadowRecordResolution(rec));
    float band = 1.5f * texel + ctx.rayBias;
    glm::vec3 start = p + nl * 1e-4f;
    glm::vec3 toLight2 = ctx.lightPos - start;
    float dist2 = glm::length(toLight2);
    if (dist2 > 0.0f) {
        RayHit near = rays.firstHit(start, toLight2 / dist2, 0.0f, std::min(band, dist2));
        if (near.hit) return ErrorClass::Contact;
    }

    gpu::GpuShadowRecord one = rec;
    one.info.x = gpu::shadowRecordWithRadius(rec.info.x, 0);
    // The view's x and y axes in the world: the inverse rotation (the conjugate quaternion) of each.
    const glm::vec4 inverse(-rec.rotation.x, -rec.rotation.y, -rec.rotation.z, rec.rotation.w);
    const glm::vec3 right = gpu::quatRotate(inverse, glm::vec3(1, 0, 0));
    const glm::vec3 up = gpu::quatRotate(inverse, glm::vec3(0, 1, 0));
    const bool centre = staticVisibility(one, ctx.words, p, n) >= 0.5f;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            if (!dx && !dy) continue;
            glm::vec3 q = p + (right * float(dx) + up * float(dy)) * texel;
            if ((staticVisibility(one, ctx.words, q, n) >= 0.5f) != centre) return ErrorClass::Resolution;
        }
    if (first.hit && !first.closed) return ErrorClass::ThinOpen;
    return ErrorClass::Other;
}

} // namespace ml
