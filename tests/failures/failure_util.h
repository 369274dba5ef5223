// The failure suite's harness: a small scene is handed to the module through its public API
// (host/scene_host.h bindScene, Module::setStaticShadow), each static light is baked on the CPU
// (rasterizeDual + encodeStatic, the same dual maps the Vulkan baker renders), one frame is rendered at
// 160x90 and read back, and the outcome is measured:
//   - the HDR image (RGBA16F, before tone mapping) must hold no NaN or Inf in any pixel;
//   - per baked light, the receivers the G-buffer sees in the light's cone and facing it are compared
//     with Embree rays (bake/reference/raytrace.h, bias 0.02 m along the normal as in bench static,
//     less in centimetre-scale cases):
//     the method's visibility is the CPU twin of the shader's lookup (static_visibility.h), which
//     tests/gpu proves equal to the GPU's value.
// With ML_FAILURE_IMAGES=<dir> in the environment each case writes <dir>/<case>.png (the tone-mapped
// output): `ML_FAILURE_IMAGES=docs/failures build/failure_tests` regenerates docs/failures/.
#pragma once
#include "tests/gpu/gpu_test_util.h"
#include "bake/scene_casters.h"

#include "scenes/mesh_utils.h"
#include "shaders/shared/light_math.h"
#include "shaders/shared/shading.h"
#include "bake/reference/raytrace.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>

