// `manylights bench vsm`: virtual shadow maps along a camera path, cached against uncached (every marked
// page redrawn every frame) in the same run, per light kind (the seed's Table 1 shape: RMVSM section 5):
// static spot lights, moving spot lights (headlights), point lights, the directional light. Each row is a
// run of the path in which only that kind has maps. Times are fenced per-pass times (each pass submitted
// and timed on its own: honest on lavapipe), means over the frames after the first (first use of
// pipelines). Writes DIR/bench_vsm.csv (per frame) and DIR/bench_vsm.json; the last stdout line is JSON.
// With --vsm-raster both (default) every run is made once per page-draw path (mesh: meshlets with task and
// mesh shaders; vertex: indexed draws), fragments drawn beside the dirty pages' texels, and a second table
// gives the mesh path's culling stages: the share of the meshlets of (caster, map, dirty mip) each stage
// removed, summed over the frames after the first.
#include "apps/commands.h"
#include "apps/json.h"
#include "apps/vsm_args.h"
#include "engine/manylights_diagnostics.h"
#include "host/vsm_session.h"
#include "shaders/shared/config.h"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace ml {

static const char* kBenchVsmHelp = R"(usage: manylights bench vsm [options]
Virtual shadow maps on a camera path: pass times and page counts, cached against uncached, per light kind.
  --scene S       night-city (default), indoor (rooms: spot, point lights, carts) or a .gltf / .glb file
  --path P        drive (default), orbit or static
  --frames N      frames per run (default 20; the first is reported apart)
  --size WxH      frame size (default 640x360)
  --lights N      lights in the scene (default 256)
  --seed S        scene seed (default 1)
  --bake FILE     static bake of this scene (then static lights' maps hold dynamic casters only)
  --vsm-res N     virtual resolution (default 4096)
  --vsm-page N    page size: 32, 64 (default), 128
  --vsm-pool N    physical pages (default 4096)
  --vsm-mark M    page marking: pixel (default: per receiver pixel) or cluster (per cluster and light)
  --vsm-texels T  shadow texels per pixel footprint: 0.25, 0.5, 1 (default), 2, 4 or 8
  --kinds LIST    rows to run, comma-separated from static-spot,moving-spot,point,directional (default all)
  --vsm-raster R  page-draw path: mesh, vertex, auto or both (default both: every row once per path)
  --meshlet VxT   meshlet limits: vertices x triangles (default 64x124, at most that; triangles a multiple of 4)
  --vsm-page-clip on|off  page draws clipped to their dirty page (default on); off: each draw covers its
                  mip's whole virtual resolution and fragments outside dirty pages are discarded (baseline)
  --out DIR       output folder (default out/bench_vsm)
Last stdout line: {"cached_draw_ms_mean": ..., "uncached_draw_ms_mean": ..., "pages_allocated_mean": ...,
"fallbacks_total": ..., ...} (the means over the first path given: mesh with both)
)";

