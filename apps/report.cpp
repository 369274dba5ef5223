#include "apps/report.h"
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
// A JSON string literal: quotes, backslashes and control characters escaped.
std::string jsonText(const std::string& s) {
    std::string o;
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\', o += char(c);
        } else if (c < 0x20 || c == 0x7F) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            o += buf;
        } else {
            o += char(c);
        }
    }
    return o;
}
std::string num(double v) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.6g", v);
    return buf;
}
} // namespace

Result<void> writeProfile(const std::string& path, const std::vector<FrameReport>& reports) {
    // Chrome trace events ("X" complete events, microseconds), one per pass per frame, on the GPU clock
    // relative to the first pass of the first frame. Opens in Perfetto and chrome://tracing.
    double origin = 1e300;
    for (const auto& r : reports)
        for (uint32_t p = 0; p < kPassCount; ++p)
            if (r.times.ran[p]) origin = std::min(origin, r.times.startMs[p]);
    std::ostringstream o;
    o << "{\"displayTimeUnit\":\"ms\",\"traceEvents\":[\n";
    bool first = true;
    for (const auto& r : reports)
        for (uint32_t p = 0; p < kPassCount; ++p) {
            if (!r.times.ran[p]) continue;
            o << (first ? "" : ",\n") << "{\"name\":\"" << passName(Pass(p))
              << "\",\"cat\":\"gpu\",\"ph\":\"X\",\"pid\":1,"
              << "\"tid\":1,\"ts\":" << num((r.times.startMs[p] - origin) * 1000.0)
              << ",\"dur\":" << num(r.times.ms[p] * 1000.0) << ",\"args\":{\"frame\":" << r.frame << "}}";
            first = false;
        }
    o << "\n]}\n";
    return writeText(path, o.str());
}

Result<void> writeFramesCsv(const std::string& path, const std::vector<FrameReport>& reports) {
    std::ostringstream o;
    o << "frame,pass,gpu_ms\n";
    for (const auto& r : reports)
        for (uint32_t p = 0; p < kPassCount; ++p)
            if (r.times.ran[p]) o << r.frame << "," << passName(Pass(p)) << "," << num(r.times.ms[p]) << "\n";
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
    std::vector<double> passMean(kPassCount, 0.0);
    std::vector<uint32_t> passCount(kPassCount, 0);
    for (size_t i = from; i < reports.size(); ++i) {
        const auto& r = reports[i];
        total += r.times.totalMs();
        frameMs.push_back(r.times.totalMs());
        for (uint32_t p = 0; p < kPassCount; ++p)
            if (r.times.ran[p]) passMean[p] += r.times.ms[p], passCount[p]++;
    }
    std::sort(frameMs.begin(), frameMs.end());
    const double median = frameMs.size() % 2
                              ? frameMs[frameMs.size() / 2]
                              : 0.5 * (frameMs[frameMs.size() / 2 - 1] + frameMs[frameMs.size() / 2]);
    std::ostringstream o;
    o << "{\n";
    o << "  \"scene\": \"" << jsonText(info.scene) << "\",\n  \"culling\": \"" << info.culling << "\",\n";
    o << "  \"device\": \"" << jsonText(info.device) << "\",\n";
    o << "  \"width\": " << info.width << ",\n  \"height\": " << info.height << ",\n";
    o << "  \"frames\": " << reports.size() << ",\n  \"seed\": " << info.seed << ",\n";
    o << "  \"lights_total\": " << s.lightsTotal << ",\n";
    o << "  \"lights_visible\": " << s.lightsVisible << ",\n";
    o << "  \"clusters\": " << s.clusters << ",\n";
    o << "  \"clusters_occupied\": " << s.clustersOccupied << ",\n";
    o << "  \"cluster_lights_mean\": " << num(s.clusterLightsMean) << ",\n";
    o << "  \"cluster_lights_max\": " << s.clusterLightsMax << ",\n";
    o << "  \"cluster_overflow_count\": " << s.clusterOverflowCount << ",\n";
    o << "  \"light_list_entries\": " << s.poolEntries << ",\n";
    o << "  \"light_list_capacity\": " << s.poolCapacity << ",\n";
    o << "  \"surface_pixels\": " << s.surfacePixels << ",\n";
    o << "  \"lights_per_pixel_evaluated_mean\": " << num(s.lightsPerPixelEvaluatedMean) << ",\n";
    o << "  \"lights_per_pixel_reaching_mean\": " << num(s.lightsPerPixelReachingMean) << ",\n";
    double tight =
        s.lightsPerPixelReachingMean > 0 ? s.lightsPerPixelEvaluatedMean / s.lightsPerPixelReachingMean : 0;
    o << "  \"culling_tightness\": " << num(tight) << ",\n";
    o << "  \"frame_gpu_ms_first\": " << num(reports.front().times.totalMs()) << ",\n";
    o << "  \"frame_gpu_ms_mean\": " << num(total / double(frameMs.size())) << ",\n";
    o << "  \"frame_gpu_ms_median\": " << num(median) << ",\n";
    const VsmStats& v = s.vsm;
    o << "  \"vsm\": {\"pages_marked\": " << v.pagesMarked << ", \"pages_allocated\": " << v.pagesAllocated
      << ", \"pages_cached\": " << v.pagesCached << ", \"pages_rendered\": " << v.pagesRendered
      << ", \"pages_invalidated\": " << v.pagesInvalidated << ", \"pages_evicted\": " << v.pagesEvicted
      << ", \"fallbacks\": " << v.fallbacks << ", \"pool_pages\": " << v.poolPages
      << ", \"pool_bytes\": " << v.poolBytes << ", \"used_bytes\": " << v.usedBytes
      << ", \"virtual_bytes\": " << v.virtualBytes << ", \"atlas_bytes\": " << v.atlasBytes
      << ", \"lights_with_pages\": " << v.lightsWithPages
      << ", \"lights_without_slot\": " << v.lightsWithoutSlot << ", \"maps_active\": " << v.mapsActive
      << ", \"instances_drawn\": " << v.instancesDrawn
      << ", \"instances_culled_hpb\": " << v.instancesCulledHpb << ", \"draw_overflow\": " << v.drawOverflow
      << ", \"raster\": \"" << (v.meshPath ? "mesh" : "vertex")
      << "\", \"meshlets_total\": " << v.meshletsTotal
      << ", \"meshlets_after_expansion\": " << v.meshletsAfterExpansion
      << ", \"meshlets_after_task\": " << v.meshletsAfterTask
      << ", \"triangles_after_task\": " << v.trianglesAfterTask
      << ", \"triangles_rasterized\": " << v.trianglesRasterized
      << ", \"meshlet_overflow\": " << v.meshletOverflow << "},\n";
    o << "  \"pass_gpu_ms_mean\": {";
    bool first = true;
    for (uint32_t p = 0; p < kPassCount; ++p) {
        if (!passCount[p]) continue;
        o << (first ? "" : ", ") << "\"" << passName(Pass(p)) << "\": " << num(passMean[p] / passCount[p]);
        first = false;
    }
    o << "}\n}\n";
    return writeText(path, o.str());
}

} // namespace ml
