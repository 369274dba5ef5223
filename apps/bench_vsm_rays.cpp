// `manylights bench vsm-rays`: the virtual shadow maps' one-tap visibility against Embree rays at every
// (G-buffer pixel, light) pair a camera path shows, per texels-per-pixel setting, with the mismatches
// broken down by cause (bake/reference/vsm_rays.h). Each setting is its own run of the path (a fresh
// module, VSM on, no bake: every light's maps hold every caster, cars included, so the rays trace the
// frame's whole scene); the VSM passes are fenced (each timed on its own) and the pages allocated read
// from the frame's statistics, both as means over the frames after the first (first use of pipelines).
// --compare-res N puts the plain per-frame shadow map of `bench flicker --vsm --compare-res` beside it: per
// static spot light and frame an N^2 map of that frame's casters (CPU rasteriser), looked up one tap by
// the CPU twin of the shader (static_visibility.h) at the same receivers, its mismatches classed by
// bake/reference/error_classes.h (contact -> bias, resolution -> resolution, the rest -> other); the VSM
// is then also counted over the same static spot pairs alone, so the two rows compare like for like.
#include "apps/commands.h"
#include "apps/json.h"
#include "apps/vsm_args.h"
#include "bake/reference/error_classes.h"
#include "bake/reference/vsm_rays.h"
#include "bake/scene_casters.h"
#include "host/vsm_session.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ml {

static const char* kVsmRaysHelp = R"(usage: manylights bench vsm-rays [options]
Virtual shadow maps against ray-traced visibility: at every (pixel, light) pair of a camera path, the
VSM's one-tap answer (the probe pass, redone on the CPU from the page table and pool) against Embree rays
from the same G-buffer receiver to the light (1 mm normal offset). Mismatch rate per texels-per-pixel
setting, broken down by cause: fallback (coarser page: pool full), bias (an occluder within the
lookup's bias band of the receiver), seam (a neighbouring texel or pixel at another mip), resolution (the
answer changes within +-1 texel), other. Spot and point lights; directional clip levels are left out.
Table on stdout, CSV in --out; the last stdout line is JSON.
  --scene S       night-city (default), indoor (rooms: spot, point lights, carts) or a .gltf / .glb file
  --path P        drive (default), orbit or static
  --frames N      frames of the path per setting (default 3; timings average the frames after the first)
  --size WxH      frame size (default 320x180)
  --lights N      lights in the scene (default 256)
  --seed S        scene seed (default 1)
  --vsm-res N     virtual resolution (default 4096)
  --vsm-page N    page size (default 64)
  --vsm-pool N    physical pages (default 4096)
  --vsm-mark M    page marking: pixel (default) or cluster
  --texels LIST   texels-per-pixel settings (each 0.25, 0.5, 1, 2, 4 or 8), one run each (default
                  0.5,1,2,4; --vsm-texels is not taken)
  --vsm-raster R  auto (default), mesh or vertex
  --compare-res N also a plain N^2 shadow map per static spot light, rendered every frame from that
                  frame's casters, at the same pairs (default 1024; 0: off)
  --out DIR       bench_vsm_rays.csv (default out/bench_vsm_rays)
Columns: pairs, rays_lit, mismatches (vsm_shadows_lit: the rays see the light; vsm_lights_shadow: they do
not), the causes, and per VSM row the pages allocated and the VSM passes' fenced ms (bookkeeping + draw).
Last stdout line: {"pairs": N, "mismatches": M, ...} over the VSM rows; exit 0 only when pairs were
compared, the CPU kernel reproduced every probe and no probe overflowed.
)";

namespace {

struct Config {
    VsmSessionOptions options;
    uint32_t frames = 0, compareRes = 0;
    std::vector<float> texels;
    std::string out;
};

Result<std::vector<float>> parseTexels(const std::string& text) {
    std::vector<float> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        const float t = std::strtof(item.c_str(), &end);
        if (item.empty() || *end || !validTexelsPerPixel(t))
            return fail("--texels: '" + item + "' is not 0.25, 0.5, 1, 2, 4 or 8");
        v.push_back(t);
    }
    if (v.empty()) return fail("--texels: empty list");
    return v;
}

