// GPU light culling against its CPU reference (culling/culling.h) on the night city: cluster bounds
// bit for bit, light lists exactly and in order (every mode sorts its lists by light index, as the
// reference does), and the per-pixel counts of the statistics.
#include "gpu_test_util.h"

#include "shaders/shared/light_math.h"

#include "lights/lights.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdlib>
#include <random>

namespace ml::test {

namespace {

struct Fixture {
    std::unique_ptr<Module> module;
    Scene scene;
};

Fixture renderCity(CullingMode mode, uint32_t lights, uint32_t width = 320, uint32_t height = 180) {
    Fixture f;
    f.module = makeModule(mode);
    auto s = loadScene("night-city", lights, 7);
    EXPECT_TRUE(s.ok()) << s.error();
    f.scene = s.value();
    auto b = bindScene(*f.module, f.scene);
    EXPECT_TRUE(b.ok()) << b.error();
    EXPECT_TRUE(f.module->createTargets(width, height).ok());
    renderFrame(*f.module);
    return f;
}

void compareWithReference(Module& m, CullingMode mode, uint32_t* wideOut = nullptr) {
    auto& impl = internals(m);
    auto depth = toFloats(readImage(m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    ClusterReference ref = cullReference(depth, impl.lastConstants, impl.lastSliceFar, impl.lastLights);
    const ClusterGrid& grid = impl.cull.grid;
    ASSERT_EQ(ref.bounds.size(), grid.count());
    if (mode == CullingMode::Tiled) {
        ASSERT_EQ(grid.slices, 1u);
    }
    std::vector<gpu::ClusterBounds> boundsRead =
        readBufferAs<gpu::ClusterBounds>(*impl.device, impl.cull.bounds); // GPU-only
    auto* bounds = boundsRead.data();
    std::vector<glm::uvec2> rangesRead = readBufferAs<glm::uvec2>(*impl.device, impl.cull.ranges); // GPU-only
    auto* ranges = rangesRead.data();
    std::vector<uint32_t> poolRead = readBufferAs<uint32_t>(*impl.device, impl.cull.pool); // GPU-only
    auto* pool = poolRead.data();
    size_t occupied = 0, entries = 0;
    for (uint32_t c = 0; c < grid.count(); ++c) {
        ASSERT_EQ(0, std::memcmp(&bounds[c], &ref.bounds[c], sizeof(gpu::ClusterBounds))) << "cluster " << c;
        if (ref.bounds[c].lo.w == 0.0f) continue;
        ++occupied;
        ASSERT_NE(ranges[c].x, ML_CLUSTER_OVERFLOW) << "unexpected overflow in cluster " << c;
        // In order: the lists are sorted on the GPU (light_fill's per-tile bitmask append, light_assign's
        // chunked write), not only equal as sets.
        std::vector<uint32_t> gpuList(pool + ranges[c].x, pool + ranges[c].x + ranges[c].y);
        ASSERT_EQ(gpuList, ref.lists[c]) << "cluster " << c;
        entries += gpuList.size();
    }
    EXPECT_GT(occupied, 100u);
    EXPECT_GT(entries, 20u) << "lists too small to mean anything";
    uint32_t wide = 0; // lights the wide pass assigned (params.w), checked against the host's rule
    for (const gpu::GpuLight& l : impl.lastLights) {
        EXPECT_EQ(l.params.w == 1.0f,
                  mode == CullingMode::Clustered && wideFootprint(l, impl.lastConstants).has_value());
        wide += l.params.w == 1.0f;
    }
    if (wideOut) *wideOut = wide;
    std::printf("  %s: %zu occupied clusters, %zu list entries identical in order, %u wide lights\n",
                cullingName(mode), occupied, entries, wide);
}

} // namespace

TEST(GpuCulling, ClusteredListsEqualCpuReference) {
    auto f = renderCity(CullingMode::Clustered, 256);
    compareWithReference(*f.module, CullingMode::Clustered);
    EXPECT_EQ(validationErrors(), 0u);
}

// The per-lane build of cluster_bounds.comp (every pixel's own shared atomics: the fallback for devices
// without subgroup arithmetic, forced with ML_BOUNDS_WAVE=0) gives the same bounds bit for bit; the test
// above ran the wave build where the device has it.
TEST(GpuCulling, PerLaneBoundsEqualCpuReference) {
    setenv("ML_BOUNDS_WAVE", "0", 1);
    auto f = renderCity(CullingMode::Clustered, 256);
    unsetenv("ML_BOUNDS_WAVE");
    EXPECT_FALSE(internals(*f.module).cull.waveBounds());
    compareWithReference(*f.module, CullingMode::Clustered);
    EXPECT_EQ(validationErrors(), 0u);
}

// Wide lights: the moon is assigned by the wide pass, one thread per tile, a point light around the
// camera (footprint: the whole screen) by its lanes; the clusters' lists still equal the reference's.
TEST(GpuCulling, WideLightsListsEqualCpuReference) {
    auto m = makeModule(CullingMode::Clustered);
    auto s = loadScene("night-city", 64, 7);
    ASSERT_TRUE(s.ok()) << s.error();
    Scene scene = s.value();
    Light around;
    around.type = LightKind::Point;
    around.position = scene.camera.position;
    around.range = 60.0f;
    scene.lights.push_back(around);
    bool moon = false;
    for (const Light& l : scene.lights) moon = moon || l.type == LightKind::Directional;
    ASSERT_TRUE(moon) << "the night city is expected to have its moon";
    ASSERT_TRUE(bindScene(*m, scene).ok());
    ASSERT_TRUE(m->createTargets(320, 180).ok());
    renderFrame(*m);
    uint32_t wide = 0;
    compareWithReference(*m, CullingMode::Clustered, &wide);
    EXPECT_EQ(wide, 1u); // the moon
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuCulling, ClusteredBruteListsEqualCpuReference) {
    auto f = renderCity(CullingMode::ClusteredBrute, 256);
    compareWithReference(*f.module, CullingMode::ClusteredBrute);
    EXPECT_EQ(validationErrors(), 0u);
}

// The footprint lists are the brute-force lists restricted to each light's footprint: a subset of
// them, cluster by cluster, and never missing a light that reaches a pixel (next test).
TEST(GpuCulling, FootprintListsAreSubsetsOfBruteForce) {
    auto f = renderCity(CullingMode::Clustered, 512);
    auto& impl = internals(*f.module);
    auto depth =
        toFloats(readImage(*f.module, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    gpu::FrameConstants brute = impl.lastConstants;
    brute.cluster.w = ML_CULL_CLUSTERED_BRUTE;
    ClusterReference fp = cullReference(depth, impl.lastConstants, impl.lastSliceFar, impl.lastLights);
    ClusterReference bf = cullReference(depth, brute, impl.lastSliceFar, impl.lastLights);
    size_t fpEntries = 0, bfEntries = 0;
    for (size_t c = 0; c < fp.lists.size(); ++c) {
        ASSERT_TRUE(
            std::includes(bf.lists[c].begin(), bf.lists[c].end(), fp.lists[c].begin(), fp.lists[c].end()))
            << "cluster " << c;
        fpEntries += fp.lists[c].size();
        bfEntries += bf.lists[c].size();
    }
    std::printf("  entries: footprint %zu, brute force %zu\n", fpEntries, bfEntries);
    EXPECT_GT(fpEntries, 100u);
}

TEST(GpuCulling, TiledListsEqualCpuReference) {
    auto f = renderCity(CullingMode::Tiled, 256);
    compareWithReference(*f.module, CullingMode::Tiled);
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuCulling, ManyLightsListsEqualCpuReference) {
    auto f = renderCity(CullingMode::Clustered, 2048, 192, 108);
    compareWithReference(*f.module, CullingMode::Clustered);
    EXPECT_EQ(validationErrors(), 0u);
}

// Every light that reaches a pixel is in that pixel's list (the cluster test is conservative), and
// the GPU's per-pixel counters equal the CPU's, in every mode (none: every visible light).
class NoLightMissing : public ::testing::TestWithParam<CullingMode> {};

TEST_P(NoLightMissing, AndStatsMatch) {
    const CullingMode mode = GetParam();
    auto f = renderCity(mode, 256);
    Module& m = *f.module;
    auto& impl = internals(m);
    auto depth = toFloats(readImage(m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    const auto& fc = impl.lastConstants;
    std::vector<glm::uvec2> rangesRead = readBufferAs<glm::uvec2>(*impl.device, impl.cull.ranges); // GPU-only
    auto* ranges = rangesRead.data();
    std::vector<uint32_t> poolRead = readBufferAs<uint32_t>(*impl.device, impl.cull.pool); // GPU-only
    auto* pool = poolRead.data();
    uint64_t surface = 0, reaching = 0, evaluated = 0;
    for (uint32_t y = 0; y < fc.size.y; ++y)
        for (uint32_t x = 0; x < fc.size.x; ++x) {
            float d = depth[size_t(y) * fc.size.x + x];
            if (!gpu::hasSurface(d)) continue;
            ++surface;
            glm::vec3 p = gpu::worldFromPixel(x, y, d, fc.invViewProj, fc.size);
            std::vector<uint32_t> list;
            if (mode == CullingMode::None) {
                for (uint32_t l = 0; l < impl.lastLights.size(); ++l) list.push_back(l);
            } else {
                uint32_t s = sliceOf(gpu::linearDepth(d, fc.depth), impl.lastSliceFar, fc.cluster.x);
                uint32_t c = ((y / ML_TILE_SIZE) * fc.size.z + x / ML_TILE_SIZE) * fc.cluster.x + s;
                ASSERT_NE(ranges[c].x, ML_CLUSTER_OVERFLOW);
                list.assign(pool + ranges[c].x, pool + ranges[c].x + ranges[c].y);
            }
            evaluated += list.size();
            for (uint32_t l = 0; l < impl.lastLights.size(); ++l)
                if (gpu::lightReachesPoint(impl.lastLights[l], p)) {
                    ++reaching;
                    ASSERT_NE(std::find(list.begin(), list.end(), l), list.end())
                        << "light " << l << " reaches pixel " << x << "," << y
                        << " but is not in its cluster";
                }
        }
    auto reports = m.takeReports();
    ASSERT_EQ(reports.size(), 1u);
    const FrameStats& st = reports[0].stats;
    EXPECT_EQ(st.surfacePixels, surface);
    EXPECT_DOUBLE_EQ(st.lightsPerPixelReachingMean, double(reaching) / surface);
    EXPECT_DOUBLE_EQ(st.lightsPerPixelEvaluatedMean, double(evaluated) / surface);
    EXPECT_GT(reaching, 0u);
    EXPECT_EQ(st.lightsTotal, 256u);
    EXPECT_EQ(st.clusterOverflowCount, 0u);
    EXPECT_EQ(validationErrors(), 0u);
    std::printf("  %s: evaluated %.3f, reaching %.3f lights per pixel\n", cullingName(mode),
                st.lightsPerPixelEvaluatedMean, st.lightsPerPixelReachingMean);
}

INSTANTIATE_TEST_SUITE_P(GpuCulling, NoLightMissing,
                         ::testing::Values(CullingMode::Clustered, CullingMode::ClusteredBrute,
                                           CullingMode::Tiled, CullingMode::None),
                         [](const auto& info) {
                             std::string n = cullingName(info.param);
                             std::erase(n, '-');
                             return n;
                         });

// A pool too small for the lists: overflowing clusters are counted, and their pixels test every
// visible light, so the image equals the one rendered with room to spare.
// lightFootprint (CPU side of the shared function): every point a light reaches projects into its
// tile rectangle and depth range, for random spot and point lights around, in front of, behind and
// straddling the camera; a light around the camera covers every tile from the near plane; one wholly
// behind the camera covers nothing.
TEST(LightFootprint, HoldsEveryReachedPoint) {
    const uint32_t width = 320, height = 180;
    glm::mat4 view = glm::lookAt(glm::vec3(0, 5, 0), glm::vec3(0, 4, -10), glm::vec3(0, 1, 0));
    glm::mat4 proj = glm::perspectiveRH_ZO(1.0f, float(width) / height, 0.1f, 500.0f);
    proj[1][1] *= -1.0f;
    const glm::mat4 vp = proj * view;
    const glm::uvec4 size(width, height, (width + ML_TILE_SIZE - 1) / ML_TILE_SIZE,
                          (height + ML_TILE_SIZE - 1) / ML_TILE_SIZE);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int checked = 0;
    for (int i = 0; i < 400; ++i) {
        LightDesc d;
        d.kind = i % 3 == 0 ? LightKind::Point : LightKind::Spot;
        d.position = glm::vec3(u(rng) * 20.0f, 5.0f + u(rng) * 5.0f, -10.0f + u(rng) * 25.0f);
        d.direction = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0, 0, 0.01f));
        d.range = 2.0f + (u(rng) + 1.0f) * 8.0f;
        d.outerAngle = 0.2f + (u(rng) + 1.0f) * 0.6f;
        d.innerAngle = 0.5f * d.outerAngle;
        gpu::GpuLight L = toGpuLight(d, 0);
        gpu::LightFootprint f = gpu::lightFootprint(L, vp, size, ML_TILE_SIZE, 0.1f);
        for (int k = 0; k < 300; ++k) {
            glm::vec3 x = toGlm(d.position) + glm::vec3(u(rng), u(rng), u(rng)) * d.range;
            if (!gpu::lightReachesPoint(L, x)) continue;
            glm::vec4 c = vp * glm::vec4(x, 1.0f);
            if (c.w < 0.1f) continue; // behind the near plane: no pixel sees it
            float px = (c.x / c.w + 1.0f) * 0.5f * width, py = (c.y / c.w + 1.0f) * 0.5f * height;
            if (px < 0 || py < 0 || px >= width || py >= height || c.w > 500.0f) continue;
            ++checked;
            uint32_t tx = uint32_t(px) / ML_TILE_SIZE, ty = uint32_t(py) / ML_TILE_SIZE;
            ASSERT_TRUE(tx >= f.tiles.x && tx <= f.tiles.z && ty >= f.tiles.y && ty <= f.tiles.w)
                << "light " << i << " point at tile " << tx << "," << ty << " outside " << f.tiles.x << ","
                << f.tiles.y << ".." << f.tiles.z << "," << f.tiles.w;
            ASSERT_GE(c.w, f.depth.x) << "light " << i;
            ASSERT_LE(c.w, f.depth.y) << "light " << i;
        }
    }
    EXPECT_GT(checked, 10000);

    LightDesc around;
    around.kind = LightKind::Point;
    around.position = glm::vec3(0.5f, 5.0f, 0.5f);
    around.range = 4.0f;
    gpu::LightFootprint all = gpu::lightFootprint(toGpuLight(around, 0), vp, size, ML_TILE_SIZE, 0.1f);
    EXPECT_EQ(all.tiles, glm::uvec4(0, 0, size.z - 1, size.w - 1));
    EXPECT_LE(all.depth.x, 0.1f);
    LightDesc behind = around;
    behind.position = glm::vec3(0.0f, 5.0f, 20.0f);
    gpu::LightFootprint none = gpu::lightFootprint(toGpuLight(behind, 0), vp, size, ML_TILE_SIZE, 0.1f);
    EXPECT_GT(none.tiles.x, none.tiles.z);
}

class Overflow : public ::testing::TestWithParam<CullingMode> {};

TEST_P(Overflow, IsCountedAndDropsNoLight) {
    auto f = renderCity(GetParam(), 256);
    Module& m = *f.module;
    std::vector<uint8_t> full, overflowed;
    ASSERT_TRUE(m.readOutput(full).ok());
    m.takeReports();
    internals(m).poolOverride = 16;
    internals(m).cullingMode = CullingMode(~0u); // resize with the small pool
    renderFrame(m);
    ASSERT_TRUE(m.readOutput(overflowed).ok());
    auto reports = m.takeReports();
    ASSERT_EQ(reports.size(), 1u);
    EXPECT_GT(reports[0].stats.clusterOverflowCount, 0u);
    EXPECT_EQ(reports[0].stats.poolCapacity, 16u);
    ASSERT_EQ(full.size(), overflowed.size());
    int maxDiff = 0;
    for (size_t i = 0; i < full.size(); ++i)
        maxDiff = std::max(maxDiff, std::abs(int(full[i]) - int(overflowed[i])));
    EXPECT_LE(maxDiff, 1) << "overflowed clusters changed the image";
    EXPECT_EQ(validationErrors(), 0u);
}

INSTANTIATE_TEST_SUITE_P(GpuCulling, Overflow,
                         ::testing::Values(CullingMode::Clustered, CullingMode::ClusteredBrute),
                         [](const auto& info) {
                             std::string n = cullingName(info.param);
                             std::erase(n, '-');
                             return n;
                         });

} // namespace ml::test
