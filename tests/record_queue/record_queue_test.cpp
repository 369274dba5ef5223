// record() never submits to or waits on the host's queue, nor builds a pipeline (a host may submit from
// another thread). This executable interposes the Vulkan entry points that submit, wait or build pipelines
// (vkQueueSubmit, vkQueueSubmit2, vkQueueWaitIdle, vkDeviceWaitIdle, vkWaitForFences, vkCreate*Pipelines):
// the definitions below take precedence over the loader's for every call the test and the statically linked
// module make, count the calls made while record() runs, and forward to the loader (dlsym RTLD_NEXT). It is
// an executable of its own so that no other test runs under the interposer.
//
// The host: two frames in flight (a command buffer and a fence per slot; the host's own fence waits
// happen outside record() and are not counted), virtual shadow maps whose slot pool starts at one map
// (so it grows inside record()), lights and meshes added and removed, a static bake attached, the
// targets resized, the LDR/HDR output switched, a debug view whose count buffer grows. Every frame:
// 0 submits, 0 waits and 0 pipeline builds inside record(), by the interposer and by the module's own
// counters (diag::queueAccessCounts), with 0 validation messages. And a borrowed device's module builds
// every pipeline through the host's cache (ModuleOptions::pipelineCache).
#include "../gpu/gpu_test_util.h"
#include "tests/common/borrowed_device.h"

#include "engine/manylights_diagnostics.h"

#include <dlfcn.h>

#include <glm/gtc/matrix_transform.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace {
// Counted while `inRecord` is set (around Module::record only).
std::atomic<bool> inRecord{false};
std::atomic<uint64_t> recordSubmits{0}, recordWaits{0}, recordPipelines{0}, allCalls{0};
// Pipelines built with the host's cache (`hostCache`) and with any other (or none).
std::atomic<VkPipelineCache> hostCache{VK_NULL_HANDLE};
std::atomic<uint64_t> throughHostCache{0}, notThroughHostCache{0};
void countPipeline(VkPipelineCache cache) {
    allCalls++;
    if (inRecord) recordPipelines++;
    (cache != VK_NULL_HANDLE && cache == hostCache ? throughHostCache : notThroughHostCache)++;
}

template <class F> F next(const char* name) {
    static_assert(sizeof(F) == sizeof(void*));
    void* f = dlsym(RTLD_NEXT, name);
    if (!f) {
        std::fprintf(stderr, "interposer: dlsym(RTLD_NEXT, %s) found nothing\n", name);
        std::abort();
    }
    return reinterpret_cast<F>(f);
}
void count(bool submit) {
    allCalls++;
    if (inRecord) (submit ? recordSubmits : recordWaits)++;
}
} // namespace

extern "C" {
VKAPI_ATTR VkResult VKAPI_CALL vkQueueSubmit(VkQueue queue, uint32_t count_, const VkSubmitInfo* submits,
                                             VkFence fence) {
    static const auto real = next<PFN_vkQueueSubmit>("vkQueueSubmit");
    count(true);
    return real(queue, count_, submits, fence);
}
VKAPI_ATTR VkResult VKAPI_CALL vkQueueSubmit2(VkQueue queue, uint32_t count_, const VkSubmitInfo2* submits,
                                              VkFence fence) {
    static const auto real = next<PFN_vkQueueSubmit2>("vkQueueSubmit2");
    count(true);
    return real(queue, count_, submits, fence);
}
VKAPI_ATTR VkResult VKAPI_CALL vkQueueWaitIdle(VkQueue queue) {
    static const auto real = next<PFN_vkQueueWaitIdle>("vkQueueWaitIdle");
    count(false);
    return real(queue);
}
VKAPI_ATTR VkResult VKAPI_CALL vkDeviceWaitIdle(VkDevice device) {
    static const auto real = next<PFN_vkDeviceWaitIdle>("vkDeviceWaitIdle");
    count(false);
    return real(device);
}
VKAPI_ATTR VkResult VKAPI_CALL vkCreateComputePipelines(VkDevice device, VkPipelineCache cache, uint32_t n,
                                                        const VkComputePipelineCreateInfo* infos,
                                                        const VkAllocationCallbacks* allocator,
                                                        VkPipeline* pipelines) {
    static const auto real = next<PFN_vkCreateComputePipelines>("vkCreateComputePipelines");
    countPipeline(cache);
    return real(device, cache, n, infos, allocator, pipelines);
}
VKAPI_ATTR VkResult VKAPI_CALL vkCreateGraphicsPipelines(VkDevice device, VkPipelineCache cache, uint32_t n,
                                                         const VkGraphicsPipelineCreateInfo* infos,
                                                         const VkAllocationCallbacks* allocator,
                                                         VkPipeline* pipelines) {
    static const auto real = next<PFN_vkCreateGraphicsPipelines>("vkCreateGraphicsPipelines");
    countPipeline(cache);
    return real(device, cache, n, infos, allocator, pipelines);
}
VKAPI_ATTR VkResult VKAPI_CALL vkWaitForFences(VkDevice device, uint32_t count_, const VkFence* fences,
                                               VkBool32 waitAll, uint64_t timeout) {
    static const auto real = next<PFN_vkWaitForFences>("vkWaitForFences");
    count(false);
    return real(device, count_, fences, waitAll, timeout);
}
}

