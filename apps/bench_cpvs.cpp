// `manylights bench cpvs`: CPVS bakes of night-city spotlights from the CPU rasteriser's dual maps. The
// targets at 8K^3: bytes <= 1/256 of a 16-bit map of the same resolution, and insert + compress no
// longer than rendering the map. With --regions, the global bottom-up build against the region build
// (section 4.3) for each region count: per-phase times, peak nodes per region, peak live bytes, and the
// bytes must be equal. Minutes of CPU at the default 8192^3, so it is a command and not a ctest; the
// ctest runs it at 64^3. Prints a table, writes DIR/bench_cpvs.csv; the last stdout line is JSON.
#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/json.h"
#include "apps/options.h"
#include "bake/scene_casters.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "shadows/static/cpvs.h"
#include "shadows/static/raster_dual.h"

#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace ml {

static const char* kBenchCpvsHelp = R"(usage: manylights bench cpvs [options]
CPVS bakes of night-city static spotlights (dual maps from the CPU rasteriser): bytes against a 16-bit
map of the same resolution (goal 1/256) and insert + compress against rendering the map (goal: no longer).
  --res N          voxels per axis, a power of two 64..16384 (default 8192)
  --lights N       static spotlights, the scene's first N (default 4)
  --regions LIST   also bake with global bottom-up compression and with the region build for each
                   regionLog2 in LIST (e.g. 1,2,3,4): times, peaks, and the bytes must equal the global ones
  --verify         check every voxel of every bake against the voxelisation of its map (verifyCpvs)
  --out DIR        output folder for bench_cpvs.csv (default out/bench_cpvs)
Exits 1 when a region build's bytes differ from the global build or --verify finds a mismatch (the size
and time goals are reported, not enforced: small resolutions cannot meet the size goal).
Last stdout line: {"bench": "cpvs", "res": N, "lights": K, "mean_bytes": ..., "map_fraction": ...,
"bytes_goal_met": ..., "render_ms_mean": ..., "dag_ms_mean": ..., "time_goal_met": ..., "regions_equal": ...,
"mismatches": ...}
)";

