// The GLSL decoders (shaders/static/*_lookup.glsl) compiled as C++ (glsl_shims.h). Every texel must
// decode bit-identically to the C++ decoders, at base 0 and with the buffer placed at an odd offset
// inside a larger array (the `base` argument). The text is the C++ decoders' own
// (shaders/static/mh_descent.h, dagmh_decode.h): this pins the GLSL instantiation (words read through
// ML_STATIC_DATA at `base`). DAG-MH's bounds tests (the one-texel test, the four-word path) are compared
// with a plain loop over the bounds cells (boundsByLoop below). The GPU run of the same text comes with
// the GPU tests (GpuStatic.*); this pins the text itself.
#include "static_test_util.h"
#include "bake/bake.h"
#include "bake/scene_casters.h"
#include "glsl_shims.h"
#include "scenes/scenes.h"

namespace ml::stest {
namespace {

// The DAG-MH bounds test as a loop over every bounds cell of the block, section offsets from the header
// words (the decoder derives them from S and B): 1 lit, 2 shadowed, 0 undecided.
uint32_t boundsByLoop(const uint32_t* data, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1,
                      uint32_t depth) {
    const uint32_t L = data[dagfmt::kLevels], S = dagfmt::skipLevel(data), B = dagfmt::boundsLevel(data);
    const uint32_t* bounds = data + data[dagfmt::kSkipOffset] + (dagfmt::kSkipWords << (2u * S));
    const uint32_t sh = L - B;
    uint32_t lo = 0xFFFFFFFFu, hi = 0u;
    for (uint32_t Y = y0 >> sh; Y <= y1 >> sh; ++Y)
        for (uint32_t X = x0 >> sh; X <= x1 >> sh; ++X) {
            const uint32_t w = bounds[(Y << B) + X];
            lo = std::min(lo, w << 16u);
            hi = std::max(hi, w | 0xFFFFu);
        }
    return depth <= lo ? 1u : (depth > hi ? 2u : 0u);
}

void compareTwins(const DualDepthMap& m) {
    const uint32_t base = 37;
    for (int method = 0; method < 5; ++method) { // MH, MMH, DAG-MH, then MH and MMH with far groups
        const Codec codec = codecs()[method];
        SCOPED_TRACE(codec.name);
        auto enc = codec.encode(m);
        ASSERT_TRUE(enc.ok()) << enc.error();
        ASSERT_TRUE(codec.validate(enc->data(), enc->size()).ok());
        std::vector<uint32_t> shifted(base, 0xDEADBEEFu);
        shifted.insert(shifted.end(), enc->begin(), enc->end());
        uint64_t diff = 0;
        for (uint32_t y = 0; y < m.resolution; ++y)
            for (uint32_t x = 0; x < m.resolution; ++x) {
                uint32_t cpu = codec.lookup(enc->data(), x, y);
                glsl::gStaticData = shifted.data();
                uint32_t g = method % 3 == 0   ? glsl::mhLookup(base, x, y)
                             : method % 3 == 1 ? glsl::mmhLookup(base, x, y)
                                               : glsl::dagmhLookup(base, x, y);
                glsl::gStaticData = enc->data();
                uint32_t g0 = method % 3 == 0   ? glsl::mhLookup(0, x, y)
                              : method % 3 == 1 ? glsl::mmhLookup(0, x, y)
                                                : glsl::dagmhLookup(0, x, y);
                diff += (g != cpu) + (g0 != cpu);
                if (method != 2) continue;
                // The value-bounds test over the 1x1, 3x3 and 9x9 blocks at this texel (the one-texel
                // test, the four-word path within 2x2 cells and the loop over more), at depths around its
                // value: the GLSL text answers as the loop does, and so does the C++ instantiation.
                glsl::gStaticData = shifted.data();
                const glsl::DagmhHeader h = glsl::dagmhHeader(base);
                diff += glsl::dagmhLevels(m.resolution) != enc->data()[dagfmt::kLevels];
                const uint32_t x0 = x > 0 ? x - 1 : 0, y0 = y > 0 ? y - 1 : 0;
                const uint32_t x1 = std::min(x + 1, m.resolution - 1), y1 = std::min(y + 1, m.resolution - 1);
                for (uint32_t depth : {cpu, cpu + 1u, cpu - 70000u, cpu + 70000u}) {
                    const uint32_t* d = enc->data();
                    diff +=
                        glsl::dagmhBoundsClass(h, x, y, x, y, depth) != boundsByLoop(d, x, y, x, y, depth);
                    diff += glsl::dagmhBoundsClass(h, x0, y0, x1, y1, depth) !=
                            boundsByLoop(d, x0, y0, x1, y1, depth);
                    diff += glsl::dagmhBoundsClass1(h, x, y, depth) != boundsByLoop(d, x, y, x, y, depth);
                    diff += dagmhBoundsClass(d, dagmhHeader(d, 0), x0, y0, x1, y1, depth) !=
                            boundsByLoop(d, x0, y0, x1, y1, depth);
                    const uint32_t X0 = x > 4 ? x - 4 : 0, Y0 = y > 4 ? y - 4 : 0;
                    const uint32_t X1 = std::min(x + 4, m.resolution - 1),
                                   Y1 = std::min(y + 4, m.resolution - 1);
                    diff += glsl::dagmhBoundsClass(h, X0, Y0, X1, Y1, depth) !=
                            boundsByLoop(enc->data(), X0, Y0, X1, Y1, depth);
                }
            }
        EXPECT_EQ(diff, 0u);
    }
}

TEST(StaticGlslTwins, BitIdenticalSynthetic) {
    compareTwins(syntheticMap(512, 77));
    compareTwins(syntheticMap(300, 78));
}

TEST(StaticGlslTwins, BitIdenticalRaster) {
    CasterTriangles c;
    std::mt19937 rng(21);
    for (int i = 0; i < 60; ++i) {
        glm::vec3 p(float(rng() % 100) / 10 - 5, float(rng() % 100) / 10 - 5, -3.0f - float(rng() % 50) / 10);
        glm::vec3 q = p + glm::vec3(0.3f + float(rng() % 10) / 10);
        glm::vec3 v[8];
        for (int k = 0; k < 8; ++k) v[k] = {k & 1 ? q.x : p.x, k & 2 ? q.y : p.y, k & 4 ? q.z : p.z};
        const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (auto& q4 : f)
            c.add(v[q4[0]], v[q4[1]], v[q4[2]], i % 4 != 0), c.add(v[q4[0]], v[q4[2]], v[q4[3]], i % 4 != 0);
    }
    LightFrustum fr;
    fr.fov = 1.2f;
    fr.farPlane = 12.0f;
    compareTwins(rasterizeDual(c, fr, 512));
}

// Real maps of the default night city (as `bake` makes them): the moon (light 239, directional,
// orthographic: the DAG-MH chunks mix roof slabs, walls and ground on shared slopes) and the first static
// spot light whose map holds more than the ground (perspective). Every texel, C++ against the GLSL text,
// and lossless (encodeChecked in compareTwins' codec.validate path is not enough: countLossy below).
TEST(StaticGlslTwins, BitIdenticalNightCityMoonAndSpot) {
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    ASSERT_GT(scene->lights.size(), 239u);
    const Light& moon = scene->lights[239];
    ASSERT_EQ(moon.type, LightKind::Directional);
    const CasterTriangles casters = castersFromScene(*scene);
    std::vector<DualDepthMap> maps{rasterizeDual(casters, bakeFrustums(*scene, moon).front(), 256)};
    for (const Light& l : scene->lights) {
        if (l.dynamic || l.type != LightKind::Spot) continue;
        DualDepthMap m = rasterizeDual(casters, bakeFrustums(*scene, l).front(), 256);
        uint64_t closed = 0;
        for (size_t i = 0; i < m.enter.size(); ++i) closed += m.exit[i] > m.enter[i];
        if (closed == 0) continue; // the ground alone (open): not the mixed case
        maps.push_back(std::move(m));
        break;
    }
    ASSERT_EQ(maps.size(), 2u);
    for (const DualDepthMap& m : maps) {
        SCOPED_TRACE(&m == &maps[0] ? "moon" : "spot");
        compareTwins(m);
        encodeChecked(m, codecs()[2]);
    }
}

} // namespace
} // namespace ml::stest
