// diag::measureZBin (engine/manylights_diagnostics.h): the Z-binning passes (culling/zbin.h) on the
// last frame's inputs, timed fenced like the frame's own passes (gpu/profiler.cpp: each pass its own
// submission, host clock from submit to completion), for `bench culling --compare-zbin`.
#include "culling/zbin.h"
#include "engine/manylights_diagnostics.h"
#include "engine/module_impl.h"

#include <chrono>
#include <functional>

namespace ml::diag {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
// Records `body` into its own command buffer and returns the milliseconds from submit to completion.
double fenced(const Device& d, const std::function<void(VkCommandBuffer)>& body) {
    VkCommandBuffer cmd = d.beginOneTime();
    body(cmd);
    auto t0 = std::chrono::steady_clock::now();
    d.endOneTime(cmd); // submit and wait
    return msSince(t0);
}
} // namespace

Result<ZBinMeasure> measureZBin(Module& module, bool depthTest, uint32_t frames) {
    Module::Impl& m = internals(module);
    if (!m.ownTargets) return fail("measureZBin: needs module-owned targets (createTargets)");
    if (m.frameIndex == 0) return fail("measureZBin: no frame recorded yet");
    if (m.lastConstants.cluster.w != ML_CULL_CLUSTERED)
        return fail("measureZBin: the last frame must use clustered culling (its tile masks)");
    const Device& d = *m.device;
    ML_VK_CHECK(d.waitQueue());
    ZBinning zb;
    ZBinMeasure out;
    auto run = [&]() -> Result<void> {
        ML_TRY(zb.create(d));
        const uint32_t n = std::max(1u, frames);
        for (uint32_t i = 0; i <= n; ++i) { // i = 0: warm-up (buffers created), not counted
            auto t0 = std::chrono::steady_clock::now();
            const ZBinFrame zf = zbinPrepare(m.lastConstants, m.lastSliceFar, m.lastLights, depthTest);
            ML_TRY(zb.prepare(d, zf, m.lastConstants, m.lastLights));
            const double host = msSince(t0);
            const double mask = fenced(d, [&](VkCommandBuffer c) { zb.recordMasks(d, c, m.cull.tileMasks); });
            const double bins = fenced(d, [&](VkCommandBuffer c) { zb.recordBins(d, c); });
            out.sorted = zf.push.sorted;
            out.wide = zf.push.wide;
            if (i == 0) continue;
            out.hostMs += host / n;
            out.maskMs += mask / n;
            out.binsMs += bins / n;
        }
        ML_TRY(zb.prepareSlices(d, m.lastSliceFar));
        const VkImageView depth = m.targets.depth.view, normal = m.targets.normal.view;
        for (uint32_t i = 0; i <= n; ++i) { // i = 0: warm-up
            for (bool z : {false, true}) {
                const double ms = fenced(d, [&](VkCommandBuffer c) {
                    zb.recordShade(d, c, z, depth, normal, m.cull.ranges, m.cull.pool);
                });
                if (i > 0) (z ? out.shadeZBinMs : out.shadeClustersMs) += ms / n;
            }
        }
        out.statsMs = fenced(d, [&](VkCommandBuffer c) { zb.recordStats(d, c, m.targets.depth.view); });
        const ZBinStats s = zb.stats();
        out.evaluated = s.evaluated;
        out.reaching = s.reaching;
        out.surface = s.surface;
        out.tile = s.tile;
        out.exact = s.exact;
        return {};
    };
    auto r = run();
    zb.destroy(d);
    if (!r) return fail("measureZBin: " + r.error());
    return out;
}

} // namespace ml::diag