namespace ml::test {
namespace {

LightDesc spot(float x, float z, bool moving) {
    LightDesc l;
    l.kind = LightKind::Spot;
    l.position = {x, 5.0f, z};
    l.direction = {0.0f, -1.0f, 0.0f};
    l.range = 9.0f;
    l.intensity = 8.0f;
    l.dynamic = moving; // a moving light's virtual map takes every caster
    return l;
}

struct Geometry {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    MeshDesc desc(const char* name, bool closed) const { return {vertices, indices, closed, name}; }
};

Geometry box() {
    Geometry m;
    for (int axis = 0; axis < 3; ++axis)
        for (float s : {-1.0f, 1.0f}) { // one face per axis and sign, CCW seen from outside
            glm::vec3 n(0.0f), u(0.0f), v(0.0f);
            n[axis] = s;
            u[(axis + 1) % 3] = 1.0f;
            v[(axis + 2) % 3] = 1.0f;
            if (s < 0) std::swap(u, v);
            const uint32_t b = uint32_t(m.vertices.size());
            for (glm::vec3 c : {n - u - v, n + u - v, n + u + v, n - u + v})
                m.vertices.push_back({{c.x, c.y, c.z}, {n.x, n.y, n.z}});
            for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(b + k);
        }
    return m;
}

// A host's frame loop on the module's device: slot = frame % 2, the host waits for the slot's fence
// (outside record), records record() alone into the slot's command buffer and submits it with the fence.
class Host {
  public:
    explicit Host(Module& m) : m_(m), info_(m.deviceInfo()) {
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = info_.queueFamily;
        EXPECT_EQ(vkCreateCommandPool(info_.device, &pci, nullptr, &pool_), VK_SUCCESS);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool_;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 2;
        EXPECT_EQ(vkAllocateCommandBuffers(info_.device, &ai, cmd_), VK_SUCCESS);
        for (VkFence& f : fences_) {
            VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, nullptr, VK_FENCE_CREATE_SIGNALED_BIT};
            EXPECT_EQ(vkCreateFence(info_.device, &fci, nullptr, &f), VK_SUCCESS);
        }
    }
    ~Host() {
        vkDeviceWaitIdle(info_.device);
        for (VkFence f : fences_) vkDestroyFence(info_.device, f, nullptr);
        vkDestroyCommandPool(info_.device, pool_, nullptr);
    }
    // One frame; returns record()'s submits, waits and pipeline builds seen by the interposer.
    uint64_t frame() {
        const uint32_t slot = uint32_t(frame_++ % 2);
        EXPECT_EQ(vkWaitForFences(info_.device, 1, &fences_[slot], VK_TRUE, UINT64_MAX), VK_SUCCESS);
        EXPECT_EQ(vkResetFences(info_.device, 1, &fences_[slot]), VK_SUCCESS);
        m_.collect(); // the slot's previous frame is done
        VkCommandBuffer cmd = cmd_[slot];
        EXPECT_EQ(vkResetCommandBuffer(cmd, 0), VK_SUCCESS);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        EXPECT_EQ(vkBeginCommandBuffer(cmd, &bi), VK_SUCCESS);
        const uint64_t before = recordSubmits + recordWaits + recordPipelines;
        const auto start = std::chrono::steady_clock::now();
        inRecord = true;
        auto r = m_.record(cmd);
        inRecord = false;
        cpuMs.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        EXPECT_TRUE(r.ok()) << r.error();
        const uint64_t seen = recordSubmits + recordWaits + recordPipelines - before;
        EXPECT_EQ(vkEndCommandBuffer(cmd), VK_SUCCESS);
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        EXPECT_EQ(vkQueueSubmit(info_.queue, 1, &si, fences_[slot]), VK_SUCCESS);
        return seen;
    }