namespace ml::test {

// ---- scene building: everything in metres, static unless said otherwise ----

// Closed box [lo, hi] (unit box scaled; scaling keeps it watertight). `closed` is what the host
// declares, which need not be the truth (the open-geometry-marked-closed case lies on purpose).
inline void addBox(Scene& s, glm::vec3 lo, glm::vec3 hi, glm::vec3 albedo = glm::vec3(0.6f)) {
    s.meshes.push_back(detail::makeUnitBox());
    glm::mat4 t =
        glm::translate(glm::mat4(1.0f), glm::vec3((lo.x + hi.x) * 0.5f, lo.y, (lo.z + hi.z) * 0.5f)) *
        glm::scale(glm::mat4(1.0f), hi - lo);
    s.instances.push_back({uint32_t(s.meshes.size() - 1), t, albedo, false});
}

// Horizontal open quad over [x0, x1] x [z0, z1] at height y, front face up.
inline void addQuad(Scene& s, float x0, float x1, float z0, float z1, float y, bool markClosed = false,
                    glm::vec3 albedo = glm::vec3(0.7f)) {
    Mesh q = detail::makeUnitQuad();
    q.closed = markClosed;
    s.meshes.push_back(q);
    glm::mat4 t = glm::translate(glm::mat4(1.0f), glm::vec3((x0 + x1) * 0.5f, y, z0)) *
                  glm::scale(glm::mat4(1.0f), glm::vec3(x1 - x0, 1.0f, z1 - z0));
    s.instances.push_back({uint32_t(s.meshes.size() - 1), t, albedo, false});
}

inline Scene groundScene(const char* name, float half = 40.0f) {
    Scene s;
    s.name = name;
    addQuad(s, -half, half, -half, half, 0.0f);
    return s;
}

inline Light spotAt(glm::vec3 position, glm::vec3 target, float range, float outer = 0.6f,
                    float intensity = 4.0f) {
    Light l;
    l.type = LightKind::Spot;
    l.position = position;
    l.direction = glm::normalize(target - position);
    l.range = range;
    l.outerAngle = outer;
    l.innerAngle = outer * 0.7f;
    l.intensity = intensity;
    l.color = glm::vec3(1.0f, 0.9f, 0.75f);
    return l;
}

inline CameraDesc lookFrom(glm::vec3 position, glm::vec3 target, float nearPlane = 0.1f,
                           float farPlane = 500.0f) {
    CameraDesc c;
    c.position = position;
    c.target = target;
    c.nearPlane = nearPlane;
    c.farPlane = farPlane;
    return c;
}

// ---- running a case ----

struct RunOptions {
    StaticMethod method = StaticMethod::DAGMH;
    uint32_t resolution = 256; // static map side (the suite stays <= 256)
    uint32_t pcf = 0;
    uint32_t width = 160, height = 90;
    float lightNear = 0.05f;    // bake frustum near plane
    float nearOverRange = 0.0f; // > 0: bake near = range * this instead (near/far ratio cases)
    uint32_t measureLights = 8; // baked lights compared with the rays (the first ones)
    float rayBias = 0.001f;     // the rays' normal offset: 1 mm, as bench static (docs/accuracy.md section 1)
};

struct Receiver {
    glm::vec3 p, n;
};

struct Outcome {
    uint32_t baked = 0;
    std::vector<std::string> bakeErrors; // per light that could not be baked or attached
    uint64_t surfacePixels = 0, nonFinite = 0;
    float maxHdr = 0;
    Disagreement vsRays; // pooled over the measured lights
    std::vector<Disagreement> perLight;
    FrameStats stats;
    std::vector<uint8_t> rgba;       // tone-mapped output, for the PNG
    std::vector<Receiver> receivers; // G-buffer positions and normals
    std::vector<LightFrustum> frustums;
    std::vector<std::vector<uint32_t>> words; // per baked light (shared bakes are copied)
    std::unique_ptr<Module> module;           // after the frame, for cases that inspect more
};

inline std::string bakeFailure(const std::vector<std::string>& errors) {
    return errors.empty() ? std::string() : errors.front();
}

// Receivers of light `l` the comparison counts: in its cone and facing it (elsewhere shading is 0).
inline bool counts(const Light& l, const Receiver& r) {
    return inLightCone(l, r.p) && glm::dot(r.n, l.position - r.p) > 0.0f;
}

// Renders `scene` from `camera` with static bakes of every static spot light; see the file comment.
inline Outcome runCase(const char* name, const Scene& scene, const CameraDesc& camera,
                       const RunOptions& o = {}) {
    Outcome out;
    auto m = makeModule();
    if (!m) return out;
    auto binding = bindScene(*m, scene);
    EXPECT_TRUE(binding.ok()) << binding.error();
    if (!binding) return out;
    EXPECT_TRUE(m->createTargets(o.width, o.height).ok());
    auto cam = m->setCamera(camera);
    EXPECT_TRUE(cam.ok()) << cam.error();
    EXPECT_TRUE(m->setShadowFilter(o.pcf).ok());
    // Bake: lights sharing a frustum (position, direction, cone, range) share one bake.
    CasterTriangles casters = castersFromScene(scene);
    std::map<std::vector<float>, size_t> cache;
    std::vector<std::vector<uint32_t>> bakes;
    std::vector<int> bakeOfLight(scene.lights.size(), -1);
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        if (l.dynamic || l.type != LightKind::Spot) continue;
        float nearPlane = o.nearOverRange > 0 ? l.range * o.nearOverRange : o.lightNear;
        LightFrustum f = spotLightFrustum(l, nearPlane);
        std::vector<float> key(&f.view[0][0], &f.view[0][0] + 16);
        key.insert(key.end(), {f.fov, f.nearPlane, f.farPlane});
        auto it = cache.find(key);
        if (it == cache.end()) {
            DualDepthMap map = rasterizeDual(casters, f, o.resolution);
            auto words = encodeStatic(o.method, map, {f.nearPlane, f.farPlane, {}});
            if (!words) {
                out.bakeErrors.push_back("light " + std::to_string(i) + ": " + words.error());
                continue;
            }
            it = cache.emplace(key, bakes.size()).first;
            bakes.push_back(std::move(words.value()));
        }
        auto r = m->setStaticShadow(binding->lights[i], {o.method, f, bakes[it->second]});
        if (!r) {
            out.bakeErrors.push_back(r.error());
            continue;
        }
        bakeOfLight[i] = int(it->second);
        out.frustums.push_back(f);
        ++out.baked;
    }
    renderFrame(*m);
    vkQueueWaitIdle(deviceOf(*m).queue);
    m->collect();
    auto reports = m->takeReports();
    if (!reports.empty()) out.stats = reports.back().stats;

