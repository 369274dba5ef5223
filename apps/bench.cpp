// `manylights bench culling`: culling and shading GPU time as lights grow, for clustered (footprint),
// clustered-brute, tiled and no culling, measured in one run on one device. Prints a table and writes
// a CSV. Times are per-pass means over --frames after one warm-up frame (GPU timestamps, or fenced
// submits on CPU devices); lights per pixel, box tests and list entries come from one extra frame with
// statistics on, so the counting loop never inflates the timed frames.
#include "apps/commands.h"
#include "apps/options.h"
#include "engine/manylights_diagnostics.h"
#include "io/safe_io.h"
#include "host/scene_host.h"
#include "scenes/scenes.h"
#include "shaders/shared/config.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace ml {

static const char* kBenchHelp =
    R"(usage: manylights bench culling|static|vsm|vsm-rays|flicker|cpvs|sizes|cpu|record|soak [options]
(`manylights bench static --help` for the static shadow benchmark, `bench flicker --help` for the
static shadows' temporal stability along a camera path, `bench vsm`, `bench vsm-rays` (virtual
shadow maps against rays), `bench cpvs`, `bench sizes` and
`bench cpu --help` (the module's CPU time per frame), `bench record --help` (record()'s CPU time in
frame 0 and after an LDR/HDR switch) and `bench soak --help` (memory over 10,000 frames) for theirs)
Culling and shading time against light count, for each culling mode, in one run; every pass timed
fenced (its own submission, timed to completion: lavapipe's timestamps do not bracket compute).
Every flag of every command may be given once; a flag's value cannot be another flag.
  --size WxH       image size (default 640x360)
  --lights LIST    comma-separated light counts (default 256,1024,4096)
  --culling LIST   modes to run (default clustered,clustered-brute,tiled,none); "vs none" needs none
  --frames N       timed frames per configuration (default 5)
  --seed S         scene seed (default 1)
  --directional D  on (default) or off: the night city's moon (a directional light) in or out
  --csv FILE       CSV output (default out/bench_culling.csv)
  --compare-zbin   also run Z-binning (Drobot 2017; culling/zbin.h) on each light count's clustered
                   frame, with and without the tiles' depth test, and print it beside the footprint
                   clusters: assignment ms and evaluated / reaching lights per pixel (needs clustered
                   in --culling; the evaluation pass keeps the clusters' lists)
)";

namespace {

struct Row {
    uint32_t lights;
    CullingMode mode;
    double boundsMs, assignMs, evalMs, gbufferMs;
    double evaluated, reaching;
    uint32_t boxTests, entries, overflow;
};

Result<std::vector<FrameReport>> runFrames(Module& m, uint32_t count) {
    std::vector<FrameReport> reports;
    for (uint32_t i = 0; i < count; ++i) {
        if (auto r = m.submitFrame(); !r) return fail(r.error());
        m.collect();
        for (auto& r : m.takeReports()) reports.push_back(r);
    }
    return reports;
}
// One culling mode on a module holding the scene: a counted frame (statistics on), a warm-up frame and
// the timed frames; per-pass means.
Result<Row> measureMode(Module& m, uint32_t lights, CullingMode mode, uint32_t frames) {
    m.setCulling(mode);
    m.setStatistics(true);
    auto counted = runFrames(m, 1);
    m.setStatistics(false);
    auto warm = runFrames(m, 1);
    auto timed = runFrames(m, frames);
    if (!counted) return fail(counted.error());
    uint32_t boxTests = diag::cullingBoxTests(m); // the counted frame has completed
    if (!warm || !timed) return fail("frame failed");
    vkDeviceWaitIdle(m.deviceInfo().device);
    m.collect();
    for (auto& r : m.takeReports()) timed->push_back(r);
    Row row{lights, mode, 0, 0, 0, 0, 0, 0, mode == CullingMode::None ? 0u : boxTests, 0, 0};
    uint32_t n = 0;
    for (const auto& r : timed.value()) {
        row.boundsMs += r.times.ms("cluster_bounds");
        row.assignMs += r.times.ms("light_assign");
        row.evalMs += r.times.ms("evaluate");
        row.gbufferMs += r.times.ms("gbuffer");
        ++n;
    }
    row.boundsMs /= n;
    row.assignMs /= n;
    row.evalMs /= n;
    row.gbufferMs /= n;
    if (counted->empty()) return fail("no statistics frame arrived");
    const FrameStats& s = counted->front().stats;
    row.evaluated = s.lightsPerPixelEvaluatedMean;
    row.reaching = s.lightsPerPixelReachingMean;
    row.overflow = s.clusterOverflowCount;
    row.entries = s.poolEntries;
    std::fprintf(stderr, "  %u lights, %s: cull %.2f ms (assign %.2f), evaluate %.2f ms\n", lights,
                 cullingName(mode), row.boundsMs + row.assignMs, row.assignMs, row.evalMs);
    return row;
}

// The table on stdout; the CSV's text.
std::string printRows(const std::vector<Row>& rows) {
    std::printf(
        "| lights | culling         | bounds ms | assign ms | cull ms | evaluate ms | cull+eval ms | vs none "
        "| box tests | list entries | evaluated/px | reaching/px | eval/reach | overflow |\n");
    std::printf(
        "|-------:|-----------------|----------:|----------:|--------:|------------:|-------------:|--------:"
        "|----------:|-------------:|-------------:|------------:|-----------:|---------:|\n");
    std::ostringstream csv;
    csv << "lights,culling,bounds_ms,assign_ms,cull_ms,evaluate_ms,gbuffer_ms,cull_plus_eval_ms,speedup_vs_"
           "none,"
           "box_tests,list_entries,evaluated_per_pixel,reaching_per_pixel,overflow_clusters\n";
    for (const Row& r : rows) {
        double cull = r.boundsMs + r.assignMs, total = cull + r.evalMs, speedup = 0;
        for (const Row& none : rows) // the none row of the same light count, when it ran
            if (none.lights == r.lights && none.mode == CullingMode::None && total > 0)
                speedup = none.evalMs / total;
        double ratio = r.reaching > 0 ? r.evaluated / r.reaching : 0;
        std::printf("| %6u | %-15s | %9.2f | %9.2f | %7.2f | %11.2f | %12.2f | %6.2fx | %9u | %12u | %12.2f "
                    "| %11.2f | %10.2f | %8u |\n",
                    r.lights, cullingName(r.mode), r.boundsMs, r.assignMs, cull, r.evalMs, total, speedup,
                    r.boxTests, r.entries, r.evaluated, r.reaching, ratio, r.overflow);
        csv << r.lights << "," << cullingName(r.mode) << "," << r.boundsMs << "," << r.assignMs << "," << cull
            << "," << r.evalMs << "," << r.gbufferMs << "," << total << "," << speedup << "," << r.boxTests
            << "," << r.entries << "," << r.evaluated << "," << r.reaching << "," << r.overflow << "\n";
    }
    return csv.str();
}

// One Z-binning run beside its light count's clustered row (diag::measureZBin).
struct ZBinRow {
    uint32_t lights;
    bool depthTest;
    double boundsMs; // the clustered frame's cluster_bounds (the depth test's input)
    diag::ZBinMeasure z;
};

// Footprint clusters and Z-binning side by side, per light count (docs/culling.md). The evaluation pass
// reads the clusters' lists only, so Z-binning's evaluate ms is projected: the clusters' measured
// evaluate ms plus what the shading-loop probe (culling/zbin_shade.comp, same loop body over both
// candidate sets) took longer over the Z-bin candidates.
void printZBin(const std::vector<Row>& rows, const std::vector<ZBinRow>& zrows) {
    std::printf(
        "\nZ-binning side by side. assign: clusters bounds + assign; Z-bins mask + bins (+ bounds with "
        "the tile depth test). host: Z-bins' footprints + sort + upload (CPU). shade probe: the "
        "light term over each scheme's candidates (no visibility; Z-bin rows: Z-bins / clusters, run in "
        "turn). evaluate: measured for the "
        "clusters; Z-bins: clusters' + (probe Z-bins - probe clusters).\n");
    std::printf("| lights | scheme                 | assign ms | parts ms                        | host ms "
                "| evaluated/px | reaching/px | eval/reach | tile alone/px | exact depth/px | shade probe ms "
                "| evaluate ms | assign+eval ms |\n");
    std::printf("|-------:|------------------------|----------:|---------------------------------|--------:"
                "|-------------:|------------:|-----------:|--------------:|---------------:|---------------:"
                "|------------:|---------------:|\n");
    for (const Row& r : rows) {
        if (r.mode != CullingMode::Clustered) continue;
        char parts[64];
        std::snprintf(parts, sizeof parts, "bounds %.2f + assign %.2f", r.boundsMs, r.assignMs);
        double probe = 0; // the clusters' probe, a mean over the Z-bin runs (each ran it beside its own)
        uint32_t probes = 0;
        for (const ZBinRow& z : zrows)
            if (z.lights == r.lights) probe += z.z.shadeClustersMs, ++probes;
        probe /= std::max(1u, probes);
        std::printf("| %6u | clustered (footprint)  | %9.2f | %-31s |       - | %12.2f | %11.2f | %10.2f "
                    "|             - |              - | %14.2f | %11.2f | %14.2f |\n",
                    r.lights, r.boundsMs + r.assignMs, parts, r.evaluated, r.reaching,
                    r.reaching > 0 ? r.evaluated / r.reaching : 0.0, probe, r.evalMs,
                    r.boundsMs + r.assignMs + r.evalMs);
        for (const ZBinRow& z : zrows) {
            if (z.lights != r.lights) continue;
            const double px = z.z.surface ? double(z.z.surface) : 1.0;
            const double ev = z.z.evaluated / px, re = z.z.reaching / px;
            const double assign = (z.depthTest ? z.boundsMs : 0.0) + z.z.maskMs + z.z.binsMs;
            const double eval = r.evalMs + z.z.shadeZBinMs - z.z.shadeClustersMs;
            std::snprintf(parts, sizeof parts, "%smask %.2f + bins %.2f", z.depthTest ? "bounds + " : "",
                          z.z.maskMs, z.z.binsMs);
            std::printf("| %6u | %-22s | %9.2f | %-31s | %7.2f | %12.2f | %11.2f | %10.2f | %13.2f | %14.2f "
                        "| %6.2f / %6.2f | ~%10.2f | ~%13.2f |\n",
                        z.lights, z.depthTest ? "zbin (tile depth test)" : "zbin (rectangles)", assign, parts,
                        z.z.hostMs, ev, re, re > 0 ? ev / re : 0.0, z.z.tile / px, z.z.exact / px,
                        z.z.shadeZBinMs, z.z.shadeClustersMs, eval, assign + eval);
        }
    }
}

// The flags of `bench culling` beside its option groups.
const cli::Flags kCullingFlags{{"--lights", "--csv", "--culling", "--directional"}, {"--compare-zbin"}};

int runBenchCulling(int argc, char** argv) {
    int status = 0;
    const auto args =
        commandArgs("bench", kBenchHelp,
                    cli::parse(argc, argv, 3, {opts::kSeedFlags, opts::kViewFlags, kCullingFlags}), status);
    if (!args) return status;
    auto view = opts::view(*args, {5, 1, 1000, "640x360"});
    auto list = opts::uintList("--lights", args->get("--lights", "256,1024,4096"), 1, ML_MAX_LIGHTS);
    auto seed = opts::seed(*args);
    auto modes =
        opts::cullingList("--culling", args->get("--culling", "clustered,clustered-brute,tiled,none"));
    for (const std::string* e : {&view.error(), &list.error(), &seed.error(), &modes.error()})
        if (!e->empty()) return usageError("bench", *e);
    const std::string csvPath = args->get("--csv", "out/bench_culling.csv");
    if (auto r = cli::checkOutputFile("--csv", csvPath); !r)
        return usageError("bench", r.error()); // before the runs
    const std::string directional = args->get("--directional", "on");
    if (directional != "on" && directional != "off")
        return usageError("bench", "--directional must be on or off, got '" + directional + "'");
    const bool compareZBin = args->has("--compare-zbin");
    if (compareZBin && std::find(modes->begin(), modes->end(), CullingMode::Clustered) == modes->end())
        return usageError("bench", "--compare-zbin needs clustered in --culling");
    std::vector<Row> rows;
    std::vector<ZBinRow> zrows;
    std::string deviceName;
    for (uint32_t lights : list.value()) {
        auto scene = loadScene("night-city", lights, seed.value());
        if (!scene) return runError("bench", scene.error());
        if (directional == "off")
            std::erase_if(scene->lights, [](const Light& l) { return l.type == LightKind::Directional; });
        // Fenced: each pass timed from submit to completion. lavapipe's timestamps do not bracket
        // compute work, so the default (timestamps) read near zero for the culling and evaluation passes.
        ModuleOptions options;
        options.timing = TimingChoice::Fenced;
        auto module = Module::create(options);
        if (!module) return runError("bench", module.error());
        Module& m = *module.value();
        deviceName = m.deviceInfo().name;
        auto binding = bindScene(m, scene.value());
        if (!binding) return runError("bench", binding.error());
        if (auto r = m.createTargets(view->width, view->height); !r) return usageError("bench", r.error());
        for (CullingMode mode : modes.value()) {
            auto row = measureMode(m, lights, mode, view->frames);
            if (!row) return runError("bench", row.error());
            rows.push_back(row.value());
            if (!compareZBin || mode != CullingMode::Clustered) continue;
            // The module's last frame is this mode's last timed one: its depth, lights, tile masks.
            for (bool depthTest : {false, true}) {
                auto z = diag::measureZBin(m, depthTest, view->frames);
                if (!z) return runError("bench", z.error());
                std::fprintf(stderr, "  %u lights, zbin%s: mask %.2f ms, bins %.2f ms, host %.2f ms\n",
                             lights, depthTest ? " (tile depth test)" : "", z->maskMs, z->binsMs, z->hostMs);
                zrows.push_back({lights, depthTest, row->boundsMs, z.value()});
            }
        }
    }
    std::printf("bench culling: night-city, %ux%u, %u timed frames each, directional light %s, %s\n",
                view->width, view->height, view->frames, directional.c_str(), deviceName.c_str());
    const std::string csv = printRows(rows);
    if (compareZBin) printZBin(rows, zrows);
    if (auto w = io::writeFileAtomically(csvPath, csv); !w) return runError("bench", w.error());
    std::printf("wrote %s\n", csvPath.c_str());
    return 0;
}
} // namespace

int runBench(int argc, char** argv) {
    if (argc < 3 || std::string(argv[2]) == "--help" || std::string(argv[2]) == "-h") {
        std::fputs(kBenchHelp, argc < 3 ? stderr : stdout);
        return argc < 3 ? kExitUsage : 0;
    }
    if (std::string(argv[2]) == "static") return runBenchStatic(argc, argv);
    if (std::string(argv[2]) == "vsm") return runBenchVsm(argc, argv);
    if (std::string(argv[2]) == "vsm-rays") return runBenchVsmRays(argc, argv);
    if (std::string(argv[2]) == "flicker") return runBenchFlicker(argc, argv);
    if (std::string(argv[2]) == "cpvs") return runBenchCpvs(argc, argv);
    if (std::string(argv[2]) == "sizes") return runBenchSizes(argc, argv);
    if (std::string(argv[2]) == "cpu") return runBenchCpu(argc, argv);
    if (std::string(argv[2]) == "record") return runBenchRecord(argc, argv);
    if (std::string(argv[2]) == "soak") return runBenchSoak(argc, argv);
    if (std::string(argv[2]) != "culling")
        return usageError(
            "bench", std::string("unknown benchmark '") + argv[2] +
                         "' (culling, static, vsm, vsm-rays, flicker, cpvs, sizes, cpu, record or soak)");
    return runBenchCulling(argc, argv);
}

} // namespace ml