namespace {

struct Row {
    std::string kind;
    bool cached = true;
    VsmRaster raster = VsmRaster::Mesh;
    // Per-step means (manylights/pass_times.h): cull on the vertex path, expand on the mesh path (0
    // otherwise).
    double markMs = 0, sortMs = 0, allocMs = 0, hpbMs = 0, groupCullMs = 0, cullMs = 0, expandMs = 0,
           drawMs = 0, frames = 0;
    double marked = 0, allocated = 0, rendered = 0, draws = 0, triangles = 0;
    // Page draws: the first frame's draw ms (pipelines' first use; every page new), and per frame after
    // it the fragment-shader invocations against the texels of the pages rendered.
    double firstDrawMs = 0, fragments = 0, dirtyTexels = 0;
    // Mesh path, summed over the frames after the first: meshlets at each stage.
    uint64_t total = 0, expFrustum = 0, expHpb = 0, afterExp = 0, taskFrustum = 0, taskCone = 0, taskHpb = 0,
             afterTask = 0, trisAfterTask = 0, trisRaster = 0, overflow = 0;
    uint64_t fallbacks = 0;
    uint32_t lightsWithPages = 0;
};

const char* rasterName(VsmRaster r) {
    return r == VsmRaster::Mesh ? "mesh" : "vertex";
}

struct Config {
    VsmSessionOptions options;
    uint32_t frames = 0;
    std::vector<std::string> kinds;
    std::vector<VsmRaster> rasters;
    std::pair<uint32_t, uint32_t> meshlet;
    std::string out;
};

Result<Config> parseConfig(const cli::Args& args) {
    Config c;
    auto options = vsmSessionOptions(args, {20, 2, "640x360", 4096}, c.frames);
    if (!options) return fail(options.error());
    c.options = options.value();
    auto kinds = opts::splitList("--kinds", args.get("--kinds", "static-spot,moving-spot,point,directional"));
    if (!kinds) return fail(kinds.error());
    for (const std::string& k : kinds.value())
        if (k != "static-spot" && k != "moving-spot" && k != "point" && k != "directional")
            return fail("--kinds: unknown kind '" + k + "' (static-spot, moving-spot, point, directional)");
    c.kinds = kinds.value();
    if (args.get("--vsm-raster", "both") == "both") {
        c.rasters = {VsmRaster::Mesh, VsmRaster::Vertex};
    } else {
        auto one = vsmRaster(args);
        if (!one)
            return fail("--vsm-raster takes mesh, vertex, auto or both, not '" +
                        args.get("--vsm-raster", "") + "'");
        c.rasters = {one.value()};
    }
    auto meshlet = cli::parseSize("--meshlet", args.get("--meshlet", "64x124"));
    if (!meshlet) return fail(meshlet.error());
    c.meshlet = meshlet.value();
    c.out = args.get("--out", "out/bench_vsm");
    const std::string clip = args.get("--vsm-page-clip", "on");
    if (clip != "on" && clip != "off") return fail("--vsm-page-clip takes on or off, not '" + clip + "'");
    c.options.module.vsm.pageClip = clip == "on";
    return c;
}

// One run of the path with only `kind`'s maps: its per-frame CSV lines, and the row of means.
Result<Row> measureRun(const Config& c, const std::string& kind, bool cached, VsmRaster raster, bool first,
                       std::ostringstream& csv) {
    VsmSessionOptions o = c.options;
    o.module.timing = TimingChoice::Fenced;
    o.module.vsm.caching = cached;
    o.module.vsm.raster = raster;
    std::tie(o.module.vsm.meshletVertices, o.module.vsm.meshletTriangles) = c.meshlet;
    o.module.vsm.kinds = kind == "point" ? 2u : kind == "directional" ? 4u : 1u;
    o.module.vsm.movingLights = kind != "static-spot";
    o.module.vsm.staticLights = kind != "moving-spot";
    auto session = VsmSession::create(o);
    if (!session) return fail(session.error());
    VsmSession& s = *session.value();
    if (first) {
        const diag::SceneCounts counts = diag::sceneCounts(*s.module);
        std::fprintf(stderr, "  %u meshes, %u instances, %u meshlets of at most %u vertices / %u triangles\n",
                     counts.meshes, counts.instances, counts.meshlets, c.meshlet.first, c.meshlet.second);
    }
    Row row;
    row.kind = kind;
    row.cached = cached;
    // Auto resolves at creation (vertex on CPU devices): report the path that ran.
    row.raster = diag::vsmMeshPath(*s.module) ? VsmRaster::Mesh : VsmRaster::Vertex;
    for (uint32_t f = 0; f < c.frames; ++f) {
        auto r = s.frame(f);
        if (!r) return fail(r.error());
        const PassTimes& t = r->times;
        const VsmStats& v = r->stats.vsm;
        auto ms = [&](const char* pass) { return t.ms(pass); }; // 0 when the step did not run
        csv << row.kind << "," << (row.cached ? "cached" : "uncached") << "," << rasterName(row.raster) << ","
            << f << "," << ms("vsm_mark") << "," << ms("vsm_sort") << "," << ms("vsm_alloc") << ","
            << ms("vsm_hpb") << "," << ms("vsm_group_cull") << "," << ms("vsm_cull") << ","
            << ms("vsm_expand") << "," << t.vsmBookkeepingMs() << "," << ms("vsm_draw") << ","
            << v.pagesMarked << "," << v.pagesAllocated << "," << v.pagesRendered << "," << v.pagesCached
            << "," << v.fallbacks << "," << v.instancesDrawn << "," << v.instancesCulledHpb << ","
            << v.lightsWithPages << "," << v.meshletsTotal << "," << v.meshletsAfterExpansion << ","
            << v.meshletsAfterTask << "," << v.trianglesAfterTask << "," << v.trianglesRasterized << ","
            << v.fragmentsDrawn << "," << v.dirtyPageTexels << "," << v.requestOverflow << ","
            << v.pageClipOverflow << "," << v.pagesNew << "," << v.pagesInvalidatedCaster << ","
            << v.pagesRenderedDynamic << "\n";
        row.fallbacks += v.fallbacks;
        row.overflow += v.pageClipOverflow;
        if (f == 0) row.firstDrawMs = ms("vsm_draw");
        if (f == 0) continue; // first use of pipelines and memory: reported in the CSV only
        row.markMs += ms("vsm_mark");
        row.sortMs += ms("vsm_sort");
        row.allocMs += ms("vsm_alloc");
        row.hpbMs += ms("vsm_hpb");
        row.groupCullMs += ms("vsm_group_cull");
        row.cullMs += ms("vsm_cull");
        row.expandMs += ms("vsm_expand");
        row.triangles += v.trianglesRasterized;
        row.total += v.meshletsTotal;
        row.expFrustum += v.meshletsCulledFrustum;
        row.expHpb += v.meshletsCulledHpb;
        row.afterExp += v.meshletsAfterExpansion;
        row.taskFrustum += v.taskCulledFrustum;
        row.taskCone += v.taskCulledCone;
        row.taskHpb += v.taskCulledHpb;
        row.afterTask += v.meshletsAfterTask;
        row.trisAfterTask += v.trianglesAfterTask;
        row.trisRaster += v.trianglesRasterized;
        row.overflow += v.meshletOverflow + v.drawOverflow;
        row.drawMs += ms("vsm_draw");
        row.marked += v.pagesMarked;
        row.allocated += v.pagesAllocated;
        row.rendered += v.pagesRendered;
        row.draws += v.instancesDrawn;
        row.fragments += double(v.fragmentsDrawn);
        row.dirtyTexels += double(v.dirtyPageTexels);
        row.lightsWithPages = std::max(row.lightsWithPages, v.lightsWithPages);
        row.frames += 1;
    }
    for (double* x : {&row.markMs, &row.sortMs, &row.allocMs, &row.hpbMs, &row.groupCullMs, &row.cullMs,
                      &row.expandMs, &row.drawMs, &row.marked, &row.allocated, &row.rendered, &row.draws,
                      &row.triangles, &row.fragments, &row.dirtyTexels})
        *x /= std::max(row.frames, 1.0);
    std::fprintf(stderr,
                 "  %s %s %s: draw %.2f ms, %.0f pages rendered, %.0f triangles rasterized per frame\n",
                 kind.c_str(), cached ? "cached" : "uncached", rasterName(row.raster), row.drawMs,
                 row.rendered, row.triangles);
    return row;
}

void printMeshTable(const std::vector<Row>& rows, json::Object& json);

// The tables on stdout; returns the summary's per-row members.
json::Object printTables(const Config& c, const std::vector<Row>& rows, double& cachedDraw,
                         double& uncachedDraw, double& allocated, uint64_t& fallbacks) {
    const VsmSessionOptions& o = c.options;
    json::Object json;
    std::printf("bench vsm: %s path, %ux%u, virtual %u, pages %u^2, pool %u pages, %u frames per run\n",
                cameraPathName(o.path), o.width, o.height, o.module.vsm.resolution, o.module.vsm.pageSize,
                o.module.vsm.poolPages, c.frames);
    std::printf(
        "| kind | caching | raster | lights | mark ms | sort ms | alloc ms | hpb ms | group cull ms | "
        "cull ms | expand ms | draw ms | first draw ms | triangles | pages marked | allocated | "
        "rendered | draws | fallbacks | fragments | dirty texels | fragments / dirty |\n");
    std::printf(
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:"
        "|---:|---:|\n");
    uint64_t overflow = 0;
    for (const Row& r : rows) {
        std::printf(
            "| %s | %s | %s | %u | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f "
            "| %.1f | %.1f | %.1f | %.1f | %llu | %.0f | %.0f | %.2f |\n",
            r.kind.c_str(), r.cached ? "cached" : "uncached", rasterName(r.raster), r.lightsWithPages,
            r.markMs, r.sortMs, r.allocMs, r.hpbMs, r.groupCullMs, r.cullMs, r.expandMs, r.drawMs,
            r.firstDrawMs, r.triangles, r.marked, r.allocated, r.rendered, r.draws,
            (unsigned long long)r.fallbacks, r.fragments, r.dirtyTexels,
            r.dirtyTexels > 0 ? r.fragments / r.dirtyTexels : 0.0);
        overflow += r.overflow;
        const std::string name = r.kind + (r.cached ? "_cached_" : "_uncached_") + rasterName(r.raster);
        json.real(name + "_draw_ms", r.drawMs).real(name + "_triangles", r.triangles);
        json.real(name + "_first_draw_ms", r.firstDrawMs).real(name + "_fragments", r.fragments);
        json.real(name + "_dirty_texels", r.dirtyTexels);
        // The VSM steps' means (manylights/pass_times.h's scopes; cull or expand is 0 by raster path).
        json.real(name + "_mark_ms", r.markMs).real(name + "_sort_ms", r.sortMs);
        json.real(name + "_alloc_ms", r.allocMs).real(name + "_hpb_ms", r.hpbMs);
        json.real(name + "_group_cull_ms", r.groupCullMs).real(name + "_cull_ms", r.cullMs);
        json.real(name + "_expand_ms", r.expandMs);
        if (r.raster != rows.front().raster) continue;
        (r.cached ? cachedDraw : uncachedDraw) += r.drawMs;
        allocated += r.cached ? r.allocated : 0.0;
        fallbacks += r.fallbacks;
    }
    for (const Row& cr : rows)
        for (const Row& u : rows)
            if (cr.cached && !u.cached && cr.kind == u.kind && cr.raster == u.raster && u.drawMs > 0)
                std::printf("%s %s: cached draw = %.1f %% of uncached\n", cr.kind.c_str(),
                            rasterName(cr.raster), 100.0 * cr.drawMs / u.drawMs);
    printMeshTable(rows, json);
    if (overflow)
        std::fprintf(stderr, "manylights bench vsm: warning: %llu draws or meshlets over their lists\n",
                     (unsigned long long)overflow);
    return json;
}

// Mesh path: the share of meshlets each stage removed (of every stage's input: meshlets_total).
void printMeshTable(const std::vector<Row>& rows, json::Object& json) {
    bool header = false;
    for (const Row& r : rows) {
        if (r.raster != VsmRaster::Mesh) continue;
        if (!header) {
            std::printf(
                "\nmesh path, meshlets of (caster, map, dirty mip), %% of the total culled by each stage:\n");
            std::printf(
                "| kind | caching | meshlets | expansion frustum | expansion HPB | task frustum | task cone "
                "| task HPB | drawn | HPB of frustum survivors | triangles after task | rasterized |\n");
            std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
            header = true;
        }
        const double t = double(std::max<uint64_t>(r.total, 1));
        const uint64_t inFrustum = r.total - r.expFrustum - r.taskFrustum;
        const double hpbShare = inFrustum ? 100.0 * double(r.expHpb + r.taskHpb) / double(inFrustum) : 0.0;
        std::printf("| %s | %s | %llu | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %.1f %% "
                    "| %llu | %llu |\n",
                    r.kind.c_str(), r.cached ? "cached" : "uncached", (unsigned long long)r.total,
                    100.0 * r.expFrustum / t, 100.0 * r.expHpb / t, 100.0 * r.taskFrustum / t,
                    100.0 * r.taskCone / t, 100.0 * r.taskHpb / t, 100.0 * r.afterTask / t, hpbShare,
                    (unsigned long long)r.trisAfterTask, (unsigned long long)r.trisRaster);
        const std::string name = r.kind + (r.cached ? "_cached" : "_uncached");
        json.real(name + "_hpb_cull_share", r.total ? double(r.expHpb + r.taskHpb) / t : 0.0)
            .real(name + "_hpb_cull_share_in_frustum", hpbShare / 100.0);
    }
}
} // namespace