    auto& impl = internals(*m);
    const auto& fc = impl.lastConstants;
    auto hdr = readImage(*m, impl.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    auto depth = toFloats(readImage(*m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    auto normal = readImage(*m, impl.targets.normal, 8, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    for (size_t i = 0; i < size_t(o.width) * o.height; ++i) {
        glm::vec4 c = half4(hdr, i);
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(c[k]))
                ++out.nonFinite;
            else
                out.maxHdr = std::max(out.maxHdr, c[k]);
        }
        if (!gpu::hasSurface(depth[i])) continue;
        ++out.surfacePixels;
        uint32_t x = uint32_t(i % o.width), y = uint32_t(i / o.width);
        glm::vec3 p = gpu::worldFromPixel(x, y, depth[i], fc.invViewProj, fc.size);
        glm::vec3 n = glm::vec3(half4(normal, i));
        float len = glm::length(n);
        out.receivers.push_back({p, len > 0 ? n / len : glm::vec3(0, 1, 0)});
    }
    EXPECT_TRUE(m->readOutput(out.rgba).ok());

    // Against the rays, per measured light.
    auto rays = RayReference::build(scene, true);
    EXPECT_TRUE(rays.ok()) << rays.error();
    uint32_t measured = 0;
    for (size_t i = 0; rays && i < scene.lights.size() && measured < o.measureLights; ++i) {
        if (bakeOfLight[i] < 0) continue;
        const Light& l = scene.lights[i];
        float nearPlane = o.nearOverRange > 0 ? l.range * o.nearOverRange : o.lightNear;
        LightFrustum f = spotLightFrustum(l, nearPlane);
        auto rec = makeShadowRecord(o.method, f, 0, o.resolution, o.pcf);
        std::vector<glm::vec3> ps, ns;
        std::vector<float> vis;
        for (const Receiver& r : out.receivers)
            if (counts(l, r)) {
                ps.push_back(r.p);
                ns.push_back(r.n);
                vis.push_back(staticVisibility(rec, bakes[size_t(bakeOfLight[i])].data(), r.p, r.n));
            }
        std::vector<uint8_t> truth(ps.size());
        rays->visibleBatch(ps.data(), ns.data(), ps.size(), l.position, o.rayBias, truth.data());
        Disagreement d = compareVisibility(vis, truth);
        out.perLight.push_back(d);
        out.vsRays.merge(d);
        ++measured;
    }
    for (int b : bakeOfLight)
        if (b >= 0) out.words.push_back(bakes[size_t(b)]);

    if (const char* dir = std::getenv("ML_FAILURE_IMAGES")) {
        auto w = writePng(std::string(dir) + "/" + name + ".png", o.width, o.height, out.rgba);
        EXPECT_TRUE(w.ok()) << w.error();
    }
    std::printf("  [%s] %s %u^2 pcf %u: %u lights baked, %llu surface pixels, %llu non-finite, max HDR %.3g, "
                "%llu receivers vs rays, %llu disagree (%.3f%%)\n",
                name, staticMethodName(o.method), o.resolution, o.pcf, out.baked,
                (unsigned long long)out.surfacePixels, (unsigned long long)out.nonFinite, out.maxHdr,
                (unsigned long long)out.vsRays.compared, (unsigned long long)out.vsRays.mismatches,
                100.0 * out.vsRays.rate());
    EXPECT_EQ(out.nonFinite, 0u) << name << ": NaN or Inf in the HDR image";
    EXPECT_EQ(validationErrors(), 0u);
    out.module = std::move(m);
    return out;
}

} // namespace ml::test
