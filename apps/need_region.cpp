#include "apps/need_region.h"

#include "scenes/camera_path.h"
#include "scenes/scenes.h"
#include "bake/reference/raytrace.h"
#include "bake/bake.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace ml {

Result<NeedRegion> makeNeedRegion(const Scene& scene, const std::string& spec, uint32_t samples,
                                  double seconds, uint32_t width, uint32_t height) {
    if (samples == 0) return fail("--need: no camera sample");
    NeedRegion r;
    char buf[160];
    const float aspect = float(width) / float(height);
    if (spec.rfind("path:", 0) == 0) {
        auto path = parseCameraPath(spec.substr(5));
        if (!path) return fail("--need: " + path.error());
        if (!(seconds > 0.0)) return fail("--need: path duration must be > 0 seconds");
        Scene moving = scene; // cars move; the drive camera follows one
        for (uint32_t i = 0; i < samples; ++i) {
            const double t = seconds * double(i) / double(samples);
            animateScene(moving, t);
            auto cam = cameraOnPath(moving, path.value(), t);
            if (!cam) return fail("--need: " + cam.error());
            NeedCamera c;
            c.position = cam->position;
            const glm::vec3 d = cam->target - cam->position;
            if (!(glm::length(d) > 0.0f))
                return fail("--need: the path's camera looks nowhere at " + std::to_string(t) + " s");
            c.forward = glm::normalize(d);
            c.fovY = cam->fovY, c.aspect = aspect, c.nearPlane = cam->nearPlane, c.farPlane = cam->farPlane;
            r.cameras.push_back(c);
            r.views.push_back(cam.value());
        }
        std::snprintf(buf, sizeof buf, "%s, %u samples over %g s", spec.c_str(), samples, seconds);
        r.text = buf;
        return r;
    }
    if (spec.rfind("box:", 0) == 0) {
        float v[6];
        std::string rest = spec.substr(4);
        size_t pos = 0;
        for (int i = 0; i < 6; ++i) {
            size_t comma = rest.find(',', pos);
            if ((i < 5) != (comma != std::string::npos))
                return fail("--need: box needs six numbers X0,Y0,Z0,X1,Y1,Z1, got '" + rest + "'");
            std::string num = rest.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
            char* end = nullptr;
            v[i] = std::strtof(num.c_str(), &end);
            if (num.empty() || *end != '\0' || !std::isfinite(v[i]))
                return fail("--need: box coordinate '" + num + "' is not a finite number");
            pos = comma + 1;
        }
        const glm::vec3 lo(v[0], v[1], v[2]), hi(v[3], v[4], v[5]);
        if (!(hi.x >= lo.x && hi.y >= lo.y && hi.z >= lo.z)) return fail("--need: box max below min");
        const uint32_t k = std::max(1u, uint32_t(std::lround(std::cbrt(double(samples)))));
        r.cameras = boxCameras(lo, hi, k, scene.camera.fovY, scene.camera.nearPlane, scene.camera.farPlane);
        for (NeedCamera& c : r.cameras) c.aspect = aspect;
        std::snprintf(buf, sizeof buf, "%s, %u^3 positions", spec.c_str(), k);
        r.text = buf;
        return r;
    }
    return fail("--need: '" + spec + "' is not path:static|drive|orbit or box:X0,Y0,Z0,X1,Y1,Z1");
}

Result<std::vector<LightNeed>> estimateNeedWithRays(const Scene& scene, const std::vector<uint32_t>& lights,
                                                    const NeedRegion& region, const NeedOptions& options) {
    auto rays = RayReference::build(scene, true);
    if (!rays) return fail(rays.error());
    NeedOptions o = options;
    const RayReference* rr = &rays.value();
    // A receiver (already 1 cm off its surface) sees the camera when nothing blocks the segment.
    o.visible = [rr](const glm::vec3& camera, const glm::vec3& receiver) {
        return rr->visible(receiver, camera, 0.001f);
    };
    std::vector<uint32_t> bakeable;
    for (uint32_t l : lights)
        if (l < scene.lights.size() && bakeSkipReason(scene, scene.lights[l]).empty()) bakeable.push_back(l);
    return estimateNeed(scene, bakeable, region.cameras, o);
}

} // namespace ml
