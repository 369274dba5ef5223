#include "apps/report.h"
#include "apps/json.h"
#include "io/safe_io.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace ml {

namespace {
// Every output file goes through the one safe writer (io/safe_io.h): a fresh temporary beside the
// target, renamed over it; a symlink or device at the target is refused.
Result<void> writeText(const std::string& path, const std::string& text) {
    return io::writeFileAtomically(path, text);
}

// stats.json's "vsm" object: the last frame's virtual shadow map counts.
std::string vsmJson(const VsmStats& v) {
    json::Object o;
    o.integer("pages_marked", v.pagesMarked).integer("pages_allocated", v.pagesAllocated);
    o.integer("pages_cached", v.pagesCached).integer("pages_rendered", v.pagesRendered);
    o.integer("pages_invalidated", v.pagesInvalidated).integer("pages_evicted", v.pagesEvicted);
    o.integer("fallbacks", v.fallbacks).integer("pool_pages", v.poolPages).integer("pool_bytes", v.poolBytes);
    o.integer("used_bytes", v.usedBytes).integer("virtual_bytes", v.virtualBytes);
    o.integer("atlas_bytes", v.atlasBytes).integer("lights_with_pages", v.lightsWithPages);
    o.integer("lights_without_slot", v.lightsWithoutSlot).integer("maps_active", v.mapsActive);
    o.integer("instances_drawn", v.instancesDrawn).integer("instances_culled_hpb", v.instancesCulledHpb);
    o.integer("draw_overflow", v.drawOverflow).text("raster", v.meshPath ? "mesh" : "vertex");
    o.integer("meshlets_total", v.meshletsTotal)
        .integer("meshlets_after_expansion", v.meshletsAfterExpansion);
    o.integer("meshlets_after_task", v.meshletsAfterTask)
        .integer("triangles_after_task", v.trianglesAfterTask);
    o.integer("triangles_rasterized", v.trianglesRasterized).integer("meshlet_overflow", v.meshletOverflow);
    o.integer("fragments_drawn", v.fragmentsDrawn).integer("dirty_page_texels", v.dirtyPageTexels);
    o.integer("page_clip_overflow", v.pageClipOverflow).integer("request_overflow", v.requestOverflow);
    o.integer("pages_new", v.pagesNew).integer("pages_invalidated_caster", v.pagesInvalidatedCaster);
    o.integer("pages_rendered_dynamic", v.pagesRenderedDynamic);
    o.integer("caster_group_tests", v.groupTests).integer("caster_groups_refused", v.groupsRefused);
    o.integer("cull_pair_overflow", v.pairOverflow);
    return o.str();
}
} // namespace

Result<void> writeProfile(const std::string& path, const std::vector<FrameReport>& reports) {
    // Chrome trace events ("X" complete events, microseconds), one per pass per frame, on the GPU clock
    // relative to the first pass of the first frame. Opens in Perfetto and chrome://tracing.
    double origin = 1e300;
    for (const auto& r : reports)
        for (const PassTime& p : r.times.passes) origin = std::min(origin, p.startMs);
    std::vector<std::string> events;
    for (const auto& r : reports)
        for (const PassTime& p : r.times.passes) {
            json::Object e;
            e.text("name", p.name).text("cat", "gpu").text("ph", "X").integer("pid", 1).integer("tid", 1);
            e.real("ts", (p.startMs - origin) * 1000.0).real("dur", p.ms * 1000.0);
            e.raw("args", json::Object().integer("frame", r.frame).str(json::Style::Compact));
            events.push_back(e.str(json::Style::Compact));
        }
    json::Object trace;
    trace.text("displayTimeUnit", "ms").raw("traceEvents", json::array(events, ",\n", "[\n", "\n]"));
    return writeText(path, trace.str(json::Style::Compact) + "\n");
}

Result<void> writeFramesCsv(const std::string& path, const std::vector<FrameReport>& reports) {
    std::ostringstream o;
    o << "frame,pass,gpu_ms\n";
    for (const auto& r : reports)
        for (const PassTime& p : r.times.passes)
            o << r.frame << "," << p.name << "," << json::number(p.ms) << "\n";
    return writeText(path, o.str());
}