namespace {

struct Row {
    size_t light = 0;
    std::string build; // "default", "global" or "regions R"
    double renderMs = 0;
    CpvsStats stats;
    bool equal = true; // region builds: bytes equal to the global build
    uint64_t mismatches = 0;
};

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

int runBenchCpvs(int argc, char** argv) {
    auto args = cli::parse(argc, argv, 3, {"--res", "--lights", "--regions", "--out"}, {"--verify"});
    if (!args) return usageError("bench cpvs", args.error());
    if (args->help) {
        std::fputs(kBenchCpvsHelp, stdout);
        return 0;
    }
    auto res = cli::parseUint("--res", args->get("--res", "8192"), kCpvsMinResolution, kCpvsMaxResolution);
    auto lightCount = cli::parseUint("--lights", args->get("--lights", "4"), 1, 256);
    for (const std::string* e : {&res.error(), &lightCount.error()})
        if (!e->empty()) return usageError("bench cpvs", *e);
    const uint32_t n = res.value();
    if (n & (n - 1))
        return usageError("bench cpvs", "--res: '" + args->get("--res", "") + "' is not a power of two");
    std::vector<uint32_t> regionLogs;
    if (args->has("--regions")) {
        auto list = opts::uintList("--regions", args->get("--regions", ""), 0, 9);
        if (!list) return usageError("bench cpvs", list.error());
        regionLogs = list.value();
    }
    const bool verify = args->has("--verify");
    const std::string out = args->get("--out", "out/bench_cpvs");
    if (auto r = cli::checkOutputDirectory("--out", out); !r) return usageError("bench cpvs", r.error());

    auto scene = loadScene("night-city", 256, 1);
    if (!scene) return inputError("bench cpvs", scene.error());
    const CasterTriangles casters = castersFromScene(*scene);
    std::vector<Light> spots;
    for (const Light& l : scene->lights)
        if (l.type == LightKind::Spot && !l.dynamic && spots.size() < lightCount.value()) spots.push_back(l);
    if (spots.empty()) return runError("bench cpvs", "the scene has no static spotlight");

    std::vector<Row> rows;
    for (size_t li = 0; li < spots.size(); ++li) {
        const LightFrustum f = spotLightFrustum(spots[li]);
        const auto t0 = std::chrono::steady_clock::now();
        const DualDepthMap map = rasterizeDual(casters, f, n);
        const double renderMs = msSince(t0);
        CpvsParams p;
        p.resolution = n;
        p.nearPlane = f.nearPlane;
        p.farPlane = f.farPlane;
        // (build name, compression, regionLog2): the shipped default first, then the comparison builds.
        std::vector<std::tuple<std::string, CpvsCompression, uint32_t>> builds{
            {"default", p.compression, p.regionLog2}};
        if (!regionLogs.empty()) builds.emplace_back("global", CpvsCompression::BottomUp, 0);
        for (uint32_t r : regionLogs)
            builds.emplace_back("regions " + std::to_string(r), CpvsCompression::Regions, r);
        std::vector<uint32_t> global;
        for (const auto& [name, compression, regionLog2] : builds) {
            p.compression = compression;
            p.regionLog2 = regionLog2;
            auto bake = bakeCpvs(map, p);
            if (!bake) return runError("bench cpvs", "light " + std::to_string(li) + ": " + bake.error());
            Row row{li, name, renderMs, bake->stats};
            if (name == "global") global = bake->data;
            if (name.starts_with("regions")) row.equal = bake->data == global;
            if (verify) row.mismatches = verifyCpvs(bake->data.data(), map).mismatches;
            std::fprintf(stderr, "  light %zu %s: %llu B, insert+compress %.0f ms\n", li, name.c_str(),
                         (unsigned long long)row.stats.bytes.total,
                         row.stats.insertMs + row.stats.compressMs);
            rows.push_back(std::move(row));
        }
    }

    const double mapBytes = 2.0 * n * n; // a 16-bit shadow map of the same resolution
    std::printf("bench cpvs: night-city, %u^3, %zu static spotlights%s\n", n, spots.size(),
                verify ? ", every voxel verified" : "");
    std::printf(
        "| light | build | render ms | precompute ms | insert ms | compress ms | merge ms | layout ms | "
        "bytes "
        "| of 16-bit map | nodes inserted | nodes final | leaves final | regions | peak region nodes | "
        "peak live MB | equal | mismatches |\n");
    std::printf(
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|\n");
    std::ostringstream csv;
    csv << "light,build,render_ms,precompute_ms,insert_ms,compress_ms,merge_ms,layout_ms,bytes,nodes_"
           "inserted,"
           "nodes_final,leaves_inserted,leaves_final,regions,region_nodes_peak,live_bytes_peak,equal,"
           "mismatches\n";
    double bytes = 0, renderMs = 0, dagMs = 0;
    uint64_t mismatches = 0;
    bool equal = true;
    for (const Row& r : rows) {
        const CpvsStats& s = r.stats;
        std::printf(
            "| %zu | %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %llu | 1/%.1f | %llu | %llu | %llu | %u "
            "| %llu | %.1f | %s | %llu |\n",
            r.light, r.build.c_str(), r.renderMs, s.precomputeMs, s.insertMs, s.compressMs, s.mergeMs,
            s.layoutMs, (unsigned long long)s.bytes.total, mapBytes / double(s.bytes.total),
            (unsigned long long)s.nodesInserted, (unsigned long long)s.nodesFinal,
            (unsigned long long)s.leavesFinal, s.regions, (unsigned long long)s.regionNodesPeak,
            s.liveBytesPeak / 1048576.0, r.equal ? "yes" : "NO", (unsigned long long)r.mismatches);
        csv << r.light << "," << r.build << "," << r.renderMs << "," << s.precomputeMs << "," << s.insertMs
            << "," << s.compressMs << "," << s.mergeMs << "," << s.layoutMs << "," << s.bytes.total << ","
            << s.nodesInserted << "," << s.nodesFinal << "," << s.leavesInserted << "," << s.leavesFinal
            << "," << s.regions << "," << s.regionNodesPeak << "," << s.liveBytesPeak << ","
            << (r.equal ? 1 : 0) << "," << r.mismatches << "\n";
        equal = equal && r.equal;
        mismatches += r.mismatches;
        if (r.build != "default") continue; // the goals are the shipped build's
        bytes += double(s.bytes.total);
        renderMs += r.renderMs;
        dagMs += s.insertMs + s.compressMs;
    }
    const double k = double(spots.size()), meanBytes = bytes / k;
    std::printf(
        "mean %.0f B = 1/%.1f of a 16-bit %u^2 map (goal 1/256: %s); mean render %.0f ms, insert+compress "
        "%.0f ms (goal: no longer than render: %s)\n",
        meanBytes, mapBytes / meanBytes, n, meanBytes <= mapBytes / 256.0 ? "met" : "missed", renderMs / k,
        dagMs / k, dagMs <= renderMs ? "met" : "missed");
    if (auto r = cli::makeDirectory(out); !r) return runError("bench cpvs", r.error());
    if (auto w = io::writeFileAtomically(out + "/bench_cpvs.csv", csv.str()); !w)
        return runError("bench cpvs", w.error());
    std::printf("wrote %s/bench_cpvs.csv\n", out.c_str());
    const bool bytesMet = meanBytes <= mapBytes / 256.0, timeMet = dagMs <= renderMs;
    json::Object summary;
    summary.text("bench", "cpvs").integer("res", n).integer("lights", spots.size());
    summary.real("mean_bytes", meanBytes, "%.0f").real("map_fraction", meanBytes / mapBytes);
    summary.raw("bytes_goal_met", bytesMet ? "true" : "false").real("render_ms_mean", renderMs / k, "%.1f");
    summary.real("dag_ms_mean", dagMs / k, "%.1f").raw("time_goal_met", timeMet ? "true" : "false");
    summary.raw("regions_equal", equal ? "true" : "false").integer("mismatches", mismatches);
    std::printf("%s\n", summary.str().c_str());
    return equal && mismatches == 0 ? 0 : 1;
}

} // namespace ml
