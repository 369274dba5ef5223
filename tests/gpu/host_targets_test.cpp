// Host targets: setTargets checks every target against HostTargets' table and refuses a
// wrong one with one line; HDR output into a host image validates (it used to leave a never-transitioned
// 1x1 stub bound: InvalidImageLayout every frame) and is switchable per frame without rebuilding the
// scene; Fenced timing with a host command buffer is refused instead of reading an undrawn G-buffer.
#include "gpu_test_util.h"

#include "engine/manylights_diagnostics.h"
#include "shaders/shared/brdf.h"

namespace ml::test {
namespace {

constexpr uint32_t kW = 32, kH = 18;
constexpr float kDepth = 0.02f; // reversed Z, near 0.1: a wall ~5 m in front of the camera

struct HostGBuffer {
    Image depth, normal, albedo, ldr, hdr;
    HostImage host(const Image& i, VkImageUsageFlags usage) const {
        return {i.image, i.view, i.format, {i.width, i.height}, usage};
    }
    HostTargets targets(bool hdrOut) const {
        HostTargets t;
        t.width = kW;
        t.height = kH;
        t.depth = host(depth, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
        t.normal = host(normal, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
        t.albedo = host(albedo, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT);
        t.output = hdrOut ? host(hdr, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT)
                          : host(ldr, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
        return t;
    }
};

// A host's G-buffer as uploaded images: a wall facing the camera (normal +Z), albedo 0.5, already in
// SHADER_READ_ONLY_OPTIMAL; outputs in GENERAL.
HostGBuffer makeGBuffer(Module& m) {
    Device& d = deviceOf(m);
    HostGBuffer g;
    const auto sampled = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    g.depth = createImage(d, kW, kH, VK_FORMAT_D32_SFLOAT, sampled, "host_depth");
    g.normal = createImage(d, kW, kH, VK_FORMAT_R16G16B16A16_SFLOAT, sampled, "host_normal");
    g.albedo = createImage(d, kW, kH, VK_FORMAT_R8G8B8A8_UNORM, sampled, "host_albedo");
    const auto storage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    g.ldr = createImage(d, kW, kH, VK_FORMAT_R8G8B8A8_UNORM, storage, "host_ldr");
    g.hdr = createImage(d, kW, kH, VK_FORMAT_R16G16B16A16_SFLOAT, storage, "host_hdr");
    const size_t n = size_t(kW) * kH;
    std::vector<float> depth(n, kDepth);
    std::vector<uint64_t> normal(n, uint64_t(glm::packHalf2x16({0.0f, 0.0f})) |
                                        (uint64_t(glm::packHalf2x16({1.0f, 0.0f})) << 32));
    std::vector<uint32_t> albedo(n, 0xff808080u);
    const VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    uploadImage(d, g.depth, 0, 0, depth.data(), n * 4, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    uploadImage(d, g.normal, 0, 0, normal.data(), n * 8, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    uploadImage(d, g.albedo, 0, 0, albedo.data(), n * 4, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    std::vector<uint8_t> zeros(n * 8, 0);
    uploadImage(d, g.ldr, 0, 0, zeros.data(), n * 4, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    uploadImage(d, g.hdr, 0, 0, zeros.data(), n * 8, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    return g;
}

void destroyGBuffer(Module& m, HostGBuffer& g) {
    vkQueueWaitIdle(deviceOf(m).queue);
    for (Image* i : {&g.depth, &g.normal, &g.albedo, &g.ldr, &g.hdr}) destroyImage(deviceOf(m), *i);
}

std::unique_ptr<Module> makeHostModule(bool hdr, TimingChoice timing = TimingChoice::Auto) {
    resetValidationCounters();
    ModuleOptions o;
    o.device.validation = true;
    o.hdrOutput = hdr;
    o.timing = timing;
    auto m = Module::create(o);
    EXPECT_TRUE(m.ok()) << m.error();
    if (!m) return nullptr;
    LightDesc l;
    l.kind = LightKind::Point;
    l.position = {0.0f, 0.0f, 3.0f};
    l.range = 10.0f;
    l.intensity = 5.0f;
    EXPECT_TRUE(m.value()->addLight(l).ok());
    EXPECT_TRUE(m.value()->setCamera({{0, 0, 5}, {0, 0, 0}}).ok());
    return std::move(m.value());
}

TEST(HostTargets, HdrAndLdrIntoHostImagesValidateAndAgree) {
    auto m = makeHostModule(/*hdr*/ true);
    ASSERT_TRUE(m);
    HostGBuffer g = makeGBuffer(*m);
    ASSERT_TRUE(m->setTargets(g.targets(true)).ok());
    // No full-size image of the module's own behind host targets: 1x1 stubs only.
    EXPECT_EQ(internals(*m).hdr.width, 1u);
    EXPECT_EQ(internals(*m).output.width, 1u);
    for (int frame = 0; frame < 3; ++frame) renderFrame(*m);
    EXPECT_EQ(validationErrors(), 0u) << "HDR into a host image";
    auto hdr = readImage(*m, g.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    // The same frame in LDR, switched with the targets (the scene, lights and camera stay).
    ASSERT_FALSE(m->setHdrOutput(false).ok()); // the current host output is RGBA16F: refused
    HostTargets ldr = g.targets(false);
    ldr.hdrOutput = false;
    auto r = m->setTargets(ldr);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_FALSE(m->hdrOutput());
    renderFrame(*m);
    auto tone = readImage(*m, g.ldr, 4, VK_IMAGE_LAYOUT_GENERAL);
    const float exposure = 3.0f;
    int lit = 0;
    for (size_t i = 0; i < size_t(kW) * kH; ++i) {
        glm::vec3 h = glm::vec3(half4(hdr, i));
        ASSERT_TRUE(std::isfinite(h.x) && h.x > 0.0f) << i;
        glm::vec3 want = gpu::toneMap(h * exposure);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(tone[i * 4 + c] / 255.0f, want[c], 1.5f / 255.0f) << i;
        lit += h.x > 0.02f; // ambient x albedo is 0.01
    }
    EXPECT_GT(lit, int(kW * kH) / 2) << "the wall under the point light is lit";
    EXPECT_EQ(validationErrors(), 0u);
    destroyGBuffer(*m, g);
}

TEST(HostTargets, RefusesEachWrongTargetWithOneLine) {
    auto m = makeHostModule(/*hdr*/ false);
    ASSERT_TRUE(m);
    HostGBuffer g = makeGBuffer(*m);
    const HostTargets good = g.targets(false);
    struct Case {
        const char* what;
        std::function<void(HostTargets&)> mutate;
        const char* message;
    };
    const Case cases[] = {
        {"output without STORAGE", [](HostTargets& t) { t.output.usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT; },
         "setTargets: output: usage lacks STORAGE"},
        {"sRGB output", [](HostTargets& t) { t.output.format = VK_FORMAT_R8G8B8A8_SRGB; },
         "setTargets: output: format R8G8B8A8_SRGB, want R8G8B8A8_UNORM"},
        {"albedo without SAMPLED",
         [](HostTargets& t) { t.albedo.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT; },
         "setTargets: albedo: usage lacks SAMPLED"},
        {"D16 depth", [](HostTargets& t) { t.depth.format = VK_FORMAT_D16_UNORM; },
         "setTargets: depth: format D16_UNORM, want D32_SFLOAT"},
        {"RGBA8 normals", [](HostTargets& t) { t.normal.format = VK_FORMAT_R8G8B8A8_UNORM; },
         "setTargets: normal: format R8G8B8A8_UNORM, want R16G16B16A16_SFLOAT"},
        {"RGBA16F output in LDR mode", [&](HostTargets& t) { t.output = g.targets(true).output; },
         "setTargets: output: format R16G16B16A16_SFLOAT, want R8G8B8A8_UNORM"},
        {"claimed size twice the images",
         [](HostTargets& t) {
             t.width *= 2;
             t.height *= 2;
         },
         "setTargets: depth: the image is 32x18, smaller than the claimed 64x36"},
        {"no view", [](HostTargets& t) { t.normal.view = VK_NULL_HANDLE; },
         "setTargets: normal: the image and its view are both required"},
        {"no size", [](HostTargets& t) { t.width = 0; }, "setTargets: size 0x18 is outside"},
    };
    for (const Case& c : cases) {
        HostTargets t = good;
        c.mutate(t);
        auto r = m->setTargets(t);
        ASSERT_FALSE(r.ok()) << c.what;
        EXPECT_EQ(r.error().rfind(c.message, 0), 0u) << c.what << ": " << r.error();
        EXPECT_EQ(r.error().find('\n'), std::string::npos) << c.what;
    }
    // Refusals leave nothing behind: the good targets then render with no message.
    ASSERT_TRUE(m->setTargets(good).ok());
    renderFrame(*m);
    EXPECT_EQ(validationErrors(), 0u);
    destroyGBuffer(*m, g);
}

TEST(HostTargets, OwnTargetsSwitchHdrPerFrame) {
    auto m = makeHostModule(/*hdr*/ false);
    ASSERT_TRUE(m);
    ASSERT_TRUE(m->createTargets(kW, kH).ok());
    renderFrame(*m);
    const uint64_t waits = diag::deviceWaitCount(*m);
    std::vector<uint8_t> rgba;
    ASSERT_TRUE(m->readOutput(rgba).ok());
    EXPECT_EQ(m->outputImage(), internals(*m).output.image);
    ASSERT_TRUE(m->setHdrOutput(true).ok());
    renderFrame(*m);
    EXPECT_EQ(m->outputImage(), internals(*m).hdr.image);
    EXPECT_FALSE(m->readOutput(rgba).ok());
    ASSERT_TRUE(m->setHdrOutput(false).ok());
    renderFrame(*m);
    EXPECT_TRUE(m->readOutput(rgba).ok());
    EXPECT_EQ(diag::deviceWaitCount(*m), waits) << "a mode switch waits for nothing";
    EXPECT_EQ(validationErrors(), 0u);
}

// Fenced timing submits each pass on its own: a host G-buffer recorded into the host's command buffer
// would not be drawn yet. Refused; record(VK_NULL_HANDLE) after the host's G-buffer work gives the same
// picture as Timestamps mode.
TEST(HostTargets, FencedTimingRefusesAHostCommandBuffer) {
    std::vector<uint8_t> reference;
    {
        auto m = makeHostModule(false);
        ASSERT_TRUE(m);
        HostGBuffer g = makeGBuffer(*m);
        ASSERT_TRUE(m->setTargets(g.targets(false)).ok());
        renderFrame(*m);
        reference = readImage(*m, g.ldr, 4, VK_IMAGE_LAYOUT_GENERAL);
        EXPECT_EQ(validationErrors(), 0u);
        destroyGBuffer(*m, g);
    }
    auto m = makeHostModule(false, TimingChoice::Fenced);
    ASSERT_TRUE(m);
    HostGBuffer g = makeGBuffer(*m);
    ASSERT_TRUE(m->setTargets(g.targets(false)).ok());
    Device& d = deviceOf(*m);
    VkCommandBuffer cmd = d.beginOneTime();
    auto r = m->record(cmd);
    d.endOneTime(cmd);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().rfind("record: Fenced timing with host targets", 0), 0u) << r.error();
    for (int frame = 0; frame < 2; ++frame) {
        auto ok = m->record(VK_NULL_HANDLE); // the host's G-buffer was uploaded and waited for
        ASSERT_TRUE(ok.ok()) << ok.error();
    }
    EXPECT_EQ(readImage(*m, g.ldr, 4, VK_IMAGE_LAYOUT_GENERAL), reference);
    m->collect();
    EXPECT_EQ(m->takeReports().size(), 2u);
    EXPECT_EQ(validationErrors(), 0u);
    destroyGBuffer(*m, g);
}

// Teardown: a host that detaches its targets and then destroys them gets a one-line refusal from
// record(), not a descriptor write of destroyed views (a crash, or validation errors); new targets,
// the host's or the module's own, render again, the same image as before.
TEST(HostTargets, DetachedTargetsAreRefusedUntilReplaced) {
    auto m = makeHostModule(false);
    ASSERT_TRUE(m);
    HostGBuffer g = makeGBuffer(*m);
    ASSERT_TRUE(m->setTargets(g.targets(false)).ok());
    renderFrame(*m);
    const std::vector<uint8_t> before = readImage(*m, g.ldr, 4, VK_IMAGE_LAYOUT_GENERAL);
    m->detachTargets();
    destroyGBuffer(*m, g); // waits for the frame, then destroys every image and view
    Device& d = deviceOf(*m);
    for (int attempt = 0; attempt < 2; ++attempt) {
        VkCommandBuffer cmd = d.beginOneTime();
        auto r = m->record(cmd);
        d.endOneTime(cmd);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().rfind("record: no targets: detachTargets() released them", 0), 0u) << r.error();
        EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
        m->detachTargets(); // a second call changes nothing
    }
    HostGBuffer again = makeGBuffer(*m);
    ASSERT_TRUE(m->setTargets(again.targets(false)).ok());
    renderFrame(*m);
    EXPECT_EQ(readImage(*m, again.ldr, 4, VK_IMAGE_LAYOUT_GENERAL), before);
    // The module's own targets detach the same way.
    ASSERT_TRUE(m->createTargets(kW, kH).ok());
    renderFrame(*m);
    m->detachTargets();
    VkCommandBuffer cmd = d.beginOneTime();
    EXPECT_FALSE(m->record(cmd).ok());
    d.endOneTime(cmd);
    ASSERT_TRUE(m->createTargets(kW, kH).ok());
    renderFrame(*m);
    EXPECT_EQ(validationErrors(), 0u);
    destroyGBuffer(*m, again);
}

// The optional material target: checked against its row (R8G8_UNORM, SAMPLED, the
// claimed size), refused with one line; given, the host's wall is shaded with GGX exactly as the CPU
// reference (shadeLightPbr) says, and without it as before (Blinn-Phong).
TEST(HostTargets, MaterialTargetIsCheckedAndShadesGgx) {
    auto m = makeHostModule(/*hdr*/ true);
    ASSERT_TRUE(m);
    HostGBuffer g = makeGBuffer(*m);
    Device& d = deviceOf(*m);
    const auto sampled = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    Image material = createImage(d, kW, kH, VK_FORMAT_R8G8_UNORM, sampled, "host_material");
    Image small = createImage(d, kW / 2, kH, VK_FORMAT_R8G8_UNORM, sampled, "host_material_small");
    const size_t n = size_t(kW) * kH;
    std::vector<uint16_t> texels(n, uint16_t(102u | (255u << 8))); // roughness 0.4, metalness 1
    const VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    uploadImage(d, material, 0, 0, texels.data(), n * 2, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    uploadImage(d, small, 0, 0, texels.data(), n, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    HostTargets good = g.targets(true);
    good.material = g.host(material, sampled);
    struct Case {
        const char* what;
        std::function<void(HostTargets&)> mutate;
        const char* message;
    };
    const Case cases[] = {
        {"RGBA8 material", [](HostTargets& t) { t.material.format = VK_FORMAT_R8G8B8A8_UNORM; },
         "setTargets: material: format R8G8B8A8_UNORM, want R8G8_UNORM"},
        {"material without SAMPLED", [](HostTargets& t) { t.material.usage = VK_IMAGE_USAGE_STORAGE_BIT; },
         "setTargets: material: usage lacks SAMPLED"},
        {"material smaller than the frame", [&](HostTargets& t) { t.material = g.host(small, sampled); },
         "setTargets: material: the image is 16x18, smaller than the claimed 32x18"},
        {"material view without its image", [](HostTargets& t) { t.material.image = VK_NULL_HANDLE; },
         "setTargets: material: the image and its view are both required"},
    };
    for (const Case& c : cases) {
        HostTargets t = good;
        c.mutate(t);
        auto r = m->setTargets(t);
        ASSERT_FALSE(r.ok()) << c.what;
        EXPECT_EQ(r.error().rfind(c.message, 0), 0u) << c.what << ": " << r.error();
        EXPECT_EQ(r.error().find('\n'), std::string::npos) << c.what;
    }
    auto shade = [&](bool pbr) {
        HostTargets t = good;
        if (!pbr) t.material = {};
        auto r = m->setTargets(t);
        EXPECT_TRUE(r.ok()) << r.error();
        renderFrame(*m);
        return readImage(*m, g.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    };
    for (bool pbr : {true, false}) {
        auto hdr = shade(pbr);
        const auto& fc = internals(*m).lastConstants;
        const gpu::GpuLight& L = internals(*m).lastLights.at(0);
        uint32_t differ = 0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                glm::vec3 P = gpu::worldFromPixel(x, y, kDepth, fc.invViewProj, fc.size);
                glm::vec3 N(0, 0, 1), a(128.0f / 255.0f);
                glm::vec3 V = glm::normalize(glm::vec3(fc.cameraPosition) - P);
                glm::vec3 want = a * glm::vec3(fc.ambient) +
                                 (pbr ? gpu::shadeLightPbr(L, P, N, V, a, 102.0f / 255.0f, 1.0f)
                                      : gpu::shadeLight(L, P, N, V, a));
                glm::vec3 got = glm::vec3(half4(hdr, size_t(y) * kW + x));
                for (int k = 0; k < 3; ++k)
                    differ += !(std::abs(got[k] - want[k]) <= 2e-3f * want[k] + 2e-4f);
            }
        EXPECT_EQ(differ, 0u) << (pbr ? "GGX" : "Blinn-Phong");
    }
    EXPECT_EQ(validationErrors(), 0u);
    vkQueueWaitIdle(d.queue);
    destroyImage(d, material);
    destroyImage(d, small);
    destroyGBuffer(*m, g);
}

} // namespace
} // namespace ml::test
