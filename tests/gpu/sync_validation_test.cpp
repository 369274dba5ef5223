// Synchronization validation (DeviceOptions::validationSync, ML_VALIDATION_SYNC=1) is really on: a
// write-after-write the recording leaves unordered is reported and counted as an error, and the same
// recording with the barrier that orders it is not; two frames in one command buffer and a slot pool
// grown twice in one frame report nothing. The frame itself is checked with synchronization
// validation by the CliSyncValidation_* tests (the demo exits non-zero on any message).
#include "gpu/device.h"
#include "gpu/resources.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

// Two fills of one buffer, with or without the barrier between them; returns the messages counted.
uint32_t twoFills(bool barrier) {
    DeviceOptions o;
    o.validationSync = true;
    auto d = Device::create(o);
    EXPECT_TRUE(d.ok()) << d.error();
    if (!d) return 0;
    Device& dev = *d.value();
    EXPECT_TRUE(dev.validationEnabled());
    EXPECT_TRUE(dev.synchronizationValidationEnabled());
    Buffer b = createDeviceBuffer(dev, 256, kStorageBufferUsage, "sync_test");
    resetValidationCounters();
    VkCommandBuffer cmd = dev.beginOneTime();
    vkCmdFillBuffer(cmd, b.buffer, 0, VK_WHOLE_SIZE, 1);
    if (barrier) // the first fill's writes -> the second fill's writes (write-after-write)
        memoryBarrier(cmd, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, kFillStages,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, b.buffer, 0, VK_WHOLE_SIZE, 2);
    dev.endOneTime(cmd);
    const uint32_t errors = validationErrors();
    destroyBuffer(dev, b);
    resetValidationCounters();
    return errors;
}

TEST(SyncValidation, ReportsAnUnorderedWriteAfterWrite) {
    EXPECT_GE(twoFills(false), 1u);
}

TEST(SyncValidation, BarrierSilencesIt) {
    EXPECT_EQ(twoFills(true), 0u);
}

} // namespace
} // namespace ml

#include "gpu_test_util.h"

namespace ml::test {

// Two frames recorded back to back into one command buffer (two frames in flight, as a host that
// submits without waiting in between would): the second frame reads and rewrites what the first wrote
// (cluster lists, the persistent virtual shadow map state, the targets). The frame-boundary barrier at
// the start of record() must order them: synchronization validation reports nothing.
// A module with synchronization validation and virtual shadow maps on, a 32-light night city bound, 160x90
// targets, and its first frame (uploads, layouts, slot pool growth) submitted and waited for.
std::unique_ptr<Module> nightCityFirstFrame(ModuleOptions o) {
    resetValidationCounters();
    o.device.validationSync = true;
    o.vsm.enabled = true;
    auto created = Module::create(o);
    EXPECT_TRUE(created.ok()) << created.error();
    if (!created) return nullptr;
    Module& m = *created.value();
    auto scene = loadScene("night-city", 32, 2);
    EXPECT_TRUE(scene.ok()) << scene.error();
    if (!scene || !bindScene(m, scene.value()).ok() || !m.createTargets(160, 90).ok() ||
        !m.submitFrame().ok())
        return nullptr;
    vkQueueWaitIdle(m.deviceInfo().queue);
    return std::move(created.value());
}

TEST(SyncValidation, TwoFramesInOneCommandBuffer) {
    ModuleOptions o;
    o.statistics = true;
    o.framesInFlight = 2;
    auto module = nightCityFirstFrame(o);
    ASSERT_TRUE(module);
    Module& m = *module;
    Device& d = deviceOf(m);
    VkCommandBuffer cmd = d.beginOneTime();
    ASSERT_TRUE(m.record(cmd).ok());
    ASSERT_TRUE(m.record(cmd).ok());
    d.endOneTime(cmd);
    vkQueueWaitIdle(m.deviceInfo().queue);
    EXPECT_EQ(validationErrors(), 0u);
}

// The map slot pool grown several times while one frame is prepared (initialMaps 1, then every light that
// needs a slot doubles it): each growth copies the page table into a new buffer, so copy k reads what
// copy k-1 wrote. FrameSetup::record orders them (read-after-write); without that barrier
// synchronization validation reports SYNC-HAZARD-READ-AFTER-WRITE on vsm_page_table (found by
// ApiFuzzSyncValidation).
TEST(SyncValidation, MapSlotsGrownTwiceInOneFrame) {
    ModuleOptions o;
    o.vsm.initialMaps = 1;
    auto module = nightCityFirstFrame(o);
    ASSERT_TRUE(module);
    EXPECT_GE(internals(*module).vsm.mapCapacity(), 4u) << "the pool did not grow twice (nothing tested)";
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace ml::test
