// The evaluation pass against its CPU reference (shaders/shared/shading.h compiled for the CPU), on
// sampled pixels of a night-city frame; and bad input to the module API.
#include "gpu_test_util.h"

#include "shaders/shared/shading.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>

namespace ml::test {

TEST(GpuEvaluate, SampledPixelsMatchCpuShading) {
    auto m = makeModule();
    auto scene = loadScene("night-city", 256, 3);
    ASSERT_TRUE(scene.ok()) << scene.error();
    ASSERT_TRUE(bindScene(*m, scene.value()).ok());
    ASSERT_TRUE(m->createTargets(320, 180).ok());
    renderFrame(*m);
    auto& impl = internals(*m);
    const auto& fc = impl.lastConstants;
    auto depth = toFloats(readImage(*m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    auto normal = readImage(*m, impl.targets.normal, 8, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    auto albedo = readImage(*m, impl.targets.albedo, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    auto hdr = readImage(*m, impl.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    std::vector<glm::uvec2> rangesRead = readBufferAs<glm::uvec2>(*impl.device, impl.cull.ranges); // GPU-only
    auto* ranges = rangesRead.data();
    std::vector<uint32_t> poolRead = readBufferAs<uint32_t>(*impl.device, impl.cull.pool); // GPU-only
    auto* pool = poolRead.data();
    uint32_t checked = 0, lit = 0;
    for (uint32_t y = 1; y < fc.size.y; y += 5)
        for (uint32_t x = 2; x < fc.size.x; x += 5) {
            size_t i = size_t(y) * fc.size.x + x;
            glm::vec3 expected = glm::vec3(fc.sky);
            if (gpu::hasSurface(depth[i])) {
                glm::vec3 P = gpu::worldFromPixel(x, y, depth[i], fc.invViewProj, fc.size);
                glm::vec3 N = glm::normalize(glm::vec3(half4(normal, i)));
                glm::vec3 a = glm::vec3(albedo[i * 4], albedo[i * 4 + 1], albedo[i * 4 + 2]) / 255.0f;
                glm::vec3 V = glm::normalize(glm::vec3(fc.cameraPosition) - P);
                expected = a * glm::vec3(fc.ambient);
                uint32_t s = sliceOf(gpu::linearDepth(depth[i], fc.depth), impl.lastSliceFar, fc.cluster.x);
                uint32_t c = ((y / ML_TILE_SIZE) * fc.size.z + x / ML_TILE_SIZE) * fc.cluster.x + s;
                for (uint32_t k = 0; k < ranges[c].y; ++k)
                    expected += gpu::shadeLight(impl.lastLights[pool[ranges[c].x + k]], P, N, V, a);
                if (ranges[c].y) ++lit;
            }
            glm::vec3 got = glm::vec3(half4(hdr, i));
            for (int k = 0; k < 3; ++k)
                ASSERT_NEAR(got[k], expected[k], 2e-3f * std::abs(expected[k]) + 2e-4f)
                    << "pixel " << x << "," << y << " channel " << k;
            ++checked;
        }
    EXPECT_GT(checked, 2000u);
    EXPECT_GT(lit, 20u) << "too few lit samples for the comparison to mean anything";
    EXPECT_EQ(validationErrors(), 0u);
}

// The wave-uniform light loop (evaluate.comp's kUniformLoop) against the per-lane loop: each lane adds
// the same lights in the same (sorted) order, so the HDR and tone-mapped images are bit-identical, with
// static bakes and virtual shadow maps on. Frames 3-5 of one module: the uniform loop twice around the
// per-lane loop, and the two uniform frames equal (the frames repeat, so a difference is the loop's).
TEST(GpuEvaluate, UniformLoopIsBitIdentical) {
    auto m = makeModule(CullingMode::Clustered, /*vsm*/ true);
    auto scene = loadScene("night-city", 256, 3);
    ASSERT_TRUE(scene.ok()) << scene.error();
    ASSERT_TRUE(bindScene(*m, scene.value()).ok());
    ASSERT_TRUE(m->createTargets(320, 180).ok());
    auto baked = m->bakeStaticShadows(StaticMethod::SM, 128);
    ASSERT_TRUE(baked.ok() && baked.value() > 10u) << (baked.ok() ? "" : baked.error());
    auto& impl = internals(*m);
    if (!impl.evaluate.uniformLoopSupported()) GTEST_SKIP() << "no subgroup arithmetic on this device";
    auto frame = [&](bool uniform) {
        EXPECT_TRUE(impl.evaluate.setUniformLoop(uniform));
        renderFrame(*m);
        std::vector<uint8_t> out;
        EXPECT_TRUE(m->readOutput(out).ok());
        auto hdr = readImage(*m, impl.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
        out.insert(out.end(), hdr.begin(), hdr.end());
        return out;
    };
    frame(true);
    frame(true); // warm-up: the virtual shadow maps settle
    const std::vector<uint8_t> uniformA = frame(true), lane = frame(false), uniformB = frame(true);
    auto differing = [](const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
        size_t n = a.size() == b.size() ? 0 : std::max(a.size(), b.size());
        for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) n += a[i] != b[i];
        return n;
    };
    // Fails with lists in the atomics' order (unsorted lists): they change from frame to frame.
    ASSERT_EQ(differing(uniformA, uniformB), 0u) << "frames do not repeat: the comparison would mean nothing";
    EXPECT_EQ(differing(lane, uniformA), 0u) << "bytes of output + HDR that differ between the loops";
    // Lists of several lights, so the union walk had lanes waiting on each other.
    std::vector<glm::uvec2> ranges = readBufferAs<glm::uvec2>(*impl.device, impl.cull.ranges);
    uint32_t multi = 0;
    for (const glm::uvec2& r : ranges) multi += r.x != ML_CLUSTER_OVERFLOW && r.y >= 2;
    EXPECT_GT(multi, 200u);
    auto reports = m->takeReports();
    ASSERT_FALSE(reports.empty());
    EXPECT_GT(reports.back().stats.lightsPerPixelEvaluatedMean, 2.0);
    std::printf("  %zu bytes identical, %u clusters with 2+ lights\n", lane.size(), multi);
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuModuleInput, BadLightsAreRejectedWithAReason) {
    auto m = makeModule();
    LightDesc ok;
    EXPECT_TRUE(m->addLight(ok).ok());
    auto check = [&](LightDesc l, const char* word) {
        auto r = m->addLight(l);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find(word), std::string::npos) << r.error();
    };
    LightDesc l = ok;
    l.position.x = NAN;
    check(l, "position");
    l = ok;
    l.range = -1.0f;
    check(l, "range");
    l = ok;
    l.intensity = -2.0f;
    check(l, "intensity");
    l = ok;
    l.color = glm::vec3(NAN);
    check(l, "colour");
    l = ok;
    l.outerAngle = 2.0f;
    check(l, "outer");
    l = ok;
    l.innerAngle = 0.9f;
    check(l, "inner");
    l = ok;
    l.direction = glm::vec3(0.0f);
    check(l, "direction");
    EXPECT_EQ(m->lightCount(), 1u) << "a rejected light must not be added";
    EXPECT_FALSE(m->createTargets(0, 0).ok());
    EXPECT_FALSE(m->createTargets(320, 0).ok());
    EXPECT_FALSE(m->setInstanceTransform(99, glm::mat4(1.0f)).ok());
    uint32_t badIndex[3] = {0, 1, 7};
    MeshVertex v[3] = {};
    EXPECT_FALSE(m->addMesh({v, badIndex, false, "bad"}).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuModuleInput, ZeroLightsRendersAmbientOnly) {
    auto m = makeModule();
    auto scene = loadScene("night-city", 1, 1);
    ASSERT_TRUE(scene.ok());
    scene->lights.clear();
    ASSERT_TRUE(bindScene(*m, scene.value()).ok());
    ASSERT_TRUE(m->createTargets(160, 90).ok());
    renderFrame(*m);
    auto reports = m->takeReports();
    ASSERT_EQ(reports.size(), 1u);
    EXPECT_EQ(reports[0].stats.lightsTotal, 0u);
    EXPECT_EQ(reports[0].stats.lightsPerPixelEvaluatedMean, 0.0);
    EXPECT_GT(reports[0].stats.surfacePixels, 0u);
    // Without lights no virtual shadow map is active: its passes are not recorded; the others are.
    for (const char* p : {"gbuffer", "cluster_bounds", "light_assign", "evaluate", "statistics"})
        EXPECT_TRUE(reports[0].times.ran(p)) << p;
    EXPECT_FALSE(reports[0].times.ran("vsm_draw"));
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace ml::test