Result<Config> parseConfig(const cli::Args& args) {
    Config c;
    auto options = vsmSessionOptions(args, {3, 1, "320x180", 4096}, c.frames);
    if (!options) return fail(options.error());
    if (args.has("--bake")) return fail("--bake is not taken: every light's maps must hold every caster");
    if (args.has("--vsm-texels")) return fail("--vsm-texels is not taken: --texels LIST gives the settings");
    auto texels = parseTexels(args.get("--texels", "0.5,1,2,4"));
    auto compareRes = cli::parseUint("--compare-res", args.get("--compare-res", "1024"), 0, 8192);
    auto raster = vsmRaster(args);
    for (const std::string* e : {&texels.error(), &compareRes.error(), &raster.error()})
        if (!e->empty()) return fail(*e);
    c.options = options.value();
    c.options.module.vsm.probeCapacity = c.options.width * c.options.height * 8;
    c.options.module.vsm.raster = raster.value();
    c.options.module.timing = TimingChoice::Fenced;
    c.texels = texels.value();
    c.compareRes = compareRes.value();
    c.out = args.get("--out", "out/bench_vsm_rays");
    return c;
}

// One table row: a method over a set of pairs.
struct Row {
    std::string method;
    float texels = 0;
    VsmRayCounts counts;
    double pages = 0, ms = 0; // VSM rows: means over the frames after the first; -1: not a VSM row
};

// Every instance of this frame as a caster (castersFromScene takes the static ones: the dynamic flags
// are lifted for the call), as `bench flicker --vsm --compare-res` renders its plain maps.
CasterTriangles frameCasters(Scene& scene) {
    std::vector<uint8_t> wasDynamic;
    for (Instance& inst : scene.instances) wasDynamic.push_back(inst.dynamic), inst.dynamic = false;
    CasterTriangles casters = castersFromScene(scene);
    for (size_t i = 0; i < wasDynamic.size(); ++i) scene.instances[i].dynamic = wasDynamic[i] != 0;
    return casters;
}

// The static spot lights' pairs: counted into `vsm` (the VSM's answers) and, against a plain
// resolution^2 map per light, into `sm`.
Result<void> comparePlainMap(Scene& scene, const RayReference& rays, const std::vector<VsmRayPair>& pairs,
                             uint32_t resolution, VsmRayCounts& vsm, VsmRayCounts& sm) {
    std::unordered_map<uint32_t, std::vector<const VsmRayPair*>> byLight;
    for (const VsmRayPair& p : pairs) {
        const Light& L = scene.lights[p.sceneLight];
        if (!L.dynamic && L.type == LightKind::Spot) byLight[p.sceneLight].push_back(&p);
    }
    if (byLight.empty()) return {};
    const CasterTriangles casters = frameCasters(scene);
    for (const auto& [light, list] : byLight) {
        const Light& L = scene.lights[light];
        const LightFrustum fr = spotLightFrustum(L);
        const DualDepthMap map = rasterizeDual(casters, fr, resolution);
        auto words = encodeStatic(StaticMethod::SM, map, {fr.nearPlane, fr.farPlane, {}});
        if (!words) return fail("sm: " + words.error());
        const gpu::GpuShadowRecord rec = makeShadowRecord(StaticMethod::SM, fr, 0, resolution, 0);
        ErrorContext ctx;
        ctx.rays = &rays;
        ctx.record = rec;
        ctx.words = words->data();
        ctx.lightPos = L.position;
        ctx.rayBias = 0.001f;
        for (const VsmRayPair* p : list) {
            for (VsmRayCounts* c : {&vsm, &sm}) ++c->pairs, c->raysLit += p->truth;
            vsm.vsmLit += p->vsm;
            if (p->vsm != p->truth) {
                ++vsm.mismatches;
                vsm.vsmShadowsLit += p->truth, vsm.vsmLightsShadow += !p->truth;
                ++vsm.byClass[uint32_t(p->cause)];
            }
            const bool lit = staticVisibility(rec, words->data(), p->p, p->n) >= 0.5f;
            sm.vsmLit += lit;
            if (lit == p->truth) continue;
            ++sm.mismatches;
            sm.vsmShadowsLit += p->truth, sm.vsmLightsShadow += !p->truth;
            const ErrorClass e = classifyDisagreement(ctx, p->p, p->n);
            const VsmRayClass cause = e == ErrorClass::Contact      ? VsmRayClass::Bias
                                      : e == ErrorClass::Resolution ? VsmRayClass::Resolution
                                                                    : VsmRayClass::Other;
            ++sm.byClass[uint32_t(cause)];
        }
    }
    return {};
}

