// Static shadows on the GPU: the GLSL decoders return the CPU twins' values bit for bit (every texel,
// every voxel), and the evaluation pass with baked shadows matches its CPU reference.
#include "gpu_test_util.h"
#include "bake/scene_casters.h"

#include "gpu/bindings.h"
#include "shaders/shared/shading.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"
#include "tests/shaders/static_decode_push.h"

#include "test_static_decode.comp.spv.h"

#include <glm/gtc/packing.hpp>

#include <set>

namespace ml::test {

namespace {
// The first static spot light of the night city whose map holds casters other than the ground.
DualDepthMap cityLightMap(const Scene& scene, uint32_t res, LightFrustum* frustumOut) {
    CasterTriangles casters = castersFromScene(scene);
    DualDepthMap best;
    size_t bestCount = 0;
    for (size_t i = 0; i < scene.lights.size() && i < 40; ++i) {
        const Light& l = scene.lights[i];
        if (l.dynamic || l.type != LightKind::Spot) continue;
        LightFrustum f = spotLightFrustum(l);
        DualDepthMap map = rasterizeDual(casters, f, res);
        std::set<uint32_t> distinct(map.enter.begin(), map.enter.end());
        if (distinct.size() > bestCount) bestCount = distinct.size(), best = map, *frustumOut = f;
    }
    return best;
}
} // namespace

TEST(GpuStatic, DecodersAreBitIdenticalToCpu) {
    auto m = makeModule();
    Device& d = deviceOf(*m);
    auto scene = loadScene("night-city", 256, 5);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const uint32_t res = 128;
    LightFrustum spot;
    DualDepthMap spotMap = cityLightMap(scene.value(), res, &spot);
    ASSERT_EQ(spotMap.resolution, res);
    // A directional map fitted to a box: fewer rows than columns (SM version 2) and linear
    // CPVS slices; the rows past the light's volume must decode as empty on both sides.
    const LightFrustum moon = directionalLightFrustum(glm::normalize(glm::vec3(-0.25f, -1.0f, 0.0f)),
                                                      glm::vec3(-40, 0, -15), glm::vec3(40, 30, 15));
    DualDepthMap moonMap = rasterizeDual(castersFromScene(scene.value()), moon, res);
    ASSERT_LT(moonMap.rows, res);
    ASSERT_GT(moonMap.rows, 0u);
    ShaderModule shader = ML_SHADER(d, spv_test_static_decode_comp);
    Program program = createComputeProgram(d, shader);
    for (int kind = 0; kind < 2; ++kind)
        for (StaticMethod method : {StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH,
                                    StaticMethod::DAGMH, StaticMethod::CPVS}) {
            const LightFrustum& frustum = kind ? moon : spot;
            const DualDepthMap& map = kind ? moonMap : spotMap;
            SCOPED_TRACE(kind ? "directional" : "spot");
            StaticEncodeOptions o{frustum.nearPlane, frustum.farPlane, {}};
            auto words = encodeStatic(method, map, o);
            ASSERT_TRUE(words.ok()) << words.error();
            // Put the encoding at a non-zero base so the decoders' base offsets are exercised.
            const uint32_t base = 37;
            std::vector<uint32_t> all(base, 0xDEADBEEFu);
            all.insert(all.end(), words->begin(), words->end());
            Buffer in = createBuffer(d, all.size() * 4, kStorageBufferUsage, "decode_in");
            upload(in, all.data(), all.size() * 4);
            uint32_t perColumn = method == StaticMethod::CPVS ? (res + 31) / 32 : 1;
            size_t outWords = size_t(res) * res * perColumn;
            Buffer out = createBuffer(d, outWords * 4, kStorageBufferUsage, "decode_out");
            const ml::gpu::StaticDecodePush push{uint32_t(method), base, res, 0};
            VkCommandBuffer cmd = d.beginOneTime();
            dispatch(d, cmd, program, res, res, push,
                     {ML_BIND(ML_DECODE_WORDS, in), ML_BIND(ML_DECODE_OUT, out)});
            fullBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_2_HOST_BIT);
            d.endOneTime(cmd);
            const uint32_t* gpu = out.as<uint32_t>();
            uint64_t compared = 0;
            for (uint32_t y = 0; y < res; ++y)
                for (uint32_t x = 0; x < res; ++x) {
                    if (method != StaticMethod::CPVS) {
                        uint32_t cpu = lookupStaticDepth(method, all.data(), base, x, y);
                        ASSERT_EQ(gpu[y * res + x], cpu)
                            << staticMethodName(method) << " texel " << x << "," << y;
                        ++compared;
                        continue;
                    }
                    for (uint32_t s = 0; s < res; ++s) {
                        bool g = (gpu[(y * res + x) * perColumn + s / 32] >> (s % 32)) & 1u;
                        bool c = cpvsShadowedVoxel(all.data(), base, int32_t(x), int32_t(y), int32_t(s));
                        ASSERT_EQ(g, c) << "cpvs voxel " << x << "," << y << "," << s;
                        ++compared;
                    }
                }
            std::printf("  %s %s: %llu values identical\n", kind ? "directional" : "spot",
                        staticMethodName(method), (unsigned long long)compared);
            destroyBuffer(d, in);
            destroyBuffer(d, out);
        }
    destroyProgram(d, program);
    destroyShader(d, shader);
    EXPECT_EQ(validationErrors(), 0u);
}

