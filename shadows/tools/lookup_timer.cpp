#include "shadows/tools/lookup_timer.h"

#include "gpu/bindings.h"
#include "gpu/resources.h"
#include "shadows/static/static_visibility.h"
#include "shadows/tools/bench_lookup_bindings.h"
#include "shadows/tools/lookup_push.h"

#include "bench_lookup.comp.spv.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

namespace ml {

struct LookupTimer::State {
    std::unique_ptr<Device> owned;
    Device* device = nullptr;
    ShaderModule shader;
    Program program;
};

LookupTimer::LookupTimer(std::unique_ptr<State> s) : s_(std::move(s)) {}

LookupTimer::~LookupTimer() {
    if (!s_) return;
    destroyProgram(*s_->device, s_->program);
    destroyShader(*s_->device, s_->shader);
}

Result<std::unique_ptr<LookupTimer>> LookupTimer::create() {
    auto created = Device::create({});
    if (!created) return fail("lookup timer: " + created.error());
    auto s = std::make_unique<State>();
    s->owned = std::move(created.value());
    s->device = s->owned.get();
    Device& device = *s->device;
    s->shader = ML_SHADER(device, spv_bench_lookup_comp);
    s->program = createComputeProgram(device, s->shader);
    return std::unique_ptr<LookupTimer>(new LookupTimer(std::move(s)));
}

uint64_t LookupTimer::maxStorageBufferRange() const {
    return s_->device->properties.limits.maxStorageBufferRange;
}

Result<std::vector<LookupTiming>> LookupTimer::measure(const std::vector<gpu::GpuShadowRecord>& records,
                                                       const std::vector<uint32_t>& words,
                                                       const std::vector<LookupPair>& pairs,
                                                       const std::vector<uint32_t>& radii,
                                                       uint32_t extraLookups, uint32_t repetitions) {
    if (pairs.empty() || records.empty() || words.empty()) return fail("lookup timing: nothing to look up");
    Device& d = *s_->device;
    const uint32_t count = uint32_t(pairs.size());
    std::vector<glm::vec4> items(size_t(count) * 2);
    for (uint32_t i = 0; i < count; ++i) {
        float bits;
        std::memcpy(&bits, &pairs[i].record, 4);
        items[2 * i] = glm::vec4(pairs[i].p, 1.0f);
        items[2 * i + 1] = glm::vec4(pairs[i].n, bits);
    }
    Buffer itemBuf = createBuffer(d, items.size() * 16, kStorageBufferUsage, "lookup_items");
    Buffer recBuf =
        createBuffer(d, records.size() * sizeof(gpu::GpuShadowRecord), kStorageBufferUsage, "lookup_records");
    Buffer wordBuf = createBuffer(d, words.size() * 4, kStorageBufferUsage, "lookup_words");
    Buffer outBuf = createBuffer(d, size_t(count) * 4, kStorageBufferUsage, "lookup_out");
    upload(itemBuf, items.data(), items.size() * 16);
    upload(recBuf, records.data(), records.size() * sizeof(gpu::GpuShadowRecord));
    upload(wordBuf, words.data(), words.size() * 4);
    auto run = [&](uint32_t lookups, uint32_t radius) {
        const gpu::LookupPush push{count, lookups, radius, 0};
        VkCommandBuffer cmd = d.beginOneTime();
        dispatch(d, cmd, s_->program, count, 1, push,
                 {ML_BIND(ML_LOOKUP_ITEMS, itemBuf), ML_BIND(ML_LOOKUP_RECORDS, recBuf),
                  ML_BIND(ML_LOOKUP_WORDS, wordBuf), ML_BIND(ML_LOOKUP_OUT, outBuf)});
        fullBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_2_HOST_BIT);
        auto t0 = std::chrono::steady_clock::now();
        d.endOneTime(cmd); // submit and wait: fenced wall time (lavapipe's timestamps do not bracket compute)
        return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    };
    std::vector<LookupTiming> out;
    for (uint32_t radius : radii) {
        LookupTiming t;
        t.radius = radius;
        // The GPU's one-lookup values against the CPU twin, so the timed code is the code that is right.
        run(1, radius);
        const float* sums = outBuf.as<float>();
        for (uint32_t i = 0; i < count; ++i) {
            gpu::GpuShadowRecord rec = records[pairs[i].record];
            rec.info.x = gpu::shadowRecordWithRadius(rec.info.x, radius);
            float cpu = staticVisibility(rec, words.data(), pairs[i].p, pairs[i].n);
            t.cpuMismatches += std::abs(cpu - sums[i]) > 1e-6f;
        }
        // Grow K until the extra lookups take >= 40 ms, well above the submit-and-wait jitter
        // (milliseconds on a loaded machine), so cheap one-tap lookups are timed as well as 9x9 PCF.
        uint32_t extra = extraLookups;
        while (extra < 4096 && run(1 + extra, radius) - run(1, radius) < 40e6) extra *= 4;
        t.lookups = extra;
        double best = 1e300, worst = 0;
        for (uint32_t r = 0; r < repetitions; ++r) {
            double base = run(1, radius);
            double more = run(1 + extra, radius);
            double ns = std::max(0.0, more - base) / (double(extra) * count);
            best = std::min(best, ns);
            worst = std::max(worst, ns);
        }
        t.nsPerLookup = best;
        t.spread = best > 0 ? (worst - best) / best : 0;
        out.push_back(t);
    }
    for (Buffer* b : {&itemBuf, &recBuf, &wordBuf, &outBuf}) destroyBuffer(d, *b);
    return out;
}

} // namespace ml
