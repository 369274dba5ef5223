#include "gpu/profiler.h"

#include <chrono>
#include <cstring>

namespace ml {

Result<void> Profiler::create(const Device& device, uint32_t slots) {
    device_ = &device;
    slots_ = slots;
    timers_.clear();
    ran_.assign(slots, {});
    fenced_.assign(slots, {});
    VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    ci.queryCount = slots * kMaxTimers * 2;
    if (VkResult r = ML_VK_ALLOC(vkCreateQueryPool(device.device, &ci, nullptr, &pool_)); r != VK_SUCCESS) {
        pool_ = VK_NULL_HANDLE;
        return fail(std::string("vkCreateQueryPool for 'profiler_queries' failed: ") + vkResultName(r));
    }
    vkResetQueryPool(device.device, pool_, 0, ci.queryCount);
    done_.assign(slots, VK_NULL_HANDLE);
    results_.assign(slots, {});
    for (uint32_t s = 0; s < slots; ++s) {
        VkEventCreateInfo ei{VK_STRUCTURE_TYPE_EVENT_CREATE_INFO};
        if (VkResult r = ML_VK_ALLOC(vkCreateEvent(device.device, &ei, nullptr, &done_[s]));
            r != VK_SUCCESS) {
            done_[s] = VK_NULL_HANDLE;
            return fail(std::string("vkCreateEvent for 'profiler_done' failed: ") + vkResultName(r));
        }
        // 2 queries per timer, {value, availability} of 8 bytes each; the host reads them.
        ML_TRY(createBuffer(device, results_[s], VkDeviceSize(kMaxTimers) * 2 * 16,
                            VK_BUFFER_USAGE_TRANSFER_DST_BIT, "profiler_results", MemoryRole::Readback));
    }
    return {};
}

void Profiler::destroy(const Device& device) {
    if (pool_) vkDestroyQueryPool(device.device, pool_, nullptr);
    pool_ = VK_NULL_HANDLE;
    for (VkEvent e : done_)
        if (e) vkDestroyEvent(device.device, e, nullptr);
    for (Buffer& b : results_) destroyBuffer(device, b);
    done_.clear();
    results_.clear();
}

void Profiler::beginFrame(VkCommandBuffer cmd, uint32_t slot) {
    current_ = slot;
    ran_[slot].clear();
    fenced_[slot] = {};
    if (fenced) return;
    vkCmdResetQueryPool(cmd, pool_, slot * kMaxTimers * 2, kMaxTimers * 2);
}

Result<uint32_t> Profiler::begin(const PassTimer& timer) {
    uint32_t index = 0;
    while (index < timers_.size() && std::strcmp(timers_[index].name, timer.name) != 0) ++index;
    if (index == timers_.size()) {
        if (index == kMaxTimers)
            return fail(std::string("profiler: timer '") + timer.name + "' is one past the " +
                        std::to_string(kMaxTimers) + " the query pool holds (Profiler::kMaxTimers)");
        timers_.push_back(timer);
    }
    for (uint32_t r : ran_[current_])
        if (r == index)
            return fail(std::string("profiler: timer '") + timer.name + "' runs twice in one frame");
    ran_[current_].push_back(index);
    return index;
}

Result<void> Profiler::run(VkCommandBuffer cmd, const PassTimer& timer,
                           const std::function<void(VkCommandBuffer)>& body) {
    auto index = begin(timer);
    if (!index) return fail(index.error());
    if (!fenced) {
        const uint32_t query = (current_ * kMaxTimers + index.value()) * 2;
        device_->beginLabel(cmd, timer.name);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, query);
        body(cmd);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, query + 1);
        device_->endLabel(cmd);
        return {};
    }
    auto own = device_->tryBeginOneTime(timer.name);
    if (!own) return fail(own.error());
    device_->beginLabel(own.value(), timer.name);
    body(own.value());
    device_->endLabel(own.value());
    auto t0 = std::chrono::steady_clock::now();
    ML_TRY(device_->tryEndOneTime(own.value(), timer.name)); // submit and wait
    auto t1 = std::chrono::steady_clock::now();
    double start = std::chrono::duration<double, std::milli>(t0.time_since_epoch()).count();
    fenced_[current_].passes.push_back(
        {timer.name, timer.group, std::chrono::duration<double, std::milli>(t1 - t0).count(), start});
    return {};
}

Result<void> Profiler::runUntimed(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& body) {
    if (!fenced) {
        body(cmd);
        return {};
    }
    auto own = device_->tryBeginOneTime("untimed pass");
    if (!own) return fail(own.error());
    body(own.value());
    return device_->tryEndOneTime(own.value(), "untimed pass");
}

void Profiler::endFrame(VkCommandBuffer cmd) {
    if (fenced) return; // every pass was submitted and waited for already
    // WAIT_BIT waits on the GPU timeline (the copy runs after the timestamps are written), not on the
    // host; it may only name queries this frame wrote, so one copy per timer that ran (a timer that
    // did not run keeps availability 0 from the host's clear below and is not read).
    std::memset(results_[current_].data, 0, size_t(results_[current_].size));
    for (uint32_t p : ran_[current_])
        vkCmdCopyQueryPoolResults(
            cmd, pool_, (current_ * kMaxTimers + p) * 2, 2, results_[current_].buffer, VkDeviceSize(p) * 32,
            16, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT | VK_QUERY_RESULT_WAIT_BIT);
    // The event signals after everything recorded before it (the whole frame, the copy included) and
    // makes those writes (results, the frame's counters) visible to host reads.
    VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    mb.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    mb.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
    mb.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
    mb.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = 1;
    di.pMemoryBarriers = &mb;
    vkCmdSetEvent2(cmd, done_[current_], &di);
}

bool Profiler::read(uint32_t slot, PassTimes& out) {
    if (fenced) {
        out = fenced_[slot];
        return true;
    }
    out = {};
    // Never vkGetQueryPoolResults here: it may wait for the device (see the header).
    if (vkGetEventStatus(device_->device, done_[slot]) != VK_EVENT_SET) return false;
    const uint64_t* data = results_[slot].as<uint64_t>(); // {begin, avail, end, avail} per timer
    for (uint32_t p : ran_[slot]) {
        const uint64_t* q = data + size_t(p) * 4;
        if (!q[1] || !q[3]) continue; // recorded but not executed (cannot happen after the event)
        out.passes.push_back({timers_[p].name, timers_[p].group,
                              double(q[2] - q[0]) * device_->timestampPeriodNs * 1e-6,
                              double(q[0]) * device_->timestampPeriodNs * 1e-6});
    }
    // The event was set by a completed frame; nothing pending waits on it, so the host may reset it
    // before the slot's next frame is recorded.
    vkResetEvent(device_->device, done_[slot]);
    return true;
}

} // namespace ml
