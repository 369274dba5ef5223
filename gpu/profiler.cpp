#include "gpu/profiler.h"

#include "gpu/resources.h"

#include <chrono>

namespace ml {

Result<void> Profiler::create(const Device& device, uint32_t slots, std::vector<std::string> timerNames) {
    device_ = &device;
    slots_ = slots;
    names_ = std::move(timerNames);
    recorded_.assign(slots, std::vector<bool>(timers(), false));
    fenced_.assign(slots, {});
    VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    ci.queryCount = slots * timers() * 2;
    if (VkResult r = ML_VK_ALLOC(vkCreateQueryPool(device.device, &ci, nullptr, &pool_)); r != VK_SUCCESS) {
        pool_ = VK_NULL_HANDLE;
        return fail(std::string("vkCreateQueryPool for 'profiler_queries' failed: ") + vkResultName(r));
    }
    vkResetQueryPool(device.device, pool_, 0, ci.queryCount);
    return {};
}

void Profiler::destroy(const Device& device) {
    if (pool_) vkDestroyQueryPool(device.device, pool_, nullptr);
    pool_ = VK_NULL_HANDLE;
}

void Profiler::beginFrame(VkCommandBuffer cmd, uint32_t slot) {
    current_ = slot;
    recorded_[slot].assign(timers(), false);
    fenced_[slot] = {std::vector<double>(timers(), 0.0), std::vector<double>(timers(), 0.0),
                     std::vector<bool>(timers(), false)};
    if (fenced) return;
    vkCmdResetQueryPool(cmd, pool_, slot * timers() * 2, timers() * 2);
}

void Profiler::run(VkCommandBuffer cmd, uint32_t timer, const std::function<void(VkCommandBuffer)>& body) {
    if (!fenced) {
        const uint32_t query = (current_ * timers() + timer) * 2;
        device_->beginLabel(cmd, names_[timer].c_str());
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, query);
        body(cmd);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, query + 1);
        recorded_[current_][timer] = true;
        device_->endLabel(cmd);
        return;
    }
    VkCommandBuffer own = device_->beginOneTime();
    device_->beginLabel(own, names_[timer].c_str());
    body(own);
    device_->endLabel(own);
    auto t0 = std::chrono::steady_clock::now();
    device_->endOneTime(own); // submit and wait
    auto t1 = std::chrono::steady_clock::now();
    double start = std::chrono::duration<double, std::milli>(t0.time_since_epoch()).count();
    setFenced(timer, start, std::chrono::duration<double, std::milli>(t1 - t0).count());
}

void Profiler::runUntimed(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& body) {
    if (!fenced) {
        body(cmd);
        return;
    }
    VkCommandBuffer own = device_->beginOneTime();
    body(own);
    device_->endOneTime(own);
}

void Profiler::setFenced(uint32_t timer, double startMs, double ms) {
    fenced_[current_].ms[timer] = ms;
    fenced_[current_].startMs[timer] = startMs;
    fenced_[current_].ran[timer] = true;
}

bool Profiler::read(uint32_t slot, Times& out) const {
    if (fenced) {
        out = fenced_[slot];
        return true;
    }
    out = {std::vector<double>(timers(), 0.0), std::vector<double>(timers(), 0.0),
           std::vector<bool>(timers(), false)};
    for (uint32_t p = 0; p < timers(); ++p) {
        if (!recorded_[slot][p]) continue;
        uint64_t data[4]; // begin, availability, end, availability
        VkResult r = vkGetQueryPoolResults(device_->device, pool_, (slot * timers() + p) * 2, 2, sizeof(data),
                                           data, 2 * sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
        if (r != VK_SUCCESS && r != VK_NOT_READY) return false;
        if (!data[1] || !data[3]) return false;
        out.ms[p] = double(data[2] - data[0]) * device_->timestampPeriodNs * 1e-6;
        out.startMs[p] = double(data[0]) * device_->timestampPeriodNs * 1e-6;
        out.ran[p] = true;
    }
    return true;
}

} // namespace ml
