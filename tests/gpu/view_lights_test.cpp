// The light-complexity view (demo --view lights / lights-reaching, lights/view_lights.comp): its
// per-pixel counts equal the CPU's (list length of the pixel's cluster, lights whose cone and range
// hold the point) and its colours are heatColor of the chosen count.
#include "gpu_test_util.h"

#include "shaders/shared/heat.h"

#include <algorithm>

namespace ml::test {
namespace {

struct Counts {
    std::vector<uint32_t> evaluated, reaching;
    std::vector<uint8_t> surface;
};

Counts cpuCounts(Module& m, CullingMode mode) {
    auto& impl = internals(m);
    auto depth = toFloats(readImage(m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    const auto& fc = impl.lastConstants;
    std::vector<glm::uvec2> rangesRead = readBufferAs<glm::uvec2>(*impl.device, impl.cull.ranges); // GPU-only
    auto* ranges = rangesRead.data();
    Counts out;
    size_t n = size_t(fc.size.x) * fc.size.y;
    out.evaluated.assign(n, 0);
    out.reaching.assign(n, 0);
    out.surface.assign(n, 0);
    for (uint32_t y = 0; y < fc.size.y; ++y)
        for (uint32_t x = 0; x < fc.size.x; ++x) {
            size_t i = size_t(y) * fc.size.x + x;
            float d = depth[i];
            if (!gpu::hasSurface(d)) continue;
            out.surface[i] = 1;
            glm::vec3 p = gpu::worldFromPixel(x, y, d, fc.invViewProj, fc.size);
            uint32_t evaluated = uint32_t(impl.lastLights.size());
            if (mode != CullingMode::None) {
                uint32_t s = sliceOf(gpu::linearDepth(d, fc.depth), impl.lastSliceFar, fc.cluster.x);
                uint32_t c = ((y / ML_TILE_SIZE) * fc.size.z + x / ML_TILE_SIZE) * fc.cluster.x + s;
                if (ranges[c].x != ML_CLUSTER_OVERFLOW) evaluated = ranges[c].y;
            }
            out.evaluated[i] = evaluated;
            for (const auto& l : impl.lastLights) out.reaching[i] += gpu::lightReachesPoint(l, p) ? 1u : 0u;
        }
    return out;
}

void check(CullingMode mode) {
    auto m = makeModule(mode);
    auto s = loadScene("night-city", 256, 3);
    ASSERT_TRUE(s.ok()) << s.error();
    ASSERT_TRUE(bindScene(*m, s.value()).ok());
    ASSERT_TRUE(m->createTargets(192, 108).ok());
    for (DebugView view : {DebugView::LightsEvaluated, DebugView::LightsReaching}) {
        m->setView(view);
        renderFrame(*m);
        std::vector<uint8_t> rgba;
        ASSERT_TRUE(m->readOutput(rgba).ok());
        Counts cpu = cpuCounts(*m, mode);
        auto* gpuCounts = internals(*m).cull.viewCounts.as<uint32_t>();
        size_t surface = 0, maxReaching = 0, maxColourDiff = 0;
        for (size_t i = 0; i < cpu.surface.size(); ++i) {
            uint32_t e = gpuCounts[i] & 0xFFFFu, r = gpuCounts[i] >> 16;
            ASSERT_EQ(e, cpu.evaluated[i]) << "pixel " << i;
            ASSERT_EQ(r, cpu.reaching[i]) << "pixel " << i;
            if (!cpu.surface[i]) continue;
            ++surface;
            maxReaching = std::max<size_t>(maxReaching, r);
            glm::vec3 want = gpu::heatColor(view == DebugView::LightsReaching ? r : e);
            for (int k = 0; k < 3; ++k) {
                int expect = int(want[k] * 255.0f + 0.5f);
                maxColourDiff =
                    std::max<size_t>(maxColourDiff, size_t(std::abs(int(rgba[i * 4 + k]) - expect)));
            }
        }
        EXPECT_GT(surface, 1000u);
        EXPECT_GE(maxReaching, 4u) << "a view where lights overlap";
        EXPECT_LE(maxColourDiff, 1u);
    }
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace

TEST(GpuViewLights, CountsAndColoursEqualCpuClustered) {
    check(CullingMode::Clustered);
}
TEST(GpuViewLights, CountsAndColoursEqualCpuNone) {
    check(CullingMode::None);
}

} // namespace ml::test