// One run of the path at `texels`: the VSM row, and with --compare-res the static spot rows.
Result<std::vector<Row>> measureSetting(const Config& c, float texels) {
    VsmSessionOptions o = c.options;
    o.module.vsm.texelsPerPixel = texels;
    auto session = VsmSession::create(o);
    if (!session) return fail(session.error());
    VsmSession& s = *session.value();
    if (auto r = s.module->setShadowFilter(0); !r) return fail(r.error()); // the probe's texel: the one tap
    // bindScene adds the scene's lights in order to a fresh module.
    std::unordered_map<uint32_t, uint32_t> sceneLight;
    for (uint32_t k = 0; k < s.binding.lights.size(); ++k) sceneLight[s.binding.lights[k]] = k;
    VsmRayOptions vo;
    vo.resolution = o.module.vsm.resolution;
    const LightDesc defaults{}; // bindScene keeps the module's bias defaults
    vo.depthBias = defaults.shadowDepthBias, vo.normalBias = defaults.shadowNormalBias;
    Row all{"vsm", texels, {}, 0, 0}, vsmSpots{"vsm static spots", texels, {}, -1, -1};
    Row sm{"sm " + std::to_string(c.compareRes) + "^2 static spots", texels, {}, -1, -1};
    double timed = 0;
    for (uint32_t f = 0; f < c.frames; ++f) {
        auto report = s.frame(f);
        if (!report) return fail(report.error());
        if (f > 0 || c.frames == 1) {
            all.pages += report->stats.vsm.pagesAllocated;
            all.ms += report->times.vsmBookkeepingMs() + report->times.ms("vsm_draw");
            timed += 1;
        }
        auto frame = readVsmRayFrame(*s.module);
        if (!frame) return fail(frame.error());
        auto rays = RayReference::build(s.scene, false); // this frame's cars too: the VSM draws them
        if (!rays) return fail(rays.error());
        std::vector<VsmRayPair> pairs;
        VsmRayCounts fc;
        measureVsmRays(frame.value(), s.scene, rays.value(), sceneLight, vo, fc, &pairs);
        all.counts.merge(fc);
        if (c.compareRes)
            if (auto r =
                    comparePlainMap(s.scene, rays.value(), pairs, c.compareRes, vsmSpots.counts, sm.counts);
                !r)
                return fail(r.error());
        std::fprintf(stderr, "  texels %g frame %u: %zu probes, %llu pairs, %llu mismatches\n", texels, f,
                     frame->probes.size(), (unsigned long long)fc.pairs, (unsigned long long)fc.mismatches);
    }
    all.pages /= std::max(timed, 1.0), all.ms /= std::max(timed, 1.0);
    std::vector<Row> rows{all};
    if (c.compareRes) rows.push_back(vsmSpots), rows.push_back(sm);
    return rows;
}

double percent(uint64_t a, uint64_t b) {
    return b ? 100.0 * double(a) / double(b) : 0.0;
}

