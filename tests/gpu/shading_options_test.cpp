// Shading options: the evaluation pass's options against its CPU reference on the night city with
// static bakes (module-baked SM 256^2): GGX shading from the module's material target
// (shaders/shared/brdf.h), per-instance receiver opt-out (the G-buffer normal's w), per-light shadow bias
// (GpuShadowRecord.bias), and physical light units (lumen -> candela, EV100 exposure).
#include "gpu_test_util.h"

#include "lights/lights.h"
#include "shaders/shared/brdf.h"
#include "shadows/static/static_visibility.h"

#include <cmath>

namespace ml::test {
namespace {

// The G-buffer, HDR output, cluster lists and static words of the last frame (the buffers are GPU-only:
// read back).
struct FrameImages {
    std::vector<float> depth;
    std::vector<uint8_t> normal, albedo, material, hdr;
    std::vector<glm::uvec2> ranges;
    std::vector<uint32_t> pool, words;
};

FrameImages readFrame(Module& m) {
    auto& impl = internals(m);
    const VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    FrameImages f;
    f.depth = toFloats(readImage(m, impl.targets.depth, 4, ro));
    f.normal = readImage(m, impl.targets.normal, 8, ro);
    f.albedo = readImage(m, impl.targets.albedo, 4, ro);
    f.material = readImage(m, impl.targets.material, 2, ro);
    f.hdr = readImage(m, impl.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    f.ranges = readBufferAs<glm::uvec2>(*impl.device, impl.cull.ranges);
    f.pool = readBufferAs<uint32_t>(*impl.device, impl.cull.pool);
    f.words = readBufferAs<uint32_t>(*impl.device, impl.staticWords);
    return f;
}

struct Expected {
    glm::vec3 hdr{0.0f};
    bool surface = false, receiver = true;
    bool shadowed = false; // some light's visibility < 1 (before the receiver flag)
    bool watchLit = false; // the light with id `watch` shades the pixel (non-zero before visibility)
    float watchVis = 1.0f; // its static visibility
};

// The CPU reference of the evaluation pass at pixel (x, y) of the last frame: ambient plus every light of
// the pixel's cluster, shaded with GGX from the material target (pbr) or Lambert + Blinn-Phong, times its
// static visibility unless the normal's w says the pixel receives no shadows.
Expected reference(const Module::Impl& impl, const FrameImages& f, uint32_t x, uint32_t y, bool pbr,
                   uint32_t watch = ~0u) {
    const auto& fc = impl.lastConstants;
    const size_t i = size_t(y) * fc.size.x + x;
    Expected e;
    e.hdr = glm::vec3(fc.sky);
    if (!gpu::hasSurface(f.depth[i])) return e;
    e.surface = true;
    glm::vec3 P = gpu::worldFromPixel(x, y, f.depth[i], fc.invViewProj, fc.size);
    glm::vec4 n = half4(f.normal, i);
    glm::vec3 N = glm::normalize(glm::vec3(n));
    e.receiver = n.w >= 0.0f;
    glm::vec3 a = glm::vec3(f.albedo[i * 4], f.albedo[i * 4 + 1], f.albedo[i * 4 + 2]) / 255.0f;
    float rough = f.material[i * 2] / 255.0f, metal = f.material[i * 2 + 1] / 255.0f;
    glm::vec3 V = glm::normalize(glm::vec3(fc.cameraPosition) - P);
    e.hdr = a * glm::vec3(fc.ambient);
    const glm::uvec2* ranges = f.ranges.data();
    const uint32_t* pool = f.pool.data();
    const uint32_t* words = f.words.data();
    uint32_t s = sliceOf(gpu::linearDepth(f.depth[i], fc.depth), impl.lastSliceFar, fc.cluster.x);
    uint32_t c = ((y / ML_TILE_SIZE) * fc.size.z + x / ML_TILE_SIZE) * fc.cluster.x + s;
    for (uint32_t k = 0; k < ranges[c].y; ++k) {
        const gpu::GpuLight& L = impl.lastLights[pool[ranges[c].x + k]];
        glm::vec3 col =
            pbr ? gpu::shadeLightPbr(L, P, N, V, a, rough, metal) : gpu::shadeLight(L, P, N, V, a);
        if (col == glm::vec3(0.0f)) continue;
        float vis = lightStaticVisibility(L, impl.lastShadowRecords(), words, P, glm::vec3(n));
        e.shadowed |= vis < 1.0f;
        if (L.info.w == watch) e.watchLit = true, e.watchVis = vis;
        e.hdr += e.receiver ? col * vis : col;
    }
    return e;
}

bool near(glm::vec3 got, glm::vec3 want) {
    for (int k = 0; k < 3; ++k)
        if (!(std::abs(got[k] - want[k]) <= 2e-3f * std::abs(want[k]) + 2e-4f)) return false;
    return true;
}

// The night city, 64 lights, looking down at the first street lamp's pool (its bench, bollard and pole
// shadows fill many pixels), every static spot baked by the module.
std::unique_ptr<Module> cityWithBakes(Scene& scene, bool materials, SceneBinding* bindingOut = nullptr) {
    auto m = makeModule();
    auto loaded = loadScene("night-city", 64, 2);
    EXPECT_TRUE(loaded.ok()) << loaded.error();
    scene = loaded.value();
    auto binding = bindScene(*m, scene);
    EXPECT_TRUE(binding.ok()) << binding.error();
    if (bindingOut) *bindingOut = binding.value();
    EXPECT_TRUE(m->createTargets(256, 144, materials).ok());
    for (const Light& l : scene.lights)
        if (!l.dynamic && l.type == LightKind::Spot && l.direction.y < -0.9f) {
            glm::vec3 ground = l.position + l.direction * (l.position.y / -l.direction.y);
            CameraDesc cam;
            cam.position = ground + glm::vec3(4.0f, 9.0f, 5.0f);
            cam.target = ground;
            EXPECT_TRUE(m->setCamera(cam).ok());
            break;
        }
    auto baked = m->bakeStaticShadows(StaticMethod::SM, 256);
    EXPECT_TRUE(baked.ok() && baked.value() > 10u) << (baked.ok() ? "" : baked.error());
    return m;
}

} // namespace

// GGX from the module's material target: the scene's instances get roughness 0.3..1 and metalness 0, 0.5
// or 1; the HDR output matches shadeLightPbr x static visibility, and differs from the Lambert + Blinn-Phong
// reference (so the GGX path really ran).
TEST(GpuPbr, SampledPixelsMatchCpuGgx) {
    Scene scene;
    SceneBinding b;
    auto m = cityWithBakes(scene, /*materials*/ true, &b);
    for (size_t i = 0; i < b.instances.size(); ++i)
        ASSERT_TRUE(m->setInstanceMaterial(b.instances[i], 0.3f + 0.7f * float(i % 5) / 4.0f,
                                           float((i + 2) % 3) * 0.5f)
                        .ok());
    renderFrame(*m);
    auto& impl = internals(*m);
    FrameImages f = readFrame(*m);
    uint32_t checked = 0, differ = 0, unlikeLegacy = 0, metals = 0;
    for (uint32_t y = 0; y < impl.lastConstants.size.y; ++y)
        for (uint32_t x = 0; x < impl.lastConstants.size.x; ++x) {
            Expected e = reference(impl, f, x, y, /*pbr*/ true);
            if (!e.surface) continue;
            glm::vec3 got = glm::vec3(half4(f.hdr, size_t(y) * impl.lastConstants.size.x + x));
            differ += !near(got, e.hdr);
            glm::vec3 legacy = reference(impl, f, x, y, /*pbr*/ false).hdr;
            unlikeLegacy += glm::length(legacy - got) > 0.1f * glm::length(got) + 1e-3f;
            metals += f.material[(size_t(y) * impl.lastConstants.size.x + x) * 2 + 1] == 255;
            ++checked;
        }
    std::printf("  %u samples, %u differ from GGX, %u unlike Blinn-Phong, %u metal\n", checked, differ,
                unlikeLegacy, metals);
    EXPECT_GT(checked, 10000u);
    EXPECT_GT(metals, 1000u) << "the material target carries the instances' metalness";
    EXPECT_GT(unlikeLegacy, checked / 10) << "GGX shading must be visible";
    EXPECT_LE(differ, checked / 500 + 1); // a PCF tap exactly on a texel boundary may flip
    EXPECT_EQ(validationErrors(), 0u);
}

// Without a material target (the default createTargets) the fallback is unchanged: the same city matches
// the Lambert + Blinn-Phong reference, whatever the instances' materials.
TEST(GpuPbr, WithoutMaterialTargetShadesBlinnPhong) {
    Scene scene;
    SceneBinding b;
    auto m = cityWithBakes(scene, /*materials*/ false, &b);
    for (InstanceId id : b.instances) ASSERT_TRUE(m->setInstanceMaterial(id, 0.3f, 1.0f).ok());
    renderFrame(*m);
    auto& impl = internals(*m);
    FrameImages f = readFrame(*m);
    uint32_t checked = 0, differ = 0;
    for (uint32_t y = 0; y < impl.lastConstants.size.y; y += 2)
        for (uint32_t x = 0; x < impl.lastConstants.size.x; x += 2) {
            Expected e = reference(impl, f, x, y, /*pbr*/ false);
            if (!e.surface) continue;
            differ += !near(glm::vec3(half4(f.hdr, size_t(y) * impl.lastConstants.size.x + x)), e.hdr);
            ++checked;
        }
    EXPECT_GT(checked, 2000u);
    EXPECT_LE(differ, checked / 500 + 1);
    EXPECT_EQ(validationErrors(), 0u);
}

// Receiver opt-out: every even instance receives no shadows; its pixels (normal.w = ML_NOT_A_RECEIVER)
// are lit unshadowed, the others keep their shadows.
TEST(GpuReceiver, OptedOutInstancesAreLitUnshadowed) {
    Scene scene;
    SceneBinding b;
    auto m = cityWithBakes(scene, /*materials*/ false, &b);
    for (size_t i = 0; i < b.instances.size(); ++i)
        ASSERT_TRUE(m->setInstanceShadowReceiving(b.instances[i], i % 2 == 1).ok());
    EXPECT_FALSE(m->setInstanceShadowReceiving(987654, false).ok());
    renderFrame(*m);
    auto& impl = internals(*m);
    FrameImages f = readFrame(*m);
    uint32_t checked = 0, differ = 0, optedOutShadowed = 0, receiverShadowed = 0;
    for (uint32_t y = 0; y < impl.lastConstants.size.y; ++y)
        for (uint32_t x = 0; x < impl.lastConstants.size.x; ++x) {
            Expected e = reference(impl, f, x, y, /*pbr*/ false);
            if (!e.surface) continue;
            differ += !near(glm::vec3(half4(f.hdr, size_t(y) * impl.lastConstants.size.x + x)), e.hdr);
            optedOutShadowed += e.shadowed && !e.receiver;
            receiverShadowed += e.shadowed && e.receiver;
            ++checked;
        }
    std::printf("  %u samples, %u differ, shadowed: %u opted out (lit), %u receivers\n", checked, differ,
                optedOutShadowed, receiverShadowed);
    // Even instances (the ground among them) opt out: 9050 and 84 on lavapipe.
    EXPECT_GT(optedOutShadowed, 1000u) << "opted-out pixels that a shadow would darken";
    EXPECT_GT(receiverShadowed, 40u) << "receivers keep their shadows";
    EXPECT_LE(differ, checked / 500 + 1);
    EXPECT_EQ(validationErrors(), 0u);
}

// Per-light bias: a large depth bias on one light lifts its shadows; every pixel that light does not
// shade keeps its value bit for bit (cluster lists are sorted by light index, so a pixel sums its
// lights in the same order every frame), its own pixels change, and both frames match the reference.
TEST(GpuLightBias, PerLightBiasChangesOnlyThatLight) {
    Scene scene;
    auto m = cityWithBakes(scene, /*materials*/ false);
    renderFrame(*m);
    auto& impl = internals(*m);
    FrameImages before = readFrame(*m);
    // The light that shadows the most samples.
    const glm::uvec4 size = impl.lastConstants.size;
    uint32_t watch = 0, best = 0;
    for (const gpu::GpuLight& L : impl.lastLights) {
        if (L.info.z == ML_NO_SHADOW) continue;
        uint32_t count = 0;
        for (uint32_t y = 0; y < size.y; y += 3)
            for (uint32_t x = 0; x < size.x; x += 3) {
                Expected e = reference(impl, before, x, y, false, L.info.w);
                count += e.watchLit && e.watchVis < 1.0f;
            }
        if (count > best) best = count, watch = L.info.w;
    }
    ASSERT_GT(best, 20u);
    LightDesc l = toLightDesc(scene.lights[watch]);
    l.shadowDepthBias = 60.0f;
    l.shadowNormalBias = 8.0f;
    ASSERT_TRUE(m->setLight(watch, l).ok());
    renderFrame(*m);
    FrameImages after = readFrame(*m);
    uint32_t untouchedSame = 0, untouchedDiffer = 0, watchChanged = 0, differ = 0, checked = 0;
    for (uint32_t y = 0; y < size.y; ++y)
        for (uint32_t x = 0; x < size.x; ++x) {
            const size_t i = size_t(y) * size.x + x;
            Expected e = reference(impl, after, x, y, false, watch);
            if (!e.surface) continue;
            ++checked;
            differ += !near(glm::vec3(half4(after.hdr, i)), e.hdr);
            const bool bitsSame = std::memcmp(&before.hdr[i * 8], &after.hdr[i * 8], 8) == 0;
            if (!e.watchLit) {
                untouchedSame += bitsSame;
                untouchedDiffer += !bitsSame;
            } else {
                watchChanged += !bitsSame;
            }
        }
    std::printf("  light %u: %u pixels it does not shade (%u changed), %u of its pixels changed, %u differ\n",
                watch, untouchedSame + untouchedDiffer, untouchedDiffer, watchChanged, differ);
    EXPECT_EQ(untouchedDiffer, 0u) << "another light's pixels changed";
    EXPECT_GT(untouchedSame, 1000u);
    EXPECT_GT(watchChanged, 20u) << "the bias lifted none of the light's shadows";
    EXPECT_LE(differ, checked / 500 + 1);
    EXPECT_EQ(validationErrors(), 0u);
}

// The static resolution hint: one static spot baked at 64^2 while the call asks 128^2 for the others.
TEST(GpuLightBias, ResolutionHintSetsThatLightsBake) {
    auto m = makeModule();
    auto scene = loadScene("night-city", 32, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    ASSERT_TRUE(bindScene(*m, scene.value()).ok());
    ASSERT_TRUE(m->createTargets(64, 36).ok());
    uint32_t hinted = ~0u;
    for (uint32_t i = 0; i < scene->lights.size() && hinted == ~0u; ++i)
        if (!scene->lights[i].dynamic && scene->lights[i].type == LightKind::Spot) {
            LightDesc l = toLightDesc(scene->lights[i]);
            l.shadowResolution = 64;
            ASSERT_TRUE(m->setLight(i, l).ok());
            hinted = i;
        }
    ASSERT_NE(hinted, ~0u);
    auto baked = m->bakeStaticShadows(StaticMethod::SM, 128);
    ASSERT_TRUE(baked.ok() && baked.value() > 1u) << (baked.ok() ? "" : baked.error());
    renderFrame(*m);
    uint32_t others = 0;
    for (uint32_t i = 0; i < scene->lights.size(); ++i) {
        const gpu::GpuShadowRecord& r = internals(*m).lastShadowRecords()[6 * i];
        if (gpu::shadowRecordMethod(r) == 0) continue;
        EXPECT_EQ(gpu::shadowRecordResolution(r), i == hinted ? 64u : 128u) << "light " << i;
        others += i != hinted;
    }
    EXPECT_GT(others, 0u);
    LightDesc bad;
    bad.shadowResolution = 4;
    EXPECT_FALSE(m->addLight(bad).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuLightBias, BadValuesAreRefusedWithOneLine) {
    auto m = makeModule();
    LightDesc ok;
    for (float bad : {NAN, -0.5f, INFINITY, 65.0f}) {
        for (int which = 0; which < 2; ++which) {
            LightDesc l = ok;
            (which ? l.shadowNormalBias : l.shadowDepthBias) = bad;
            auto r = m->addLight(l);
            ASSERT_FALSE(r.ok()) << bad;
            EXPECT_NE(r.error().find(which ? "shadowNormalBias" : "shadowDepthBias"), std::string::npos)
                << r.error();
            EXPECT_EQ(r.error().find('\n'), std::string::npos);
        }
    }
    LightDesc sun;
    sun.kind = LightKind::Directional;
    sun.unit = LightUnit::Lumen;
    auto r = m->addLight(sun);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("lux"), std::string::npos) << r.error();
    EXPECT_EQ(m->lightCount(), 0u);
    for (float bad : {NAN, -0.1f, 1.5f}) {
        EXPECT_FALSE(m->setInstanceMaterial(0, bad, 0.0f).ok());
    }
    EXPECT_FALSE(m->setExposureEV100(NAN).ok());
    EXPECT_FALSE(m->setExposureEV100(INFINITY).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

// Physical units: Filament's conversions, and a point light of 400 pi lm renders as one of 100 cd; the
// EV100 exposure reaches the frame constants.
TEST(GpuLightUnits, LumenConvertsToCandelaAndEv100SetsExposure) {
    LightDesc point;
    point.kind = LightKind::Point;
    point.unit = LightUnit::Lumen;
    point.intensity = 1000.0f;
    EXPECT_NEAR(lightIntensityCandela(point), 1000.0f / (4.0f * 3.14159265f), 1e-3f);
    LightDesc spot = point;
    spot.kind = LightKind::Spot;
    EXPECT_NEAR(lightIntensityCandela(spot), 1000.0f / 3.14159265f, 1e-3f);
    spot.unit = LightUnit::Candela;
    EXPECT_EQ(lightIntensityCandela(spot), 1000.0f);
    EXPECT_NEAR(toGpuLight(point, 0).colorSinOuter.x, 1000.0f / (4.0f * 3.14159265f), 1e-3f);
    EXPECT_NEAR(exposureFromEV100(0.0f), 1.0f / 1.2f, 1e-7f);
    EXPECT_NEAR(exposureFromEV100(10.0f), 1.0f / (1.2f * 1024.0f), 1e-9f);
    EXPECT_NEAR(ev100FromCamera(1.0f, 1.0f, 100.0f), 0.0f, 1e-6f);
    EXPECT_NEAR(ev100FromCamera(16.0f, 1.0f / 125.0f, 100.0f), std::log2(256.0f * 125.0f), 1e-4f); // 14.97

    auto m = makeModule();
    auto scene = loadScene("night-city", 1, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    scene->lights.clear();
    ASSERT_TRUE(bindScene(*m, scene.value()).ok());
    ASSERT_TRUE(m->createTargets(160, 90).ok());
    LightDesc lamp;
    lamp.kind = LightKind::Point;
    lamp.position = scene->camera.target + glm::vec3(0.0f, 4.0f, 0.0f);
    lamp.range = 30.0f;
    lamp.intensity = 100.0f; // cd
    auto id = m->addLight(lamp);
    ASSERT_TRUE(id.ok()) << id.error();
    ASSERT_TRUE(m->setExposureEV100(2.0f).ok());
    renderFrame(*m);
    EXPECT_FLOAT_EQ(internals(*m).lastConstants.ambient.w, exposureFromEV100(2.0f));
    auto candela = readImage(*m, internals(*m).hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    lamp.unit = LightUnit::Lumen;
    lamp.intensity = 400.0f * 3.14159265f;
    ASSERT_TRUE(m->setLight(id.value(), lamp).ok());
    renderFrame(*m);
    auto lumen = readImage(*m, internals(*m).hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    uint32_t lit = 0;
    for (size_t i = 0; i < size_t(160) * 90; ++i) {
        glm::vec3 a = glm::vec3(half4(candela, i)), b = glm::vec3(half4(lumen, i));
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(b[k], a[k], 1e-3f * a[k] + 1e-6f) << i;
        lit += a.x > 0.05f;
    }
    EXPECT_GT(lit, 500u) << "the lamp must light the street";
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace ml::test