Result<void> writeStats(const std::string& path, const RunInfo& info,
                        const std::vector<FrameReport>& reports) {
    if (reports.empty()) return fail(path + ": no frame results arrived (nothing to report)");
    // Per-frame counts come from the last frame. Times: the first frame apart (first use of pipelines and
    // memory: 10x a later frame on lavapipe), means and the median over the frames after it.
    const FrameStats& s = reports.back().stats;
    const size_t from = reports.size() > 1 ? 1 : 0;
    double total = 0;
    std::vector<double> frameMs;
    // Per pass, in frame order: each frame's passes are in recording order, and a pass first seen in a
    // later frame (the VSM steps once maps are active) goes after the pass before it in that frame.
    std::vector<std::string> passOrder;
    std::vector<double> passMean;
    std::vector<uint32_t> passCount;
    // The VSM bookkeeping (the steps vsm_mark..vsm_expand, PassTimes::vsmBookkeepingMs): the mean of the
    // per-frame sums over the frames that ran it, so it equals the sum of the steps' means when each step
    // ran in those frames.
    double bookkeeping = 0;
    uint32_t bookkeepingFrames = 0;
    for (size_t i = from; i < reports.size(); ++i) {
        const auto& r = reports[i];
        total += r.times.totalMs();
        frameMs.push_back(r.times.totalMs());
        size_t at = 0; // where this frame's next new pass goes
        bool vsmRan = false;
        for (const PassTime& p : r.times.passes) {
            size_t k = size_t(std::find(passOrder.begin(), passOrder.end(), p.name) - passOrder.begin());
            if (k == passOrder.size()) {
                k = at;
                passOrder.insert(passOrder.begin() + std::ptrdiff_t(k), std::string(p.name));
                passMean.insert(passMean.begin() + std::ptrdiff_t(k), 0.0);
                passCount.insert(passCount.begin() + std::ptrdiff_t(k), 0u);
            }
            passMean[k] += p.ms, passCount[k]++;
            at = k + 1;
            vsmRan = vsmRan || p.group == kVsmBookkeeping;
        }
        if (vsmRan) bookkeeping += r.times.vsmBookkeepingMs(), bookkeepingFrames++;
    }
    std::sort(frameMs.begin(), frameMs.end());
    const double median = frameMs.size() % 2
                              ? frameMs[frameMs.size() / 2]
                              : 0.5 * (frameMs[frameMs.size() / 2 - 1] + frameMs[frameMs.size() / 2]);
    const double tight =
        s.lightsPerPixelReachingMean > 0 ? s.lightsPerPixelEvaluatedMean / s.lightsPerPixelReachingMean : 0;
    json::Object passes;
    for (size_t p = 0; p < passOrder.size(); ++p) passes.real(passOrder[p], passMean[p] / passCount[p]);
    json::Object o;
    o.text("scene", info.scene).text("culling", info.culling).text("device", info.device);
    o.integer("width", info.width).integer("height", info.height).integer("frames", reports.size());
    o.integer("seed", info.seed)
        .integer("lights_total", s.lightsTotal)
        .integer("lights_visible", s.lightsVisible);
    o.integer("clusters", s.clusters).integer("clusters_occupied", s.clustersOccupied);
    o.real("cluster_lights_mean", s.clusterLightsMean).integer("cluster_lights_max", s.clusterLightsMax);
    o.integer("cluster_overflow_count", s.clusterOverflowCount).integer("light_list_entries", s.poolEntries);
    o.integer("light_list_capacity", s.poolCapacity).integer("surface_pixels", s.surfacePixels);
    o.real("lights_per_pixel_evaluated_mean", s.lightsPerPixelEvaluatedMean);
    o.real("lights_per_pixel_reaching_mean", s.lightsPerPixelReachingMean).real("culling_tightness", tight);
    o.real("frame_gpu_ms_first", reports.front().times.totalMs());
    o.real("frame_gpu_ms_mean", total / double(frameMs.size())).real("frame_gpu_ms_median", median);
    o.raw("vsm", vsmJson(s.vsm)).raw("pass_gpu_ms_mean", passes.str());
    if (bookkeepingFrames) o.real("vsm_bookkeeping_gpu_ms_mean", bookkeeping / bookkeepingFrames);
    // Memory of the module's buffers and images by kind (gpu/memory.h roles), at the last frame.
    json::Object memory;
    for (uint32_t k = 0; k < kMemoryKindCount; ++k)
        memory.integer(memoryKindName(MemoryKind(k)), s.memory.bytes[k]);
    json::Object roles; // gpu/memory.h MemoryRole order
    const char* const roleNames[] = {"gpu_only", "upload", "readback", "staging"};
    for (uint32_t r = 0; r < 4; ++r) roles.integer(roleNames[r], s.memory.roleBytes[r]);
    o.raw("memory_bytes", memory.str()).raw("memory_bytes_by_role", roles.str());
    o.text("memory_placement", info.memoryPlacement);
    return writeText(path, o.str(json::Style::Lines) + "\n");
}

} // namespace ml