// Every visible static spot light gets a DAG-MH (or CPVS) bake; the evaluation pass's HDR output is
// compared with the CPU reference (shading.h + static_visibility.cpp) on sampled pixels.
// byLevel: MH, MMH, DAG-MH and CPVS take the level shadowLevelStep picks for the pixel (setShadowFilter); the
// CPU twin gets the same footprint, and some pixels must see another visibility than at the finest level.
void checkEvaluationWithShadows(StaticMethod method, uint32_t pcf, bool byLevel = false) {
    auto m = makeModule();
    auto scene = loadScene("night-city", 64, 2);
    ASSERT_TRUE(scene.ok()) << scene.error();
    ASSERT_TRUE(bindScene(*m, scene.value()).ok());
    ASSERT_TRUE(m->createTargets(256, 144).ok());
    ASSERT_TRUE(m->setShadowFilter(pcf, byLevel).ok());
    // Look down at the first street lamp's pool from above, so its bench, bollard and pole shadows
    // fill many pixels.
    for (const Light& l : scene->lights)
        if (!l.dynamic && l.type == LightKind::Spot && l.direction.y < -0.9f) {
            glm::vec3 ground = l.position + l.direction * (l.position.y / -l.direction.y);
            CameraDesc cam;
            cam.position = ground + glm::vec3(4.0f, 9.0f, 5.0f);
            cam.target = ground;
            ASSERT_TRUE(m->setCamera(cam).ok());
            break;
        }
    CasterTriangles casters = castersFromScene(scene.value());
    uint32_t baked = 0;
    for (uint32_t i = 0; i < scene->lights.size(); ++i) {
        const Light& l = scene->lights[i];
        if (l.dynamic || l.type != LightKind::Spot) continue;
        LightFrustum f = spotLightFrustum(l);
        // By level: maps 4x finer, so that texels of a quarter pixel (shadowLevelStep) are coarser levels.
        DualDepthMap map = rasterizeDual(casters, f, byLevel ? 1024 : 256);
        auto words = encodeStatic(method, map, {f.nearPlane, f.farPlane, {}});
        ASSERT_TRUE(words.ok()) << words.error();
        ASSERT_TRUE(m->setStaticShadow(i, {method, f, words.value()}).ok());
        ++baked;
    }
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
    std::vector<uint32_t> wordsRead = readBufferAs<uint32_t>(*impl.device, impl.staticWords); // GPU-only
    auto* words = wordsRead.data();
    uint32_t checked = 0, shadowed = 0, differ = 0, levelChanged = 0;
    for (uint32_t y = 0; y < fc.size.y; ++y)
        for (uint32_t x = 0; x < fc.size.x; ++x) {
            size_t i = size_t(y) * fc.size.x + x;
            if (!gpu::hasSurface(depth[i])) continue;
            glm::vec3 P = gpu::worldFromPixel(x, y, depth[i], fc.invViewProj, fc.size);
            glm::vec3 N = glm::normalize(glm::vec3(half4(normal, i)));
            glm::vec3 a = glm::vec3(albedo[i * 4], albedo[i * 4 + 1], albedo[i * 4 + 2]) / 255.0f;
            glm::vec3 V = glm::normalize(glm::vec3(fc.cameraPosition) - P);
            glm::vec3 expected = a * glm::vec3(fc.ambient);
            uint32_t s = sliceOf(gpu::linearDepth(depth[i], fc.depth), impl.lastSliceFar, fc.cluster.x);
            uint32_t c = ((y / ML_TILE_SIZE) * fc.size.z + x / ML_TILE_SIZE) * fc.cluster.x + s;
            bool anyShadow = false;
            for (uint32_t k = 0; k < ranges[c].y; ++k) {
                const gpu::GpuLight& L = impl.lastLights[pool[ranges[c].x + k]];
                glm::vec3 col = gpu::shadeLight(L, P, N, V, a);
                if (col == glm::vec3(0.0f)) continue;
                const float f2 = gpu::shadowFootprint2(glm::vec3(fc.cameraPosition), P, fc.cameraPosition.w);
                float vis = lightStaticVisibility(L, impl.lastShadowRecords(), words, P, N, f2);
                levelChanged += vis != lightStaticVisibility(L, impl.lastShadowRecords(), words, P, N, 0.0f);
                anyShadow |= vis < 1.0f;
                expected += col * vis;
            }
            shadowed += anyShadow;
            glm::vec3 got = glm::vec3(half4(hdr, i));
            bool same = true;
            for (int k = 0; k < 3; ++k)
                same &= std::abs(got[k] - expected[k]) <= 2e-3f * std::abs(expected[k]) + 2e-4f;
            differ += !same;
            ++checked;
        }
    std::printf("  %s pcf %u%s: %u lights baked, %u samples, %u in some shadow, %u differ; %u light-pixel "
                "visibilities other than the finest level's\n",
                staticMethodName(method), pcf, byLevel ? " by level" : "", baked, checked, shadowed, differ,
                levelChanged);
    if (byLevel) {
        EXPECT_GT(levelChanged, 100u) << "the level filter must reach coarser levels on this view";
    } else {
        EXPECT_EQ(levelChanged, 0u);
    }
    EXPECT_GT(baked, 10u);
    EXPECT_GT(shadowed, 200u) << "too few shadowed samples for the comparison to mean anything";
    // Float rounding of a receiver's texel or slice may flip a tap exactly on a boundary.
    EXPECT_LE(differ, checked / 500 + 1);
    EXPECT_EQ(validationErrors(), 0u);
}

