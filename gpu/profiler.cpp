#include "gpu/profiler.h"
#include "gpu/resources.h"

#include <chrono>

namespace ml {

const char* passName(Pass pass) {
    switch (pass) {
    case Pass::GBuffer:
        return "gbuffer";
    case Pass::ClusterBounds:
        return "cluster_bounds";
    case Pass::LightAssign:
        return "light_assign";
    case Pass::VsmMark:
        return "vsm_mark";
    case Pass::VsmAlloc:
        return "vsm_alloc";
    case Pass::VsmHpb:
        return "vsm_hpb";
    case Pass::VsmCull:
        return "vsm_cull";
    case Pass::VsmExpand:
        return "vsm_expand";
    case Pass::VsmDraw:
        return "vsm_draw";
    case Pass::Evaluate:
        return "evaluate";
    case Pass::Statistics:
        return "statistics";
    case Pass::Count:
        break;
    }
    return "?";
}

double PassTimes::totalMs() const {
    double t = 0;
    for (uint32_t i = 0; i < kPassCount; ++i)
        if (ran[i]) t += ms[i];
    return t;
}

void Profiler::create(const Device& device, uint32_t slots) {
    device_ = &device;
    slots_ = slots;
    recorded_.assign(slots, {});
    fenced_.assign(slots, {});
    VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    ci.queryCount = slots * kPassCount * 2;
    ML_VK_CHECK(vkCreateQueryPool(device.device, &ci, nullptr, &pool_));
    vkResetQueryPool(device.device, pool_, 0, ci.queryCount);
}

void Profiler::destroy(const Device& device) {
    if (pool_) vkDestroyQueryPool(device.device, pool_, nullptr);
    pool_ = VK_NULL_HANDLE;
}

void Profiler::beginFrame(VkCommandBuffer cmd, uint32_t slot) {
    current_ = slot;
    recorded_[slot] = {};
    fenced_[slot] = {};
    if (mode == TimingMode::Fenced) return;
    vkCmdResetQueryPool(cmd, pool_, slot * kPassCount * 2, kPassCount * 2);
}

void Profiler::begin(VkCommandBuffer cmd, Pass pass) {
    device_->beginLabel(cmd, passName(pass));
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_,
                         (current_ * kPassCount + uint32_t(pass)) * 2);
}

void Profiler::end(VkCommandBuffer cmd, Pass pass) {
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_,
                         (current_ * kPassCount + uint32_t(pass)) * 2 + 1);
    recorded_[current_][uint32_t(pass)] = true;
    device_->endLabel(cmd);
}

void Profiler::run(VkCommandBuffer cmd, Pass pass, const std::function<void(VkCommandBuffer)>& body) {
    if (mode == TimingMode::Timestamps) {
        begin(cmd, pass);
        body(cmd);
        end(cmd, pass);
        return;
    }
    VkCommandBuffer own = device_->beginOneTime();
    device_->beginLabel(own, passName(pass));
    body(own);
    device_->endLabel(own);
    auto t0 = std::chrono::steady_clock::now();
    device_->endOneTime(own); // submit and wait
    auto t1 = std::chrono::steady_clock::now();
    double start = std::chrono::duration<double, std::milli>(t0.time_since_epoch()).count();
    setFenced(pass, start, std::chrono::duration<double, std::milli>(t1 - t0).count());
}

void Profiler::runUntimed(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& body) {
    if (mode == TimingMode::Timestamps) {
        body(cmd);
        return;
    }
    VkCommandBuffer own = device_->beginOneTime();
    body(own);
    device_->endOneTime(own);
}

void Profiler::setFenced(Pass pass, double startMs, double ms) {
    fenced_[current_].ms[uint32_t(pass)] = ms;
    fenced_[current_].startMs[uint32_t(pass)] = startMs;
    fenced_[current_].ran[uint32_t(pass)] = true;
}

bool Profiler::read(uint32_t slot, PassTimes& out) const {
    if (mode == TimingMode::Fenced) {
        out = fenced_[slot];
        return true;
    }
    out = PassTimes{};
    for (uint32_t p = 0; p < kPassCount; ++p) {
        if (!recorded_[slot][p]) continue;
        uint64_t data[4]; // begin, availability, end, availability
        VkResult r = vkGetQueryPoolResults(device_->device, pool_, (slot * kPassCount + p) * 2, 2,
                                           sizeof(data), data, 2 * sizeof(uint64_t),
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