    std::vector<double> cpuMs; // record()'s wall time per frame (validation on: informative only)

  private:
    Module& m_;
    DeviceInfo info_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_[2]{};
    VkFence fences_[2]{};
    uint64_t frame_ = 0;
};

TEST(QueueAccess, RecordNeverSubmitsOrWaits) {
    resetValidationCounters();
    ModuleOptions o;
    o.device.validation = true;
    o.framesInFlight = 2;
    o.timing = TimingChoice::Timestamps; // Fenced timing submits each pass by design
    o.vsm.enabled = true;
    o.vsm.resolution = 1024;
    o.vsm.poolPages = 256;
    o.vsm.initialMaps = 1; // the slot pool grows inside record() as shadowed lights arrive
    o.vsm.maxMaps = 64;
    auto made = Module::create(o);
    ASSERT_TRUE(made.ok()) << made.error();
    Module& m = *made.value();
    // The interposer sees the calls: a check that it is in the call path at all (else every 0 below
    // would pass for nothing). readOutput waits for the queue outside record().
    const uint64_t callsBefore = allCalls;

    Geometry quad;
    for (glm::vec2 c : {glm::vec2(-8, -8), glm::vec2(8, -8), glm::vec2(8, 8), glm::vec2(-8, 8)})
        quad.vertices.push_back({{c.x, 0.0f, c.y}, {0.0f, 1.0f, 0.0f}});
    quad.indices = {0, 2, 1, 0, 3, 2};
    const Geometry cubeGeometry = box();
    const MeshId ground = m.addMesh(quad.desc("ground", false)).value();
    const MeshId cube = m.addMesh(cubeGeometry.desc("box", true)).value();
    ASSERT_TRUE(m.addInstance(ground, glm::mat4(1.0f), glm::vec3(0.6f), false).ok());
    ASSERT_TRUE(m.addInstance(cube, glm::translate(glm::mat4(1.0f), {0, 1, 0}), glm::vec3(0.5f), false).ok());
    const InstanceId mover =
        m.addInstance(cube, glm::translate(glm::mat4(1.0f), {2, 1, 1}), glm::vec3(0.7f), true).value();
    std::vector<LightId> lights;
    lights.push_back(m.addLight(spot(-2.0f, 0.0f, true)).value());
    ASSERT_TRUE(m.createTargets(64, 36).ok());
    ASSERT_TRUE(m.setCamera({{0, 9, 11}, {0, 0, 0}}).ok());

    Host host(m);
    std::vector<uint64_t> interposed;
    auto frame = [&] { interposed.push_back(host.frame()); };
    frame(); // frame 0: every buffer's first use (its pipelines were built by createTargets)
    frame();
    for (int i = 0; i < 5; ++i) lights.push_back(m.addLight(spot(-4.0f + 2.0f * i, 2.0f, true)).value());
    frame(); // six moving shadowed lights: the VSM slot pool grows (1 -> 8 maps)
    frame();
    const MeshId late = m.addMesh(cubeGeometry.desc("late", true)).value(); // the mesh buffers are replaced
    const InstanceId added =
        m.addInstance(late, glm::translate(glm::mat4(1.0f), {-2, 1, -2}), glm::vec3(0.4f), true).value();
    frame();
    ASSERT_TRUE(m.setInstanceTransform(mover, glm::translate(glm::mat4(1.0f), {2, 1, 2})).ok());
    ASSERT_TRUE(m.removeLight(lights[2]).ok());
    frame();
    ASSERT_TRUE(m.setHdrOutput(true).ok()); // LDR -> HDR
    frame();
    frame();
    ASSERT_TRUE(m.createTargets(96, 54).ok()); // a new size: the cluster buffers are remade
    frame();
    ASSERT_TRUE(m.setHdrOutput(false).ok());
    frame();
    // A static light and its bake (a load-time call: it may wait; outside record()). The words reach
    // the GPU in the next record(), through the shared arena (a new GPU-only buffer).
    const LightId fixed = m.addLight(spot(1.0f, -1.0f, false)).value();
    ASSERT_TRUE(m.bakeStaticShadows(StaticMethod::SM, 32).ok());
    frame();
    ASSERT_TRUE(m.removeInstance(added).ok());
    ASSERT_TRUE(m.removeLight(fixed).ok());
    m.setView(DebugView::LightsEvaluated); // its per-pixel count buffer is made inside record()
    frame();
    ASSERT_TRUE(m.createTargets(128, 72).ok()); // and grows with the targets
    frame();
    m.setView(DebugView::Shaded);
    for (int i = 0; i < 8; ++i) lights.push_back(m.addLight(spot(-3.0f + i, -3.0f, true)).value());
    frame(); // more maps: the pool grows again (8 -> 16 or more)
    frame();
    for (int i = 0; i < 9; ++i) frame();
    ASSERT_EQ(interposed.size(), 24u);

    for (size_t f = 0; f < interposed.size(); ++f)
        EXPECT_EQ(interposed[f], 0u) << "record() of frame " << f
                                     << " submitted, waited or built a pipeline (interposed calls)";
    const diag::QueueAccessCounts counted = diag::queueAccessCounts(m);
    EXPECT_EQ(counted.recordSubmits, 0u) << "the module counted submits inside record()";
    EXPECT_EQ(counted.recordWaits, 0u) << "the module counted waits inside record()";
    EXPECT_EQ(counted.recordPipelines, 0u) << "the module counted pipeline builds inside record()";
    EXPECT_EQ(recordSubmits + recordWaits + recordPipelines, 0u);
    EXPECT_GT(counted.pipelines, 0u) << "the module's pipeline counter saw no build at all";
    std::printf("record() ms (validation on): frame 0 %.2f, after LDR->HDR %.2f, after HDR->LDR %.2f, "
                "median %.2f\n",
                host.cpuMs[0], host.cpuMs[6], host.cpuMs[9], [v = host.cpuMs]() mutable {
                    std::sort(v.begin(), v.end());
                    return v[v.size() / 2];
                }());
    // The slot pool did grow inside record() (the path this test is about), and the calls outside
    // record() went through the interposer (the host's fence waits and submits, the bake's).
    EXPECT_GT(internals(m).vsm.mapCapacity(), 8u) << "the VSM slot pool never grew: the test lost its point";
    EXPECT_GE(allCalls - callsBefore, 2u * interposed.size()) << "the interposer is not in the call path";
    EXPECT_GT(counted.submits, 0u) << "the module's counter saw no submit at all (the bake submits)";
    EXPECT_EQ(validationErrors(), 0u);
}

// The interposer itself: a one-time submit inside the counted window is seen by both counters, so the
// zeros above cannot come from a counter that misses the module's submits.
TEST(QueueAccess, CountersSeeASubmitInsideRecord) {
    resetValidationCounters();
    ModuleOptions o;
    o.device.validation = true;
    auto made = Module::create(o);
    ASSERT_TRUE(made.ok()) << made.error();
    Module& m = *made.value();
    Device& d = deviceOf(m);
    const uint64_t before = recordSubmits + recordWaits;
    {
        const Device::RecordScope scope(d); // what record() opens
        inRecord = true;
        Buffer b = createDeviceBuffer(d, 64, kStorageBufferUsage, "probe"); // no frame setup active: submits
        inRecord = false;
        destroyBuffer(d, b);
    }
    EXPECT_EQ(recordSubmits + recordWaits - before, 2u) << "one vkQueueSubmit and one vkQueueWaitIdle";
    EXPECT_EQ(recordPipelines, 0u);
    const diag::QueueAccessCounts counted = diag::queueAccessCounts(m);
    EXPECT_EQ(counted.recordSubmits, 1u);
    EXPECT_EQ(counted.recordWaits, 1u);
    EXPECT_EQ(validationErrors(), 0u);
}

// ModuleOptions::pipelineCache: every pipeline the module builds on a borrowed device goes through the
// host's cache (the interposer sees the handle; lavapipe's cache data stays a bare header, so its size
// cannot tell), none inside record(), LDR and HDR.
TEST(QueueAccess, PipelinesGoThroughTheHostsCache) {
    resetValidationCounters();
    DeviceOptions own;
    own.validation = true;
    auto physical = Device::create(own); // the instance and physical device the host's device is made on
    ASSERT_TRUE(physical.ok()) << physical.error();
    {
        HostDevice host(*physical.value());
        VkPipelineCacheCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
        VkPipelineCache cache = VK_NULL_HANDLE;
        ASSERT_EQ(vkCreatePipelineCache(host.device, &ci, nullptr, &cache), VK_SUCCESS);
        hostCache = cache;
        throughHostCache = notThroughHostCache = 0;
        {
            ModuleOptions o;
            o.borrow = host.borrow(*physical.value());
            o.pipelineCache = cache;
            o.vsm.enabled = true;
            auto created = Module::create(o);
            ASSERT_TRUE(created.ok()) << created.error();
            Module& m = *created.value();
            ASSERT_TRUE(m.createTargets(32, 18).ok());
            ASSERT_TRUE(m.setCamera({{0, 4, 6}, {0, 0, 0}}).ok());
            const uint64_t beforeFrames = throughHostCache + notThroughHostCache;
            renderFrame(m);
            ASSERT_TRUE(m.setHdrOutput(true).ok());
            renderFrame(m);
            EXPECT_EQ(throughHostCache + notThroughHostCache, beforeFrames) << "record() built a pipeline";
            EXPECT_EQ(diag::queueAccessCounts(m).pipelines, throughHostCache.load())
                << "the module's count and the interposer's differ";
        }
        vkDestroyPipelineCache(host.device, cache, nullptr);
        hostCache = VK_NULL_HANDLE;
    }
    EXPECT_GT(throughHostCache.load(), 10u) << "the module's pipelines did not reach the host's cache";
    EXPECT_EQ(notThroughHostCache.load(), 0u) << "pipelines built without the host's cache";
    EXPECT_EQ(validationErrors(), 0u);
}

// Every submit and wait of the module goes through gpu/device.cpp (Device::submit, waitQueue,
// waitDevice, waitFences), where they are counted: a direct call anywhere else in the module's sources
// would be a path the module's counter cannot see.
TEST(QueueAccess, OnlyDeviceCallsTheQueue) {
    namespace fs = std::filesystem;
    const std::regex direct(R"(\b(vkQueueSubmit2?|vkQueueWaitIdle|vkDeviceWaitIdle|vkWaitForFences)\s*\()");
    size_t files = 0;
    std::vector<std::string> offenders;
    for (const char* dir : {"gpu", "engine", "lights", "culling", "shadows/virtual", "shadows/gpu"}) {
        for (const auto& e : fs::directory_iterator(fs::path(ML_SOURCE_DIR) / dir)) {
            const std::string ext = e.path().extension().string();
            if (ext != ".cpp" && ext != ".h") continue;
            ++files;
            if (e.path().filename() == "device.cpp" && std::string(dir) == "gpu") continue;
            std::ifstream in(e.path());
            std::string line;
            for (int n = 1; std::getline(in, line); ++n) {
                const std::string code = line.substr(0, line.find("//")); // comments may name them
                if (std::regex_search(code, direct))
                    offenders.push_back(e.path().string() + ":" + std::to_string(n) + ": " + line);
            }
        }
    }
    EXPECT_GT(files, 50u) << "the module's sources were not found under " << ML_SOURCE_DIR;
    std::ostringstream list;
    for (const std::string& o : offenders) list << "\n  " << o;
    EXPECT_TRUE(offenders.empty()) << "direct queue calls outside gpu/device.cpp:" << list.str();
}

} // namespace
} // namespace ml::test