// DAG-MH with 5x5 PCF takes the hierarchical path (taps share the traversal prefix).
TEST(GpuStatic, EvaluationWithDagMhPcf5x5MatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::DAGMH, 2);
}
TEST(GpuStatic, EvaluationWithDagMhOneTapMatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::DAGMH, 0);
}
TEST(GpuStatic, EvaluationWithMhPcf5x5MatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::MH, 2);
}
TEST(GpuStatic, EvaluationWithMhByLevel3x3MatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::MH, 1, true);
}
TEST(GpuStatic, EvaluationWithMmhByLevelOneTapMatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::MMH, 0, true);
}
TEST(GpuStatic, EvaluationWithDagMhByLevel3x3MatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::DAGMH, 1, true);
}
TEST(GpuStatic, EvaluationWithDagMhByLevelOneTapMatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::DAGMH, 0, true);
}
TEST(GpuStatic, EvaluationWithCpvsPcf3x3MatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::CPVS, 1);
}
TEST(GpuStatic, EvaluationWithCpvsByLevel3x3MatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::CPVS, 1, true);
}
TEST(GpuStatic, EvaluationWithCpvsByLevelOneTapMatchesCpu) {
    checkEvaluationWithShadows(StaticMethod::CPVS, 0, true);
}

} // namespace ml::test
