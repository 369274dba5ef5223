// The Vulkan dual depth bake against the CPU reference rasteriser, tiling, and losslessness of the
// encoders on GPU-rendered maps.
#include "gpu_test_util.h"
#include "bake/scene_casters.h"

#include "shadows/gpu/dual_depth_gpu.h"

#include <glm/gtc/matrix_transform.hpp>
#include "shadows/static/static_method.h"

namespace ml::test {

namespace {
struct Agreement {
    uint64_t texels = 0, coverageDiffer = 0, enterFar = 0, exitFar = 0, closedBoth = 0, gpuClosed = 0,
             cpuClosed = 0;
};

// Depth tolerance: the GPU quantises a float depth, the CPU a double one (2e-5 of the range), and the
// CPU snaps vertices to 1/256 texel: on a surface seen at a grazing angle that moves depth by up to the
// depth step between neighbouring texels / 256, so the tolerance adds the local step / 64.
Agreement compare(const DualDepthMap& gpuMap, const DualDepthMap& cpuMap) {
    Agreement a;
    const uint32_t res = cpuMap.resolution;
    for (size_t i = 0; i < gpuMap.enter.size(); ++i) {
        uint64_t step = 0;
        uint32_t x = uint32_t(i % res), y = uint32_t(i / res);
        for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
            int nx = int(x) + dx, ny = int(y) + dy;
            if (nx < 0 || ny < 0 || nx >= int(res) || ny >= int(res)) continue;
            uint32_t n = cpuMap.enter[size_t(ny) * res + nx];
            if (n != kDepthEmpty && cpuMap.enter[i] != kDepthEmpty)
                step = std::max<uint64_t>(step, std::llabs(int64_t(n) - int64_t(cpuMap.enter[i])));
        }
        const uint64_t tol = uint64_t(4294967294.0 * 2e-5) + step / 64;
        ++a.texels;
        bool ge = gpuMap.enter[i] == kDepthEmpty, ce = cpuMap.enter[i] == kDepthEmpty;
        if (ge != ce) {
            ++a.coverageDiffer;
            continue;
        }
        if (ge) continue;
        if (std::llabs(int64_t(gpuMap.enter[i]) - int64_t(cpuMap.enter[i])) > int64_t(tol)) ++a.enterFar;
        bool gClosed = gpuMap.exit[i] != gpuMap.enter[i], cClosed = cpuMap.exit[i] != cpuMap.enter[i];
        a.gpuClosed += gClosed;
        a.cpuClosed += cClosed;
        if (gClosed && cClosed) {
            ++a.closedBoth;
            // The GPU's exit is the nearest closed back face: never past the CPU's counting exit.
            if (int64_t(gpuMap.exit[i]) > int64_t(cpuMap.exit[i]) + int64_t(tol)) ++a.exitFar;
        }
    }
    return a;
}

LightFrustum boxFrustum() {
    LightFrustum f;
    f.view = glm::lookAt(glm::vec3(0.3f, 6.0f, 0.2f), glm::vec3(0.0f), glm::vec3(0, 0, 1));
    f.fov = 1.2f;
    f.nearPlane = 0.1f;
    f.farPlane = 12.0f;
    return f;
}

CasterTriangles boxAndQuad() {
    CasterTriangles c;
    // A closed unit box (CCW outward), centred at (0, 1, 0), and an open ground quad at y = 0.
    glm::vec3 p[8];
    for (int i = 0; i < 8; ++i)
        p[i] = glm::vec3(i & 1 ? 0.5f : -0.5f, i & 2 ? 1.5f : 0.5f, i & 4 ? 0.5f : -0.5f);
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (auto& f : faces) {
        c.add(p[f[0]], p[f[1]], p[f[2]], true);
        c.add(p[f[0]], p[f[2]], p[f[3]], true);
    }
    c.add({-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, false);
    c.add({-5, 0, -5}, {5, 0, 5}, {5, 0, -5}, false);
    return c;
}
} // namespace

TEST(GpuDualDepth, BoxAndQuadMatchCpuReference) {
    auto m = makeModule();
    auto r = DualDepthRenderer::create(deviceOf(*m));
    ASSERT_TRUE(r.ok()) << r.error();
    CasterTriangles c = boxAndQuad();
    auto gpuMap = r.value()->render(c, boxFrustum(), 256);
    ASSERT_TRUE(gpuMap.ok()) << gpuMap.error();
    DualDepthMap cpuMap = rasterizeDual(c, boxFrustum(), 256);
    Agreement a = compare(gpuMap.value(), cpuMap);
    std::printf("  closed: gpu %llu cpu %llu\n", (unsigned long long)a.gpuClosed,
                (unsigned long long)a.cpuClosed);
    std::printf("  %llu texels, coverage differs %llu, enter off %llu, closed both %llu, exit past %llu\n",
                (unsigned long long)a.texels, (unsigned long long)a.coverageDiffer,
                (unsigned long long)a.enterFar, (unsigned long long)a.closedBoth,
                (unsigned long long)a.exitFar);
    EXPECT_EQ(a.coverageDiffer, 0u) << "the ground quad covers the whole view";
    EXPECT_LE(a.enterFar, a.texels / 1000);
    EXPECT_GT(a.closedBoth, 1000u) << "the box should be entered in many texels";
    // Exits lie on the box's side faces, seen edge-on: a few texels right at a side face's silhouette.
    EXPECT_LE(a.exitFar, a.closedBoth / 50);
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuDualDepth, NightCityLightMatchesCpuAndTilesAgree) {
    auto m = makeModule();
    auto r = DualDepthRenderer::create(deviceOf(*m));
    ASSERT_TRUE(r.ok()) << r.error();
    auto scene = loadScene("night-city", 256, 4);
    ASSERT_TRUE(scene.ok());
    CasterTriangles c = castersFromScene(scene.value());
    // A floodlight: it sees a facade, the sidewalk and street furniture.
    const Light* light = nullptr;
    for (const Light& l : scene->lights)
        if (!l.dynamic && l.direction.y > 0.5f) light = &l;
    ASSERT_NE(light, nullptr);
    LightFrustum f = spotLightFrustum(*light);
    auto whole = r.value()->render(c, f, 512);
    auto tiled = r.value()->render(c, f, 512, 128);
    ASSERT_TRUE(whole.ok() && tiled.ok());
    DualDepthMap cpuMap = rasterizeDual(c, f, 512);
    Agreement a = compare(whole.value(), cpuMap);
    Agreement t = compare(tiled.value(), whole.value());
    std::printf("  gpu vs cpu: coverage differs %llu, enter off %llu of %llu; tiled vs whole: %llu / %llu\n",
                (unsigned long long)a.coverageDiffer, (unsigned long long)a.enterFar,
                (unsigned long long)a.texels, (unsigned long long)t.coverageDiffer,
                (unsigned long long)t.enterFar);
    EXPECT_LE(a.coverageDiffer, a.texels / 200) << "coverage differs beyond triangle edges";
    EXPECT_LE(a.enterFar, a.texels / 200);
    EXPECT_LE(t.coverageDiffer + t.enterFar, t.texels / 1000);
    // Every method is lossless on the GPU map: every texel decodes inside its interval.
    for (StaticMethod method : {StaticMethod::MH, StaticMethod::MMH, StaticMethod::DAGMH}) {
        auto words = encodeStatic(method, whole.value());
        ASSERT_TRUE(words.ok()) << words.error();
        uint64_t bad = 0;
        for (uint32_t y = 0; y < 512; ++y)
            for (uint32_t x = 0; x < 512; ++x) {
                uint32_t v = lookupStaticDepth(method, words->data(), 0, x, y);
                size_t i = size_t(y) * 512 + x;
                bad += whole->enter[i] == kDepthEmpty ? v != kDepthEmpty
                                                      : (v < whole->enter[i] || v > whole->exit[i]);
            }
        EXPECT_EQ(bad, 0u) << staticMethodName(method);
    }
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace ml::test
