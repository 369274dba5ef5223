// record() never waits for the GPU: a host with two frames in flight, each with its own
// command buffer and fence, records frame N while frame N-1 still runs. record() reads the results of
// the slot's previous frame (already waited for by the host) without touching the frame in flight:
// before the fix it called vkGetQueryPoolResults, which on lavapipe waits for the device to go idle,
// so record() took about a whole frame's GPU time.
#include "gpu_test_util.h"

#include <algorithm>
#include <chrono>

namespace ml::test {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

TEST(FramePacing, RecordDoesNotWaitForTheFrameInFlight) {
    resetValidationCounters();
    ModuleOptions o;
    o.device.validation = true;
    o.framesInFlight = 2;
    o.timing = TimingChoice::Timestamps; // the host's own submissions (fenced mode would submit itself)
    auto created = Module::create(o);
    ASSERT_TRUE(created.ok()) << created.error();
    Module& m = *created.value();
    auto scene = loadScene("night-city", 128, 2);
    ASSERT_TRUE(scene.ok()) << scene.error();
    ASSERT_TRUE(bindScene(m, scene.value()).ok());
    ASSERT_TRUE(m.createTargets(320, 180).ok());
    ASSERT_TRUE(m.submitFrame().ok()); // uploads and first layouts in their own submission
    m.collect();
    m.takeReports();

    // The GPU time of one frame, submitted and waited for on its own.
    auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(m.submitFrame().ok());
    const double frameMs = msSince(t0);
    m.collect();
    m.takeReports();

    const DeviceInfo info = m.deviceInfo();
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = info.queueFamily;
    VkCommandPool pool;
    ASSERT_EQ(vkCreateCommandPool(info.device, &pci, nullptr, &pool), VK_SUCCESS);
    VkCommandBuffer cmds[2];
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 2;
    ASSERT_EQ(vkAllocateCommandBuffers(info.device, &ai, cmds), VK_SUCCESS);
    VkFence fences[2];
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fci.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    for (VkFence& f : fences) ASSERT_EQ(vkCreateFence(info.device, &fci, nullptr, &f), VK_SUCCESS);

    constexpr int kFrames = 8;
    std::vector<double> recordMs;
    for (int i = 0; i < kFrames; ++i) {
        const int s = i % 2;
        // The host's half of the contract: the slot's previous frame has completed.
        ASSERT_EQ(vkWaitForFences(info.device, 1, &fences[s], VK_TRUE, UINT64_MAX), VK_SUCCESS);
        vkResetFences(info.device, 1, &fences[s]);
        vkResetCommandBuffer(cmds[s], 0);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkBeginCommandBuffer(cmds[s], &bi);
        auto r0 = std::chrono::steady_clock::now();
        auto r = m.record(cmds[s]); // frame i-1 is in flight on the other slot (from i = 1 on)
        if (i > 0) recordMs.push_back(msSince(r0));
        ASSERT_TRUE(r.ok()) << r.error();
        vkEndCommandBuffer(cmds[s]);
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmds[s];
        ASSERT_EQ(vkQueueSubmit(info.queue, 1, &si, fences[s]), VK_SUCCESS);
    }
    vkQueueWaitIdle(info.queue);
    m.collect();
    const auto reports = m.takeReports();
    vkDestroyFence(info.device, fences[0], nullptr);
    vkDestroyFence(info.device, fences[1], nullptr);
    vkDestroyCommandPool(info.device, pool, nullptr);

    // Every frame's report arrives, with its timings (nothing dropped because record() did not wait).
    EXPECT_EQ(reports.size(), size_t(kFrames));
    for (const FrameReport& rep : reports) EXPECT_TRUE(rep.times.ran("evaluate"));
    // Before the fix record() took about frameMs here (it waited for the frame in flight); a quarter of
    // it leaves room for a loaded CI machine while still failing the old behaviour.
    const double rec = median(recordMs);
    std::printf("frame %.1f ms (submitted alone), record() median %.2f ms with a frame in flight\n", frameMs,
                rec);
    EXPECT_LT(rec, 0.25 * frameMs);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
