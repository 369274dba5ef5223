// Point lights' static shadows: six cube-face bakes per light, the face picked per receiver in the
// evaluation pass. A box on open ground under a point light: the GPU's shadow on the ground matches the
// exact ray-box answer on every pixel away from the shadow's edge, and every face that sees ground is used.
#include "gpu_test_util.h"
#include "bake/scene_casters.h"
#include "tests/common/ray_box.h"

#include "shaders/shared/shading.h"
#include "shadows/gpu/dual_depth_gpu.h"
#include "shadows/static/raster_dual.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

namespace ml::test {

namespace {

Scene boxOnGround(glm::vec3 lo, glm::vec3 hi, glm::vec3 lightPos) {
    Scene s;
    s.name = "box-on-ground";
    Mesh box;
    box.name = "box";
    glm::vec3 p[8];
    for (int i = 0; i < 8; ++i) p[i] = glm::vec3(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0);
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (auto& f : faces) {
        glm::vec3 n = glm::normalize(glm::cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]));
        uint32_t b = uint32_t(box.vertices.size());
        for (int k = 0; k < 4; ++k) box.vertices.push_back({p[f[k]], n});
        for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) box.indices.push_back(b + i);
    }
    box.closed = false; // split corners: not welded here, so mark by hand below
    Mesh ground;
    ground.name = "ground";
    for (glm::vec3 q :
         {glm::vec3(-20, 0, -20), glm::vec3(-20, 0, 20), glm::vec3(20, 0, 20), glm::vec3(20, 0, -20)})
        ground.vertices.push_back({q, glm::vec3(0, 1, 0)});
    ground.indices = {0, 1, 2, 0, 2, 3};
    s.meshes = {box, ground};
    s.meshes[0].closed = isClosedMesh(s.meshes[0]);
    Instance bi;
    bi.mesh = 0;
    bi.transform = glm::translate(glm::mat4(1.0f), lo) * glm::scale(glm::mat4(1.0f), hi - lo);
    Instance gi;
    gi.mesh = 1;
    s.instances = {bi, gi};
    Light l;
    l.type = LightKind::Point;
    l.position = lightPos;
    l.range = 14.0f;
    l.intensity = 30.0f;
    s.lights = {l};
    s.camera.position = lightPos + glm::vec3(0.5f, 7.0f, 6.0f);
    s.camera.target = glm::vec3(lightPos.x, 0.0f, lightPos.z);
    return s;
}
} // namespace

TEST(GpuPointShadow, CubeFacesShadowTheGroundLikeRays) {
    const glm::vec3 lo(-1.0f, 0.0f, -0.5f), hi(0.0f, 1.2f, 0.5f), lightPos(1.0f, 1.6f, 0.2f);
    Scene scene = boxOnGround(lo, hi, lightPos);
    ASSERT_TRUE(scene.meshes[0].closed);
    auto m = makeModule();
    auto binding = bindScene(*m, scene);
    ASSERT_TRUE(binding.ok()) << binding.error();
    ASSERT_TRUE(m->createTargets(256, 192).ok());
    auto renderer = DualDepthRenderer::create(deviceOf(*m));
    ASSERT_TRUE(renderer.ok());
    CasterTriangles casters = castersFromScene(scene);
    auto frustums = lightFrustums(scene.lights[0]);
    ASSERT_EQ(frustums.size(), 6u);
    for (uint32_t face = 0; face < 6; ++face) {
        auto map = renderer.value()->render(casters, frustums[face], 512);
        ASSERT_TRUE(map.ok());
        auto words = encodeStatic(StaticMethod::DAGMH, map.value());
        ASSERT_TRUE(words.ok()) << words.error();
        ASSERT_TRUE(
            m->setStaticShadow(binding->lights[0], {StaticMethod::DAGMH, frustums[face], words.value(), face})
                .ok());
    }
    EXPECT_FALSE(m->setStaticShadow(binding->lights[0], {StaticMethod::DAGMH, frustums[0], {}, 6}).ok());
    renderFrame(*m);
    auto& impl = internals(*m);
    const auto& fc = impl.lastConstants;
    auto depth = toFloats(readImage(*m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    auto hdr = readImage(*m, impl.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    auto albedo = readImage(*m, impl.targets.albedo, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    ASSERT_EQ(impl.lastLights.size(), 1u);
    const gpu::GpuLight& L = impl.lastLights[0];
    uint32_t checked = 0, wrong = 0, shadowed = 0;
    bool facesSeen[6] = {};
    for (uint32_t y = 0; y < fc.size.y; ++y)
        for (uint32_t x = 0; x < fc.size.x; ++x) {
            size_t i = size_t(y) * fc.size.x + x;
            if (!gpu::hasSurface(depth[i])) continue;
            glm::vec3 P = gpu::worldFromPixel(x, y, depth[i], fc.invViewProj, fc.size);
            if (std::abs(P.y) > 1e-3f) continue; // ground receivers only
            glm::vec3 N(0, 1, 0), V = glm::normalize(glm::vec3(fc.cameraPosition) - P);
            glm::vec3 a = glm::vec3(albedo[i * 4], albedo[i * 4 + 1], albedo[i * 4 + 2]) / 255.0f;
            glm::vec3 lit = gpu::shadeLight(L, P, N, V, a);
            if (lit.x < 0.05f) continue; // too dark to read the shadow term back
            float got = half4(hdr, i).x - a.x * fc.ambient.x;
            float vis = got / lit.x;
            bool truth = blockedByBox(P, lightPos, lo, hi);
            bool edge = false;
            for (glm::vec3 o : {glm::vec3(0.1f, 0, 0), glm::vec3(-0.1f, 0, 0), glm::vec3(0, 0, 0.1f),
                                glm::vec3(0, 0, -0.1f)})
                edge |= blockedByBox(P + o, lightPos, lo, hi) != truth;
            if (edge) continue;
            ++checked;
            shadowed += truth;
            wrong += (vis < 0.5f) != truth;
            facesSeen[gpu::pointLightFace(P - lightPos)] = true;
        }
    std::printf("  %u ground pixels checked, %u in shadow, %u wrong\n", checked, shadowed, wrong);
    EXPECT_GT(checked, 5000u);
    EXPECT_GT(shadowed, 300u);
    EXPECT_LE(wrong, checked / 1000);
    for (uint32_t f : {0u, 1u, 3u, 4u, 5u}) EXPECT_TRUE(facesSeen[f]) << "face " << f << " not exercised";
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace ml::test
