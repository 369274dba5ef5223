// The camera (engine/camera.h): reversed-Z depth precision on far receivers, host view/projection
// matrices, sub-pixel jitter, and the refusal of matrices the module cannot use.
#include "gpu_test_util.h"

#include "engine/camera.h"
#include "shaders/shared/light_math.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>

namespace ml::test {

namespace {

// A 2 km ground square at y = 0 (two triangles) and a few boxes: receivers from 1 m to 1 km away.
void addGround(Module& m) {
    std::vector<MeshVertex> v = {{{-1000, 0, -1000}, {0, 1, 0}},
                                 {{-1000, 0, 1000}, {0, 1, 0}},
                                 {{1000, 0, 1000}, {0, 1, 0}},
                                 {{1000, 0, -1000}, {0, 1, 0}}};
    std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
    auto mesh = m.addMesh({v, idx, false, "ground"});
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    ASSERT_TRUE(m.addInstance(mesh.value(), glm::mat4(1.0f), glm::vec3(0.5f), false).ok());
}

std::vector<float> depthImage(Module& m) {
    return toFloats(readImage(m, internals(m).targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
}

} // namespace

// Receivers on a ground plane 20-1000 m away, reconstructed from the module's D32 depth buffer (as every
// pass does: worldFromPixel through invViewProj in float), against the exact hit of the pixel's ray
// (double precision). Reversed Z keeps them within millimetres at every distance. The same points
// through a standard-Z D32 value (simulated on the CPU: the exact depth rounded to float, reconstructed
// through the standard projection's inverse) are printed beside them: that is the error this project's
// G-buffer had before, centimetres at 100-200 m.
TEST(GpuCamera, ReversedZReceiversStayOnTheSurface) {
    auto m = makeModule();
    addGround(*m);
    ASSERT_TRUE(m->createTargets(320, 180).ok());
    CameraDesc cam{{0, 1.8f, 0}, {0, 1.4f, -100}, {0, 1, 0}, 1.0f, 0.1f, 1000.0f};
    ASSERT_TRUE(m->setCamera(cam).ok());
    renderFrame(*m);
    const auto& fc = internals(*m).lastConstants;
    const auto depth = depthImage(*m);

    const glm::dmat4 inv = glm::inverse(glm::dmat4(fc.viewProj));
    glm::mat4 fwd = glm::perspectiveRH_ZO(cam.fovY, 320.0f / 180.0f, cam.nearPlane, cam.farPlane);
    fwd[1][1] *= -1.0f;
    const glm::mat4 fwdViewProj = fwd * glm::lookAt(toGlm(cam.position), toGlm(cam.target), toGlm(cam.up));
    const glm::mat4 fwdInv = glm::inverse(fwdViewProj);
    // Bins by distance: [20, 100), [100, 250), [250, 1000) m.
    const double edges[4] = {20, 100, 250, 1000};
    double worst[3] = {0, 0, 0}, worstStd[3] = {0, 0, 0};
    uint32_t counted[3] = {0, 0, 0};
    for (uint32_t y = 0; y < fc.size.y; ++y)
        for (uint32_t x = 0; x < fc.size.x; ++x) {
            const float d = depth[size_t(y) * fc.size.x + x];
            if (!gpu::hasSurface(d)) continue;
            const double nx = (x + 0.5) / fc.size.x * 2 - 1, ny = (y + 0.5) / fc.size.y * 2 - 1;
            glm::dvec4 a = inv * glm::dvec4(nx, ny, 1.0, 1.0), b = inv * glm::dvec4(nx, ny, 0.5, 1.0);
            const glm::dvec3 o = glm::dvec3(a) / a.w, e = glm::dvec3(b) / b.w;
            const glm::dvec3 dir = glm::normalize(e - o);
            if (!(dir.y < -1e-6)) continue;
            const glm::dvec3 hit = o + dir * (-o.y / dir.y);
            const double dist = glm::length(hit - glm::dvec3(toGlm(cam.position)));
            int bin = dist < edges[1] ? 0 : dist < edges[2] ? 1 : 2;
            if (dist < edges[0] || dist >= edges[3]) continue;
            const glm::vec3 p = gpu::worldFromPixel(x, y, d, fc.invViewProj, fc.size);
            worst[bin] = std::max(worst[bin], glm::length(glm::dvec3(p) - hit));
            glm::vec4 c = fwdViewProj * glm::vec4(glm::vec3(hit), 1.0f);
            const float dStd = float(double(c.z) / c.w);
            const glm::vec3 q = gpu::worldFromPixel(x, y, dStd, fwdInv, fc.size);
            worstStd[bin] = std::max(worstStd[bin], glm::length(glm::dvec3(q) - hit));
            ++counted[bin];
        }
    for (int b = 0; b < 3; ++b) {
        std::printf(
            "  receivers %4.0f-%4.0f m: %5u, worst error reversed Z %.2f mm (GPU), standard Z %.1f mm "
            "(simulated)\n",
            edges[b], edges[b + 1], counted[b], worst[b] * 1e3, worstStd[b] * 1e3);
        EXPECT_GT(counted[b], 100u) << "bin " << b;
    }
    EXPECT_LT(worst[0], 0.002);
    EXPECT_LT(worst[1], 0.005);
    EXPECT_LT(worst[2], 0.02);
    // The simulation leaves out the rasteriser's interpolation, which standard Z's d -> 1 amplifies too;
    // beyond 250 m the rounding alone is over 10x reversed Z's whole error.
    EXPECT_GT(worstStd[2], 10.0 * worst[2]) << "the comparison shows no difference: check the simulation";
    EXPECT_EQ(validationErrors(), 0u);
}

// The host's own matrices built like the module's give the same frame, bit for bit, and
// viewProjection() returns what the passes used.
TEST(GpuCamera, HostMatricesEqualTheDescribedCamera) {
    auto scene = loadScene("night-city", 64, 2);
    ASSERT_TRUE(scene.ok()) << scene.error();
    std::vector<uint8_t> images[2];
    for (int run = 0; run < 2; ++run) {
        auto m = makeModule();
        ASSERT_TRUE(bindScene(*m, scene.value()).ok());
        ASSERT_TRUE(m->createTargets(160, 90).ok());
        const CameraDesc cam = toCameraDesc(scene.value().camera);
        if (run == 0) {
            ASSERT_TRUE(m->setCamera(cam).ok());
        } else {
            const CameraMatrices cm = cameraMatrices(cam, 160.0f / 90.0f);
            auto r = m->setCameraMatrices(cm.view, cm.projection);
            ASSERT_TRUE(r.ok()) << r.error();
            // What the module read back out of the matrices.
            const CameraDesc& got = internals(*m).camera;
            EXPECT_NEAR(got.nearPlane, cam.nearPlane, 1e-4f * cam.nearPlane);
            EXPECT_NEAR(got.farPlane, cam.farPlane, 1e-3f * cam.farPlane);
            EXPECT_NEAR(got.fovY, cam.fovY, 1e-5f);
            EXPECT_LT(glm::length(toGlm(got.position) - toGlm(cam.position)), 1e-3f);
        }
        renderFrame(*m);
        const glm::mat4 vp = toGlm(m->viewProjection());
        EXPECT_EQ(std::memcmp(&vp, &internals(*m).lastConstants.viewProj, sizeof(vp)), 0);
        ASSERT_TRUE(m->readOutput(images[run]).ok());
        EXPECT_EQ(validationErrors(), 0u);
    }
    ASSERT_EQ(images[0].size(), images[1].size());
    size_t differ = 0;
    for (size_t i = 0; i < images[0].size(); ++i) differ += images[0][i] != images[1][i];
    // Matrices rebuilt from the same inputs: equal; near/far/fov read back from them may round in
    // the last bit, which moves cluster slice boundaries, not the shading.
    EXPECT_EQ(differ, 0u);
}

// A one-pixel jitter moves the G-buffer by one pixel: the jittered depth at (x + 1, y) equals the plain
// depth at (x, y) (up to the rasteriser's rounding at edges), and it differs where it stands.
TEST(GpuCamera, JitterShiftsTheGBuffer) {
    auto scene = loadScene("night-city", 16, 2);
    ASSERT_TRUE(scene.ok()) << scene.error();
    auto m = makeModule();
    ASSERT_TRUE(bindScene(*m, scene.value()).ok());
    ASSERT_TRUE(m->createTargets(160, 90).ok());
    CameraDesc cam = toCameraDesc(scene.value().camera);
    ASSERT_TRUE(m->setCamera(cam).ok());
    renderFrame(*m);
    const auto plain = depthImage(*m);
    cam.jitter = {1.0f, 0.0f};
    ASSERT_TRUE(m->setCamera(cam).ok());
    renderFrame(*m);
    const auto shifted = depthImage(*m);
    size_t same = 0, moved = 0, total = 0;
    for (uint32_t y = 0; y < 90; ++y)
        for (uint32_t x = 0; x + 1 < 160; ++x) {
            const float a = plain[y * 160 + x], b = shifted[y * 160 + x + 1], c = shifted[y * 160 + x];
            ++total;
            same += std::abs(a - b) <= 1e-5f * std::max(std::abs(a), 1e-6f);
            moved += std::abs(a - c) > 1e-5f * std::max(std::abs(a), 1e-6f);
        }
    std::printf("  jitter (1, 0): %zu of %zu pixels equal one pixel over, %zu differ in place\n", same, total,
                moved);
    EXPECT_GT(same, total * 97 / 100);
    EXPECT_GT(moved, total / 20);
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuCamera, UnusableMatricesAreRefusedWithAReason) {
    auto m = makeModule();
    const CameraDesc cam{{0, 2, 5}, {0, 0, 0}, {0, 1, 0}, 1.0f, 0.1f, 100.0f};
    const CameraMatrices good = cameraMatrices(cam, 16.0f / 9.0f);
    ASSERT_TRUE(m->setCameraMatrices(good.view, good.projection, {0.5f, -0.5f}).ok());
    auto refused = [&](glm::mat4 view, glm::mat4 proj, glm::vec2 jitter, const char* word) {
        auto r = m->setCameraMatrices(view, proj, jitter);
        ASSERT_FALSE(r.ok()) << word;
        EXPECT_NE(r.error().find(word), std::string::npos) << r.error();
    };
    glm::mat4 nan = good.view;
    nan[3][0] = std::nanf("");
    refused(nan, good.projection, {}, "not finite");
    refused(glm::scale(good.view, glm::vec3(2.0f)), good.projection, {}, "rigid");
    glm::mat4 standard = glm::perspectiveRH_ZO(1.0f, 16.0f / 9.0f, 0.1f, 100.0f);
    standard[1][1] *= -1.0f;
    refused(good.view, standard, {}, "standard Z");
    glm::mat4 infinite = good.projection;
    infinite[2][2] = 0.0f;
    infinite[3][2] = 0.1f;
    refused(good.view, infinite, {}, "infinite far");
    glm::mat4 yUp = good.projection;
    yUp[1][1] *= -1.0f;
    refused(good.view, yUp, {}, "y must point down");
    // Both problems of an infinite reversed-Z projection with y up, in one line.
    glm::mat4 infiniteYUp = infinite;
    infiniteYUp[1][1] *= -1.0f;
    refused(good.view, infiniteYUp, {},
            "y must point down (Vulkan clip space): negate glm's [1][1]; it has an infinite far plane");
    glm::mat4 leftHanded = good.projection;
    leftHanded[2][3] = 1.0f;
    refused(good.view, leftHanded, {}, "right-handed");
    refused(good.view, good.projection, {2.0f, 0.0f}, "jitter");
    refused(good.view, good.projection, {0.0f, std::nanf("")}, "jitter");
    CameraDesc jittery = cam;
    jittery.jitter = {0.0f, -1.5f};
    EXPECT_FALSE(m->setCamera(jittery).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace ml::test