// The flags of `bench vsm` beside its option groups.
const cli::Flags kBenchVsmFlags{{"--kinds", "--out", "--vsm-raster", "--meshlet", "--vsm-page-clip"}, {}};

int runBenchVsm(int argc, char** argv) {
    int status = 0;
    const auto args =
        commandArgs("bench vsm", kBenchVsmHelp, parseVsmCommand(argc, argv, 3, kBenchVsmFlags), status);
    if (!args) return status;
    auto config = parseConfig(*args);
    if (!config) return usageError("bench vsm", config.error());
    const Config& c = config.value();
    if (auto r = cli::checkOutputDirectory("--out", c.out); !r) return usageError("bench vsm", r.error());
    std::ostringstream csv;
    csv << "kind,caching,raster,frame,mark_ms,sort_ms,alloc_ms,hpb_ms,group_cull_ms,cull_ms,expand_ms,"
           "bookkeeping_ms,draw_ms,pages_marked,pages_allocated,"
           "pages_rendered,pages_cached,fallbacks,instances_drawn,instances_culled_hpb,lights_with_pages,"
           "meshlets_total,meshlets_after_expansion,meshlets_after_task,triangles_after_task,triangles_"
           "rasterized,fragments_drawn,dirty_page_texels,request_overflow,page_clip_overflow,pages_new,"
           "pages_invalidated_caster,pages_rendered_dynamic\n";
    std::vector<Row> rows;
    for (const std::string& kind : c.kinds)
        for (bool cached : {false, true})
            for (VsmRaster raster : c.rasters) {
                auto row = measureRun(c, kind, cached, raster, rows.empty(), csv);
                if (!row) return runError("bench vsm", row.error());
                rows.push_back(row.value());
            }
    double cachedDraw = 0, uncachedDraw = 0, allocated = 0;
    uint64_t fallbacks = 0;
    const json::Object perRow = printTables(c, rows, cachedDraw, uncachedDraw, allocated, fallbacks);
    std::ofstream(c.out + "/bench_vsm.csv") << csv.str();
    const double kinds = double(std::max<size_t>(c.kinds.size(), 1));
    json::Object summary;
    summary.real("cached_draw_ms_mean", cachedDraw / kinds, "%.4f")
        .real("uncached_draw_ms_mean", uncachedDraw / kinds, "%.4f")
        .real("pages_allocated_mean", allocated / kinds, "%.2f")
        .integer("fallbacks_total", fallbacks)
        .text("raster", c.rasters.size() > 1
                            ? "both"
                            : rasterName(rows.empty() ? VsmRaster::Vertex : rows.front().raster));
    const std::string last = summary.append(perRow).str();
    std::ofstream(c.out + "/bench_vsm.json") << last << "\n";
    std::printf("wrote %s/bench_vsm.csv and bench_vsm.json\n%s\n", c.out.c_str(), last.c_str());
    return 0;
}

} // namespace ml