Result<void> report(const Config& c, const std::string& scene, const std::vector<Row>& rows) {
    const VsmSessionOptions& o = c.options;
    std::printf("bench vsm-rays: %s, path %s, %u frames %ux%u, virtual %u^2, pages %u^2, pool %u\n",
                scene.c_str(), cameraPathName(o.path), c.frames, o.width, o.height, o.module.vsm.resolution,
                o.module.vsm.pageSize, o.module.vsm.poolPages);
    std::printf(
        "| method | texels/pixel | pairs | rays lit %% | mismatch %% | vsm shadows lit %% | vsm lights "
        "shadowed %% | fallback %% | bias %% | seam %% | resolution %% | other %% | pages | VSM ms |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    std::ostringstream csv;
    csv << "scene,method,texels_per_pixel,pairs,rays_lit,mismatches,vsm_shadows_lit,vsm_lights_shadow";
    for (uint32_t k = 0; k < kVsmRayClassCount; ++k) csv << "," << vsmRayClassName(VsmRayClass(k));
    csv << ",pages_allocated,vsm_ms\n";
    for (const Row& r : rows) {
        const VsmRayCounts& k = r.counts;
        std::printf("| %s | %g | %llu | %.2f | %.3f | %.3f | %.3f", r.method.c_str(), r.texels,
                    (unsigned long long)k.pairs, percent(k.raysLit, k.pairs), percent(k.mismatches, k.pairs),
                    percent(k.vsmShadowsLit, k.pairs), percent(k.vsmLightsShadow, k.pairs));
        for (uint32_t i = 0; i < kVsmRayClassCount; ++i)
            std::printf(" | %.3f", percent(k.byClass[i], k.pairs));
        if (r.pages >= 0)
            std::printf(" | %.0f | %.2f |\n", r.pages, r.ms);
        else
            std::printf(" | - | - |\n");
        csv << scene << "," << r.method << "," << r.texels << "," << k.pairs << "," << k.raysLit << ","
            << k.mismatches << "," << k.vsmShadowsLit << "," << k.vsmLightsShadow;
        for (uint32_t i = 0; i < kVsmRayClassCount; ++i) csv << "," << k.byClass[i];
        csv << "," << (r.pages >= 0 ? r.pages : 0.0) << "," << (r.ms >= 0 ? r.ms : 0.0) << "\n";
    }
    std::ofstream file(c.out + "/bench_vsm_rays.csv");
    if (!file || !(file << csv.str())) return fail(c.out + "/bench_vsm_rays.csv: cannot write");
    std::printf("wrote %s/bench_vsm_rays.csv\n", c.out.c_str());
    return {};
}

} // namespace

// The flags of `bench vsm-rays` beside its option groups.
const cli::Flags kVsmRaysFlags{{"--texels", "--vsm-raster", "--compare-res", "--out"}, {}};

int runBenchVsmRays(int argc, char** argv) {
    int status = 0;
    const auto args =
        commandArgs("bench vsm-rays", kVsmRaysHelp, parseVsmCommand(argc, argv, 3, kVsmRaysFlags), status);
    if (!args) return status;
    auto parsed = parseConfig(*args);
    if (!parsed) return usageError("bench vsm-rays", parsed.error());
    const Config& c = parsed.value();
    if (auto r = cli::checkOutputDirectory("--out", c.out); !r)
        return usageError("bench vsm-rays", r.error());
    std::vector<Row> rows;
    VsmRayCounts total;
    for (float t : c.texels) {
        auto r = measureSetting(c, t);
        if (!r) return runError("bench vsm-rays", r.error());
        total.merge(r->front().counts);
        rows.insert(rows.end(), r->begin(), r->end());
    }
    if (validationErrors())
        std::fprintf(stderr, "manylights bench vsm-rays: %u validation messages\n", validationErrors());
    if (auto r = report(c, c.options.scene, rows); !r) return runError("bench vsm-rays", r.error());
    json::Object summary;
    summary.integer("pairs", total.pairs).integer("mismatches", total.mismatches);
    for (uint32_t k = 0; k < kVsmRayClassCount; ++k)
        summary.integer(vsmRayClassName(VsmRayClass(k)), total.byClass[k]);
    summary.integer("fallback_pairs", total.fallbackPairs).integer("missing", total.missing);
    summary.integer("directional", total.directional).integer("outside_cone", total.outsideCone);
    summary.integer("back_facing", total.backFacing).integer("unknown_light", total.unknownLight);
    summary.integer("probe_disagrees", total.probeDisagrees).integer("probe_overflow", total.probeOverflow);
    std::printf("%s\n", summary.str().c_str());
    const bool clean = total.probeDisagrees == 0 && total.probeOverflow == 0 && total.unknownLight == 0;
    return total.pairs > 0 && clean ? 0 : kExitRun;
}

} // namespace ml
