// Z-binning (culling/zbin.h) against its CPU reference on the night city: the tile masks and the bins
// word for word, the per-pixel statistics exactly, and the candidates conservative (the lights reaching
// each pixel, counted among its Z-bin candidates, sum to the brute-force count of statistics.comp).
#include "gpu_test_util.h"

#include "culling/zbin.h"
#include "shaders/shared/light_math.h"
#include "shaders/shared/shading.h"

namespace ml::test {

namespace {

struct ZBinCase {
    uint32_t lights;
    bool depthTest;
};
void PrintTo(const ZBinCase& c, std::ostream* os) {
    *os << c.lights << " lights" << (c.depthTest ? ", tile depth test" : ", rectangles");
}

class ZBinEqualsReference : public ::testing::TestWithParam<ZBinCase> {};

} // namespace

TEST_P(ZBinEqualsReference, MasksBinsAndStats) {
    const ZBinCase param = GetParam();
    auto m = makeModule(CullingMode::Clustered);
    auto s = loadScene("night-city", param.lights, 7);
    ASSERT_TRUE(s.ok()) << s.error();
    ASSERT_TRUE(bindScene(*m, s.value()).ok());
    ASSERT_TRUE(m->createTargets(320, 180).ok());
    renderFrame(*m);
    auto& impl = internals(*m);
    const Device& d = *impl.device;
    const gpu::FrameConstants& fc = impl.lastConstants;
    auto depth = toFloats(readImage(*m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));

    // The depth test's input, from the culling reference (its bounds equal the GPU's: culling_test).
    const ClusterReference cref = cullReference(depth, fc, impl.lastSliceFar, impl.lastLights);
    const uint32_t tiles = fc.size.z * fc.size.w, slices = fc.cluster.x;
    std::vector<glm::uvec2> tileSlices(tiles, glm::uvec2(0u));
    for (uint32_t t = 0; t < tiles; ++t)
        for (uint32_t sl = 0; sl < slices; ++sl)
            if (cref.bounds[size_t(t) * slices + sl].lo.w != 0.0f) tileSlices[t][sl / 32] |= 1u << (sl % 32);
    std::vector<glm::uvec2> gpuSlices = readBufferAs<glm::uvec2>(d, impl.cull.tileMasks);
    ASSERT_GE(gpuSlices.size(), tiles);
    gpuSlices.resize(tiles); // the buffer may be larger than the grid
    for (uint32_t t = 0; t < tiles; ++t) ASSERT_EQ(gpuSlices[t], tileSlices[t]) << "tile " << t;

    const ZBinFrame zf = zbinPrepare(fc, impl.lastSliceFar, impl.lastLights, param.depthTest);
    const ZBinReference ref = zbinReference(zf, fc, tileSlices);
    EXPECT_GT(zf.push.sorted, param.lights / 4) << "most lights are expected on screen";
    EXPECT_EQ(zf.push.wide, 1u); // the moon

    ZBinning zb;
    ASSERT_TRUE(zb.create(d).ok());
    ASSERT_TRUE(zb.prepare(d, zf, fc, impl.lastLights).ok());
    VkCommandBuffer cmd = d.beginOneTime();
    zb.recordMasks(d, cmd, impl.cull.tileMasks);
    zb.recordBins(d, cmd);
    zb.recordStats(d, cmd, impl.targets.depth.view);
    d.endOneTime(cmd);
    std::vector<uint32_t> masks = readBufferAs<uint32_t>(d, zb.masks);
    masks.resize(ref.masks.size()); // the buffer is sized for ML_ZBIN_WORDS words per tile
    std::vector<uint32_t> bins = readBufferAs<uint32_t>(d, zb.bins);
    bins.resize(ref.bins.size()); // the buffer may be larger than ML_ZBIN_BINS words
    const ZBinStats gpuStats = zb.stats();
    // The shading probe over both candidate sets (zbin_shade.comp).
    std::vector<glm::vec4> shaded[2];
    ASSERT_TRUE(zb.prepareSlices(d, impl.lastSliceFar).ok());
    for (uint32_t z = 0; z < 2; ++z) {
        cmd = d.beginOneTime();
        zb.recordShade(d, cmd, z == 1, impl.targets.depth.view, impl.targets.normal.view, impl.cull.ranges,
                       impl.cull.pool);
        d.endOneTime(cmd);
        shaded[z] = readBufferAs<glm::vec4>(d, zb.shaded);
    }
    zb.destroy(d);

    size_t bits = 0, usedBins = 0;
    for (size_t w = 0; w < masks.size(); ++w) {
        ASSERT_EQ(masks[w], ref.masks[w]) << "tile " << w / zf.push.words << " word " << w % zf.push.words;
        bits += size_t(__builtin_popcount(ref.masks[w]));
    }
    ASSERT_EQ(bins, ref.bins);
    for (uint32_t b : ref.bins) usedBins += b != ML_ZBIN_EMPTY;
    EXPECT_GT(bits, size_t(param.lights)); // lights cover several tiles each
    EXPECT_GT(usedBins, 100u);

    const ZBinStats cpuStats = zbinStatsReference(zf, ref, depth, fc, impl.lastLights);
    EXPECT_EQ(gpuStats.evaluated, cpuStats.evaluated);
    EXPECT_EQ(gpuStats.reaching, cpuStats.reaching);
    EXPECT_EQ(gpuStats.surface, cpuStats.surface);
    EXPECT_EQ(gpuStats.tile, cpuStats.tile);
    EXPECT_EQ(gpuStats.exact, cpuStats.exact);
    EXPECT_GE(gpuStats.tile, gpuStats.evaluated);
    EXPECT_GE(gpuStats.evaluated, gpuStats.exact);
    EXPECT_GE(gpuStats.exact, gpuStats.reaching);
    // Conservative: the reaching lights found among the candidates are all of them (statistics.comp's
    // brute force over every visible light, same frame).
    auto reports = m->takeReports();
    ASSERT_EQ(reports.size(), 1u);
    const FrameStats& st = reports[0].stats;
    EXPECT_EQ(st.surfacePixels, gpuStats.surface);
    EXPECT_DOUBLE_EQ(st.lightsPerPixelReachingMean, double(gpuStats.reaching) / gpuStats.surface);
    EXPECT_GE(gpuStats.evaluated, gpuStats.reaching);
    // Both candidate sets shade like every visible light on the CPU (shading.h; non-reaching lights
    // add zero), within the tolerance of pow and normalize.
    auto normal = readImage(*m, impl.targets.normal, 8, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    size_t lit = 0;
    for (uint32_t y = 0; y < fc.size.y; ++y)
        for (uint32_t x = 0; x < fc.size.x; ++x) {
            const size_t i = size_t(y) * fc.size.x + x;
            if (!gpu::hasSurface(depth[i])) {
                ASSERT_EQ(shaded[0][i].w, 0.0f);
                ASSERT_EQ(shaded[1][i].w, 0.0f);
                continue;
            }
            const glm::vec3 P = gpu::worldFromPixel(x, y, depth[i], fc.invViewProj, fc.size);
            const glm::vec3 N = glm::normalize(glm::vec3(half4(normal, i)));
            const glm::vec3 V = glm::normalize(glm::vec3(fc.cameraPosition) - P);
            glm::vec3 want(0.0f);
            for (uint32_t l = 0; l < fc.cluster.z; ++l)
                want += gpu::shadeLight(impl.lastLights[l], P, N, V, glm::vec3(0.5f));
            lit += want.x + want.y + want.z > 1e-4f;
            for (uint32_t z = 0; z < 2; ++z)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(shaded[z][i][c], want[c], 1e-3f * std::abs(want[c]) + 1e-5f)
                        << (z ? "Z-bins" : "clusters") << " pixel " << x << "," << y;
        }
    EXPECT_GT(lit, size_t(fc.size.x) * fc.size.y / 10);
    EXPECT_EQ(validationErrors(), 0u);
    std::printf("  bins over %.3f-%.2f m\n", zf.push.binNear,
                zf.push.binNear + ML_ZBIN_BINS / zf.push.binScale);
    std::printf("  %u lights%s: %u sorted, %zu mask bits, %zu bins used; evaluated %.2f, reaching %.2f "
                "per pixel (tile alone %.2f, exact depth ranges %.2f; clusters: evaluated %.2f)\n",
                param.lights, param.depthTest ? " (tile depth test)" : "", zf.push.sorted, bits, usedBins,
                double(gpuStats.evaluated) / gpuStats.surface, double(gpuStats.reaching) / gpuStats.surface,
                double(gpuStats.tile) / gpuStats.surface, double(gpuStats.exact) / gpuStats.surface,
                st.lightsPerPixelEvaluatedMean);
}

INSTANTIATE_TEST_SUITE_P(GpuZBin, ZBinEqualsReference,
                         ::testing::Values(ZBinCase{256, false}, ZBinCase{256, true}, ZBinCase{2048, true}),
                         [](const auto& info) {
                             return std::to_string(info.param.lights) +
                                    (info.param.depthTest ? "_depth_test" : "_rectangles");
                         });

// Every pixel's bin holds each light whose depth range holds the pixel's depth (zbinOf is monotonic).
TEST(GpuZBin, BinOfIsMonotonic) {
    const float nearZ = 0.1f, scale = 1024.0f / 250.0f;
    uint32_t last = 0;
    for (float z = 0.0f; z < 400.0f; z += 0.013f) {
        const uint32_t b = gpu::zbinOf(z, nearZ, scale, 1024);
        ASSERT_GE(b, last);
        ASSERT_LT(b, 1024u);
        last = b;
    }
    EXPECT_EQ(last, 1023u);
}

} // namespace ml::test
