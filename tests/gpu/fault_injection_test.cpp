// Out of memory is an error, not an abort (gpu/vk_check.h ML_VK_ALLOC): the demo path (create the module,
// add meshes, lights and instances, bake static shadows in the module, set targets, 3 frames, read the
// output, destroy) runs once per allocation point with that one allocation failing. Each run must end in
// an error naming the call and the resource (no abort, no crash) and leave no Vulkan object behind: the
// validation layer's object tracker reports every object still alive at vkDestroyDevice as an error,
// which the test's messenger counts (VerifiesLeaksAreCounted shows that it does).
//
// ctest runs FaultInjection.DemoPathStrided (every ML_FAULT_STRIDE-th point, default 16, plus the first and
// the last: each run creates a module and its pipelines, ~0.3 s on lavapipe) and, labelled `long`,
// FaultInjectionAll (FaultInjection.DISABLED_DemoPathEveryPoint: every point).
#include "gpu_test_util.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdlib>
#include <tuple>

namespace ml::test {
namespace {

struct Outcome {
    bool ok = false;
    std::string error;
    uint64_t points = 0; // allocation points passed
};

// A closed box (outward faces); MeshDesc views the arrays, which live here.
struct Box {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    Box(glm::vec3 lo, glm::vec3 hi) {
        const glm::vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                                {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                                {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
        for (const glm::vec3& p : c) vertices.push_back({{p.x, p.y, p.z}, {0, 1, 0}});
        indices = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                   3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    }
    MeshDesc desc() const { return {vertices, indices, true, "box"}; }
};

// The demo path at tiny sizes. Virtual shadow maps on (small), so their allocations are covered too.
// fenced: TimingChoice::Fenced, whose passes each get their own command buffer and submission.
Outcome runDemoPath(bool fenced = false) {
    Outcome out;
    const uint64_t start = faultInjection::allocationPoints();
    auto finish = [&](bool ok, std::string error) {
        out.ok = ok;
        out.error = std::move(error);
        out.points = faultInjection::allocationPoints() - start;
        return out;
    };
    ModuleOptions o;
    o.device.validation = true;
    o.statistics = true;
    o.vsm.enabled = true;
    o.vsm.resolution = 256;
    o.vsm.pageSize = 32;
    o.vsm.poolPages = 64;
    o.vsm.maxMaps = 8;
    o.vsm.clipLevels = 2;
    o.vsm.maxDrawsPerMip = 64;
    o.vsm.maxMeshletsPerMip = 256;
    if (fenced) o.timing = TimingChoice::Fenced;
    auto created = Module::create(o);
    if (!created) return finish(false, created.error());
    std::unique_ptr<Module> m = std::move(created.value());
    const Box groundBox({-8, -0.1f, -8}, {8, 0, 8}), blockBox({-1, 0, -1}, {1, 2, 1});
    auto ground = m->addMesh(groundBox.desc());
    auto block = m->addMesh(blockBox.desc());
    if (!ground || !block) return finish(false, "addMesh refused a valid mesh");
    for (auto [mesh, at, dynamic] : {std::tuple{ground.value(), glm::vec3(0), false},
                                     std::tuple{block.value(), glm::vec3(1, 0, 0), false},
                                     std::tuple{block.value(), glm::vec3(-3, 0, 2), true}})
        if (!m->addInstance(mesh, glm::translate(glm::mat4(1.0f), at), glm::vec3(0.6f), dynamic))
            return finish(false, "addInstance refused");
    LightDesc spot;
    spot.position = {0, 6, 0};
    spot.range = 12;
    LightDesc point = spot;
    point.kind = LightKind::Point;
    point.position = {3, 3, 3};
    LightDesc moving = spot; // no bake: a virtual shadow map
    moving.position = {-3, 5, 2};
    moving.dynamic = true;
    for (const LightDesc& l : {spot, point, moving})
        if (!m->addLight(l)) return finish(false, "addLight refused");
    if (auto b = m->bakeStaticShadows(StaticMethod::SM, 32); !b) return finish(false, b.error());
    if (auto t = m->createTargets(32, 16); !t) return finish(false, t.error());
    CameraDesc cam;
    cam.position = {0, 4, 10};
    cam.target = {0, 0, 0};
    if (auto c = m->setCamera(cam); !c) return finish(false, c.error());
    for (int f = 0; f < 3; ++f) {
        if (auto r = m->submitFrame(); !r) return finish(false, r.error());
        vkQueueWaitIdle(deviceOf(*m).queue);
        m->collect();
    }
    std::vector<uint8_t> rgba;
    if (auto r = m->readOutput(rgba); !r) return finish(false, r.error());
    return finish(true, "");
}

// Runs the path with point `n` failing; checks error, message and leaks.
void expectCleanFailure(uint64_t n, bool fenced = false) {
    resetValidationCounters();
    faultInjection::failAt(n);
    Outcome o = runDemoPath(fenced); // the module (and its device) is destroyed inside
    faultInjection::failAt(0);
    EXPECT_FALSE(o.ok) << "point " << n << ": the failed allocation was not reported";
    EXPECT_NE(o.error.find("failed: VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos)
        << "point " << n << ": " << o.error;
    EXPECT_NE(o.error.find(" for '"), std::string::npos)
        << "point " << n << ": names no resource: " << o.error;
    EXPECT_EQ(validationErrors(), 0u) << "point " << n << " (" << o.error << "): objects left or misuse";
}

uint64_t countPoints(bool fenced = false) {
    resetValidationCounters();
    faultInjection::failAt(0);
    Outcome o = runDemoPath(fenced);
    EXPECT_TRUE(o.ok) << o.error;
    EXPECT_EQ(validationErrors(), 0u);
    EXPECT_GT(o.points, 50u) << "the path passed fewer allocation points than it makes objects";
    std::printf("fault injection: the demo path (%s timing) passes %llu allocation points\n",
                fenced ? "fenced" : "timestamp", (unsigned long long)o.points);
    return o.points;
}

TEST(FaultInjection, VerifiesLeaksAreCounted) {
    // A buffer left alive when the device is destroyed must reach the messenger as an error, or the
    // zero-leak checks below could not fail.
    resetValidationCounters();
    {
        DeviceOptions o;
        o.validation = true;
        auto d = Device::create(o);
        ASSERT_TRUE(d.ok()) << d.error();
        Buffer leaked;
        ASSERT_TRUE(createBuffer(*d.value(), leaked, 64, kStorageBufferUsage, "leaked").ok());
        EXPECT_EQ(validationErrors(), 0u);
    } // ~Device: vkDestroyDevice with the buffer and its memory alive
    EXPECT_GE(validationErrors(), 1u) << "the object tracker's leak report did not reach the messenger";
    resetValidationCounters();
}

TEST(FaultInjection, DemoPathStrided) {
    const uint64_t points = countPoints();
    const char* env = std::getenv("ML_FAULT_STRIDE");
    const uint64_t stride = env && std::atoi(env) > 0 ? uint64_t(std::atoi(env)) : 16;
    uint64_t runs = 0;
    for (uint64_t n = 1; n <= points; n += stride, ++runs) expectCleanFailure(n);
    if ((points - 1) % stride) expectCleanFailure(points), ++runs;
    std::printf("fault injection: %llu of %llu points failed in turn (stride %llu)\n",
                (unsigned long long)runs, (unsigned long long)points, (unsigned long long)stride);
}

// Fenced timing (a profiling mode): every pass's own command buffer and submission is an allocation
// point too, so the path passes more points; each fails cleanly.
TEST(FaultInjection, FencedDemoPathStrided) {
    const uint64_t points = countPoints(true);
    EXPECT_GT(points, countPoints(false)) << "fenced passes add no allocation points";
    uint64_t runs = 0;
    for (uint64_t n = 1; n <= points; n += 16, ++runs) expectCleanFailure(n, true);
    if ((points - 1) % 16) expectCleanFailure(points, true), ++runs;
    std::printf("fault injection (fenced): %llu of %llu points failed in turn\n", (unsigned long long)runs,
                (unsigned long long)points);
}

TEST(FaultInjection, DISABLED_DemoPathEveryPoint) {
    const uint64_t points = countPoints();
    for (uint64_t n = 1; n <= points; ++n) expectCleanFailure(n);
    std::printf("fault injection: all %llu points failed in turn\n", (unsigned long long)points);
}

} // namespace
} // namespace ml::test
