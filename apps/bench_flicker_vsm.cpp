// `manylights bench flicker --vsm`: temporal stability of the virtual shadow maps along a camera path
// with moving lights (the drive path: the followed car's headlights and the other cars' move every frame,
// the street lamps stand still). The module runs with VSM on and without a bake, so
// every light's maps hold every caster and its dynamic visibility is its whole shadow. Per frame:
//   - the probe pass (vsm_probe.comp, the one `check vsm` reads) gives, per (shaded pixel, light with
//     maps), the map, mip and texel the evaluation pass's lookup ended at (after any fallback) and the
//     receiver's biased depth it compared;
//   - the page table and the physical pool are read back, and the PCF kernel around that texel is
//     evaluated on the CPU the way vsmKernelLit (vsm_common.glsl) does, for every radius asked for.
//     The module runs with the largest radius, so every tap of every smaller kernel is resident too.
//     Checked: the kernel's centre depth equals the depth the probe read, "no caster" answers are the
//     texels whose page holds no caster, and every tap of the module's kernel is resident; any
//     disagreement is counted and fails the run;
//   - the receiver is the G-buffer's (the pixel's depth and normal, worldFromPixel as the shader), and
//     Embree casts a ray from it to the light's position this frame against this frame's scene (the
//     cars where animateScene put them: the VSM draws them too).
// A (pixel, light) pair flickers when it has a lookup in two consecutive frames, faces the light in
// both, and the VSM's binary answer (visibility >= 0.5) changes while the rays' does not; the graded
// measure is the mean |change of visibility| over the pairs whose rays do not flip. Directional maps
// (the moon's clip levels) are counted and left out: the rays here aim at a light position.
// --compare-res N puts a plain shadow map beside it at the same pairs: per static spot light and frame,
// an N^2 map of that frame's casters (CPU rasteriser, cars included), looked up by the CPU twin of the
// shader (static_visibility.h) at the same receivers and radii.
// Candidates beside the module's lookup: --bilinear thresholds a 2x2 bilinear answer computed on the CPU
// over the same pages (diag::vsmBilinearLit), --lamp-bias sets the static lights' shadow bias and
// --lamp-texels their LightDesc::shadowTexelScale; the pages
// allocated per frame come with every run, since a setting that buys stability with pages must show both.
// Reads the G-buffer, frame constants and VSM state through engine/manylights_diagnostics.h.
#include "apps/commands.h"
#include "bake/scene_casters.h"
#include "apps/json.h"
#include "apps/vsm_args.h"
#include "engine/manylights_diagnostics.h"
#include "host/scene_host.h"
#include "host/vsm_session.h"
#include "shaders/shared/light_math.h"
#include "bake/reference/raytrace.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>

namespace ml {

static const char* kFlickerVsmHelp = R"(usage: manylights bench flicker --vsm [options]
Share of (pixel, light) pairs whose virtual-shadow-map answer flips between consecutive frames of a
camera path while the ray-traced visibility does not, per light kind (moving: headlights; static:
lamps) and PCF size, with the mean |delta visibility| where the rays do not flip, the share of pairs
whose lookup changed mip and of the flips among them, and the lookups per mip. GPU module (VSM on, no
bake), Embree rays from the same G-buffer receivers. Table on stdout, CSV in --out.
  --scene S      night-city (default) or a .gltf / .glb file
  --path P       drive (default), orbit or static
  --frames N     frames of the path (>= 2, default 16)
  --size WxH     frame size (default 320x180)
  --lights N     lights in the scene (default 256)
  --seed S       scene seed (default 1)
  --vsm-res N    virtual resolution (default 1024)
  --vsm-page N   page size (default 64)
  --vsm-pool N   physical pages (default 4096)
  --vsm-mark M   page marking: pixel (default: per receiver pixel) or cluster (per cluster and light)
  --vsm-texels T shadow texels per pixel footprint: 0.25, 0.5, 1 (default), 2, 4 or 8
  --pcf LIST     PCF radii evaluated (0 = one tap .. 4 = 9x9), default 0,2; the module runs with the largest
  --vsm-raster R auto (default), mesh or vertex
  --compare-res N  also a plain shadow map (sm) of N^2 per static spot light, re-rendered every frame
                 with that frame's casters (cars included, as the VSM draws them), looked up at the same
                 receivers and radii: extra rows "static, sm N^2" over the same pairs (default 0: off)
  --bilinear     also a candidate filtered lookup the module does not have, on the CPU over the same pages:
                 the 2x2 texels around each static light's lookup, weighted by the sub-texel position
                 (row "static, VSM 2x2 bilinear"; needs a --pcf radius >= 1, so that its taps are resident)
  --lamp-bias N,D  the static lights' shadowNormalBias and shadowDepthBias (LightDesc; default 1,0.5)
  --lamp-texels T  the static lights' shadowTexelScale (LightDesc: T times --vsm-texels for them alone;
                 0.25, 0.5, 1 (default), 2, 4 or 8)
  --out DIR      bench_flicker_vsm.csv (default out/bench_flicker_vsm)
Last stdout line: {"pairs": N, "truth_flips": T, "flips": F, "mismatches": M, ..., "pages_allocated_mean":
P} (P: every light's pages allocated per frame, mean after the first); exit 0 only when pairs were
compared and the CPU kernel agreed with every probe (M == 0, no non-resident tap, no probe overflow).
)";

namespace {

struct Sample {
    uint32_t kind = 0;         // 0 moving light, 1 static light
    uint32_t map = 0, mip = 0; // where the lookup ended (after any fallback)
    bool truth = false;
    std::vector<float> vis;    // per PCF radius of the list
    std::vector<float> cmpVis; // --compare-res: the per-frame sm map's, per radius (static spots only)
    float bilinear = -1.0f;    // --bilinear: the candidate's visibility (static lights; -1: none)
};
using Samples = std::unordered_map<uint64_t, Sample>; // by (pixel << 32 | module light)

// Per kind (moving, static, static with the per-frame sm map of --compare-res) and radius, then one row
// for --bilinear (at index kKinds * radii).
constexpr uint32_t kKinds = 3;

struct Counts {
    explicit Counts(size_t n)
        : pairs(n), truthFlips(n), flips(n), mipChanged(n), mipChangedFlips(n), graded(n, 0.0) {}
    // Pairs (rays stable) whose lookup changed map or mip between the frames, and the flips among them:
    // the VSM picks the mip from the camera's footprint, so a moving camera moves receivers across mips.
    std::vector<uint64_t> pairs, truthFlips, flips, mipChanged, mipChangedFlips;
    std::vector<double> graded;
    // Probes: checked against the CPU kernel, or left out and why.
    uint64_t lookups = 0, mismatches = 0, notResident = 0, missing = 0, directional = 0, backFacing = 0,
             fallbacks = 0, unknownLight = 0, bilinearLeftOut = 0;
    uint32_t probeOverflow = 0;
    // Pages allocated (the frame statistics', every light's maps), summed over the frames after the first:
    // the memory a setting costs beside the flicker it buys.
    uint64_t pagesAllocated = 0, pageFrames = 0;
    std::vector<uint64_t> perMip = std::vector<uint64_t>(16, 0); // lookups per mip they ended at
};

struct Run {
    VsmSessionOptions options;
    uint32_t frames = 0, compareRes = 0, moduleRadius = 0;
    bool bilinear = false;
    float normalBias = -1.0f, depthBias = -1.0f; // --lamp-bias (negative: the lights' own)
    float lampTexels = 1.0f;                     // --lamp-texels
    std::vector<uint32_t> radii;
    std::string out;
    std::unordered_map<uint32_t, uint32_t> sceneLight; // module light index -> scene light
};

Result<Run> parseRun(const cli::Args& args) {
    Run run;
    auto options = vsmSessionOptions(args, {16, 2, "320x180", 1024}, run.frames);
    if (!options) return fail(options.error());
    if (args.has("--bake")) return fail("--bake is not taken: every light's maps must hold every caster");
    auto radii = opts::uintList("--pcf", args.get("--pcf", "0,2"), 0, ML_MAX_PCF_RADIUS);
    auto compareRes = cli::parseUint("--compare-res", args.get("--compare-res", "0"), 0, 8192);
    auto raster = vsmRaster(args);
    for (const std::string* e : {&radii.error(), &compareRes.error(), &raster.error()})
        if (!e->empty()) return fail(*e);
    run.options = options.value();
    run.options.module.vsm.probeCapacity = run.options.width * run.options.height * 8;
    run.options.module.vsm.raster = raster.value();
    run.radii = radii.value();
    run.moduleRadius = *std::max_element(run.radii.begin(), run.radii.end());
    run.compareRes = compareRes.value();
    run.bilinear = args.has("--bilinear");
    if (args.has("--lamp-bias")) {
        const std::string v = args.get("--lamp-bias", "");
        if (std::sscanf(v.c_str(), "%f,%f", &run.normalBias, &run.depthBias) != 2 ||
            !(run.normalBias >= 0.0f) || !(run.depthBias >= 0.0f) || run.normalBias > kMaxShadowBias ||
            run.depthBias > kMaxShadowBias)
            return fail("--lamp-bias: '" + v + "' is not N,D (two biases in [0, kMaxShadowBias])");
    }
    if (args.has("--lamp-texels")) {
        const std::string v = args.get("--lamp-texels", "");
        char* end = nullptr;
        run.lampTexels = std::strtof(v.c_str(), &end);
        if (v.empty() || *end || !validTexelsPerPixel(run.lampTexels))
            return fail("--lamp-texels: '" + v + "' is not 0.25, 0.5, 1, 2, 4 or 8");
    }
    if (run.bilinear && run.moduleRadius < 1) return fail("--bilinear needs a --pcf radius >= 1");
    run.out = args.get("--out", "out/bench_flicker_vsm");
    return run;
}

// The frame's read-backs the probes are judged with.
struct FrameState {
    std::vector<diag::VsmProbe> probes;
    std::shared_ptr<const diag::VsmPageState> pages;
    std::vector<diag::VsmMap> maps;
    diag::LastFrame constants;
    std::vector<float> depth;
    std::vector<glm::vec3> normal;
};

// Per scene light: the receivers to trace, and their samples' keys.
struct Batch {
    std::vector<glm::vec3> p, n;
    std::vector<uint64_t> keys;
};

// One probe: the CPU kernel at the probe's place, checked against what the probe read, as a sample
// of its (pixel, light) pair in `batches` and `cur`; or counted as left out.
void sampleProbe(const Run& run, const VsmSession& s, const FrameState& fs, const diag::VsmProbe& p,
                 uint32_t f, Counts& c, std::unordered_map<uint32_t, Batch>& batches, Samples& cur) {
    const uint32_t map = p.map, mip = p.mip, pixel = p.pixel, light = p.light;
    if (p.status == diag::VsmProbeStatus::Missing) {
        ++c.missing;
        return;
    }
    if (fs.maps[map].orthographic) {
        ++c.directional;
        return;
    }
    auto sl = run.sceneLight.find(light);
    if (sl == run.sceneLight.end()) {
        ++c.unknownLight;
        return;
    }
    ++c.lookups;
    ++c.perMip[std::min<uint32_t>(mip, 15)];
    c.fallbacks += p.status == diag::VsmProbeStatus::Fallback;
    const Light& L = s.scene.lights[sl->second];
    const uint32_t width = run.options.width, px = pixel % width, py = pixel / width;
    const glm::vec3 P =
        gpu::worldFromPixel(px, py, fs.depth[pixel], fs.constants.invViewProj, fs.constants.size);
    glm::vec3 N = fs.normal[pixel];
    const float len = glm::length(N);
    N = len > 0.0f ? N / len : glm::vec3(0, 1, 0);

    Sample smp;
    smp.kind = L.dynamic ? 0 : 1;
    smp.map = map, smp.mip = mip;
    const int tx = int(p.x), ty = int(p.y);
    const uint32_t receiver = p.receiverDepth;
    uint32_t centre = 0;
    const diag::VsmPageState& st = *fs.pages;
    const int full = diag::vsmKernelLit(st, map, mip, tx, ty, receiver, int(run.moduleRadius), centre);
    const bool centreNeedsPage = diag::vsmTexelNeedsPage(st, map, mip, tx, ty);
    bool ok =
        full >= 0 && (p.status == diag::VsmProbeStatus::NoCaster ? !centreNeedsPage
                                                                 : centreNeedsPage && centre == p.depth);
    c.notResident += full < 0;
    for (uint32_t r : run.radii) {
        const int lit = diag::vsmKernelLit(st, map, mip, tx, ty, receiver, int(r), centre);
        ok = ok && lit >= 0;
        smp.vis.push_back(lit < 0 ? 1.0f : float(lit) / float((2 * r + 1) * (2 * r + 1)));
    }
    if (!ok) {
        if (++c.mismatches <= 3)
            std::fprintf(stderr,
                         "  frame %u: map %u mip %u texel (%d, %d): probe depth %u status %u, cpu "
                         "kernel %d centre %u\n",
                         f, map, mip, tx, ty, p.depth, uint32_t(p.status), full, centre);
        return;
    }
    if (run.bilinear && smp.kind == 1) {
        smp.bilinear = diag::vsmBilinearLit(st, map, mip, P, N, tx, ty, receiver);
        c.bilinearLeftOut += smp.bilinear < 0.0f;
    }
    if (!(glm::dot(N, L.position - P) > 0.0f)) {
        ++c.backFacing; // unlit by N.L whatever the shadow says
        return;
    }
    const uint64_t key = (uint64_t(pixel) << 32) | light;
    Batch& b = batches[sl->second];
    b.p.push_back(P), b.n.push_back(N), b.keys.push_back(key);
    cur.emplace(key, std::move(smp));
}

// Every instance of this frame as a caster (castersFromScene takes the static ones: the dynamic flags
// are lifted for the call).
CasterTriangles frameCasters(Scene& scene) {
    std::vector<uint8_t> wasDynamic;
    for (Instance& inst : scene.instances) wasDynamic.push_back(inst.dynamic), inst.dynamic = false;
    CasterTriangles casters = castersFromScene(scene);
    for (size_t i = 0; i < wasDynamic.size(); ++i) scene.instances[i].dynamic = wasDynamic[i] != 0;
    return casters;
}

// The rays' visibility of every batch, and with --compare-res the per-frame sm map's.
Result<void> traceBatches(const Run& run, VsmSession& s, const RayReference& rays,
                          const std::unordered_map<uint32_t, Batch>& batches, Samples& cur) {
    CasterTriangles casters;
    if (run.compareRes) casters = frameCasters(s.scene);
    for (auto& [k, b] : batches) {
        const Light& L = s.scene.lights[k];
        std::vector<uint8_t> truth(b.p.size());
        rays.visibleBatch(b.p.data(), b.n.data(), b.p.size(), L.position, 0.001f,
                          truth.data()); // 1 mm, as bench static
        for (size_t i = 0; i < b.keys.size(); ++i) cur[b.keys[i]].truth = truth[i] != 0;
        if (!run.compareRes || L.dynamic || L.type != LightKind::Spot) continue;
        const LightFrustum fr = spotLightFrustum(L);
        const DualDepthMap map = rasterizeDual(casters, fr, run.compareRes);
        auto words = encodeStatic(StaticMethod::SM, map, {fr.nearPlane, fr.farPlane, {}});
        if (!words) return fail("sm: " + words.error());
        for (size_t i = 0; i < b.keys.size(); ++i)
            for (uint32_t r : run.radii) {
                auto rec = makeShadowRecord(StaticMethod::SM, fr, 0, run.compareRes, r);
                cur[b.keys[i]].cmpVis.push_back(staticVisibility(rec, words->data(), b.p[i], b.n[i]));
            }
    }
    return {};
}

// The pairs with a sample in both frames: flips of the VSM's (and the sm map's) answer against the rays'.
void comparePairs(size_t K, const Samples& prev, const Samples& cur, Counts& c) {
    for (const auto& [key, b] : cur) {
        auto it = prev.find(key);
        if (it == prev.end()) continue;
        const Sample& a = it->second;
        const bool compared = !a.cmpVis.empty() && !b.cmpVis.empty();
        for (size_t r = 0; r < K * (compared ? 2 : 1); ++r) {
            // r < K: the VSM's answer; r >= K: the per-frame sm map's, as kind 2
            const size_t i = r < K ? b.kind * K + r : 2 * K + (r - K);
            const float va = r < K ? a.vis[r] : a.cmpVis[r - K], vb = r < K ? b.vis[r] : b.cmpVis[r - K];
            ++c.pairs[i];
            if (a.truth != b.truth) {
                ++c.truthFlips[i];
                continue;
            }
            const bool flip = (va >= 0.5f) != (vb >= 0.5f);
            const bool moved = r < K && (a.map != b.map || a.mip != b.mip); // the VSM rows only
            c.flips[i] += flip;
            c.mipChanged[i] += moved;
            c.mipChangedFlips[i] += flip && moved;
            c.graded[i] += std::abs(double(va) - double(vb));
        }
        if (a.bilinear < 0.0f || b.bilinear < 0.0f) continue;
        const size_t i = kKinds * K; // --bilinear's row
        ++c.pairs[i];
        if (a.truth != b.truth) {
            ++c.truthFlips[i];
            continue;
        }
        c.flips[i] += (a.bilinear >= 0.5f) != (b.bilinear >= 0.5f);
        c.mipChanged[i] += a.map != b.map || a.mip != b.mip;
        c.mipChangedFlips[i] +=
            (a.bilinear >= 0.5f) != (b.bilinear >= 0.5f) && (a.map != b.map || a.mip != b.mip);
        c.graded[i] += std::abs(double(a.bilinear) - double(b.bilinear));
    }
}

Result<void> measureFrame(const Run& run, VsmSession& s, uint32_t f, Counts& c, Samples& prev, Samples& cur) {
    auto report = s.frame(f);
    if (!report) return fail(report.error());
    if (f > 0) c.pagesAllocated += report->stats.vsm.pagesAllocated, ++c.pageFrames;
    FrameState fs;
    uint32_t overflow = 0;
    fs.probes = diag::readVsmProbes(*s.module, &overflow);
    c.probeOverflow += overflow;
    fs.pages = diag::readVsmPageState(*s.module);
    fs.maps = diag::vsmMaps(*s.module);
    fs.constants = diag::lastFrame(*s.module);
    if (auto r = diag::readGBuffer(*s.module, fs.depth, fs.normal); !r) return fail(r.error());
    auto rays = RayReference::build(s.scene, false); // this frame's cars too: the VSM draws them
    if (!rays) return fail(rays.error());
    std::unordered_map<uint32_t, Batch> batches;
    cur.clear();
    for (const diag::VsmProbe& p : fs.probes) sampleProbe(run, s, fs, p, f, c, batches, cur);
    if (auto r = traceBatches(run, s, rays.value(), batches, cur); !r) return r;
    if (f) comparePairs(run.radii.size(), prev, cur, c);
    std::fprintf(stderr, "frame %u: %zu probes, %zu pairs with rays\n", f, fs.probes.size(), cur.size());
    std::swap(prev, cur);
    return {};
}

double pagesMean(const Counts& c) {
    return c.pageFrames ? double(c.pagesAllocated) / double(c.pageFrames) : 0.0;
}

struct Sums {
    uint64_t pairs = 0, truthFlips = 0, flips = 0;
};

// The table and CSV per (kind, radius); returns the sums over the moving and static rows.
Result<Sums> report(const Run& run, const VsmSession& s, const Counts& c) {
    const VsmSessionOptions& o = run.options;
    const std::vector<uint32_t>& R = run.radii;
    const size_t K = R.size();
    std::printf(
        "bench flicker --vsm: %s, path %s, %u frames %ux%u, virtual %u^2, %g texels per pixel, module "
        "PCF radius %u, pages allocated per frame %.1f (mean after the first)\n",
        s.scene.name.c_str(), cameraPathName(o.path), run.frames, o.width, o.height, o.module.vsm.resolution,
        double(o.module.vsm.texelsPerPixel), run.moduleRadius, pagesMean(c));
    std::printf("| lights | pcf | pixel-light pairs in consecutive frames | rays flip %% | VSM flips where "
                "rays do not %% "
                "| mean abs delta visibility where rays do not flip %% | pairs at another mip %% | flips at "
                "another mip %% "
                "|\n|---|---|---:|---:|---:|---:|---:|---:|\n");
    std::printf("lookups per mip (virtual %u^2, mip m is %u^2 >> m):", o.module.vsm.resolution,
                o.module.vsm.resolution);
    for (uint32_t m = 0; m < 16; ++m)
        if (c.perMip[m]) std::printf(" %u: %llu", m, (unsigned long long)c.perMip[m]);
    std::printf("\n");
    std::ostringstream csv;
    csv << "lights,pcf_radius,pairs,truth_flips,flicker,graded_sum,mip_changed,mip_changed_flips\n";
    Sums all;
    const std::string smName = "static, sm " + std::to_string(run.compareRes) + "^2";
    auto row = [&](const std::string& name, size_t i, const std::string& pcf, const std::string& radius) {
        const uint64_t pairs = c.pairs[i], stable = pairs - c.truthFlips[i];
        std::printf("| %s | %s | %llu | %.3f | %.4f | %.4f | %.2f | %.1f |\n", name.c_str(), pcf.c_str(),
                    (unsigned long long)pairs, pairs ? 100.0 * double(c.truthFlips[i]) / double(pairs) : 0.0,
                    pairs ? 100.0 * double(c.flips[i]) / double(pairs) : 0.0,
                    stable ? 100.0 * c.graded[i] / double(stable) : 0.0,
                    stable ? 100.0 * double(c.mipChanged[i]) / double(stable) : 0.0,
                    c.flips[i] ? 100.0 * double(c.mipChangedFlips[i]) / double(c.flips[i]) : 0.0);
        csv << name << "," << radius << "," << pairs << "," << c.truthFlips[i] << "," << c.flips[i] << ","
            << c.graded[i] << "," << c.mipChanged[i] << "," << c.mipChangedFlips[i] << "\n";
    };
    for (uint32_t kind = 0; kind < (run.compareRes ? kKinds : 2); ++kind)
        for (size_t r = 0; r < K; ++r) {
            const size_t i = kind * K + r;
            const std::string side = std::to_string(2 * R[r] + 1);
            row(kind == 0   ? "moving"
                : kind == 1 ? "static"
                            : smName,
                i, side + "x" + side, std::to_string(R[r]));
            if (kind < 2) all.pairs += c.pairs[i], all.truthFlips += c.truthFlips[i], all.flips += c.flips[i];
        }
    if (run.bilinear) row("static, VSM 2x2 bilinear", kKinds * K, "2x2 bilinear", "bilinear");
    std::ofstream file(run.out + "/bench_flicker_vsm.csv");
    if (!file || !(file << csv.str())) return fail(run.out + "/bench_flicker_vsm.csv: cannot write");
    std::printf("wrote %s/bench_flicker_vsm.csv\n", run.out.c_str());
    return all;
}

} // namespace

// The flags of `bench flicker --vsm` beside its option groups.
const cli::Flags kFlickerVsmFlags{
    {"--pcf", "--vsm-raster", "--out", "--compare-res", "--lamp-bias", "--lamp-texels"}, {"--bilinear"}};

int runBenchFlickerVsm(int argc, char** argv) {
    int status = 0;
    const auto args = commandArgs("bench flicker --vsm", kFlickerVsmHelp,
                                  parseVsmCommand(argc, argv, 4, kFlickerVsmFlags), status);
    if (!args) return status;
    auto parsed = parseRun(*args);
    if (!parsed) return usageError("bench flicker --vsm", parsed.error());
    Run& run = parsed.value();
    if (auto r = cli::checkOutputDirectory("--out", run.out); !r)
        return usageError("bench flicker --vsm", r.error());
    bool refused = false; // settings past the device's limits: a usage error (README, exit status)
    auto session = VsmSession::create(run.options, &refused);
    if (!session)
        return refused ? usageError("bench flicker --vsm", session.error())
                       : runError("bench flicker --vsm", session.error());
    VsmSession& s = *session.value();
    if (auto r = s.module->setShadowFilter(run.moduleRadius); !r)
        return usageError("bench flicker --vsm", r.error());
    // bindScene adds the scene's lights in order to a fresh module.
    for (uint32_t k = 0; k < s.binding.lights.size(); ++k) run.sceneLight[s.binding.lights[k]] = k;
    if (run.normalBias >= 0.0f || run.lampTexels != 1.0f) // static lights only: updateScene re-sets the
        for (uint32_t k = 0; k < s.binding.lights.size(); ++k) { // moving ones every frame
            if (s.scene.lights[k].dynamic) continue;
            LightDesc d = toLightDesc(s.scene.lights[k]);
            if (run.normalBias >= 0.0f)
                d.shadowNormalBias = run.normalBias, d.shadowDepthBias = run.depthBias;
            d.shadowTexelScale = run.lampTexels;
            if (auto r = s.module->setLight(s.binding.lights[k], d); !r)
                return runError("bench flicker --vsm", r.error());
        }
    Counts c(kKinds * run.radii.size() + 1);
    Samples prev, cur;
    for (uint32_t f = 0; f < run.frames; ++f)
        if (auto r = measureFrame(run, s, f, c, prev, cur); !r)
            return runError("bench flicker --vsm", r.error());
    if (s.module->deviceInfo().validation && validationErrors())
        std::fprintf(stderr, "manylights bench flicker --vsm: %u validation messages\n", validationErrors());
    auto sums = report(run, s, c);
    if (!sums) return runError("bench flicker --vsm", sums.error());
    json::Object summary;
    summary.integer("pairs", sums->pairs)
        .integer("truth_flips", sums->truthFlips)
        .integer("flips", sums->flips);
    summary.integer("lookups", c.lookups).integer("mismatches", c.mismatches);
    summary.integer("not_resident", c.notResident).integer("missing", c.missing);
    summary.integer("fallbacks", c.fallbacks).integer("directional", c.directional);
    summary.integer("back_facing", c.backFacing).integer("unknown_light", c.unknownLight);
    if (run.bilinear) {
        const size_t b = kKinds * run.radii.size();
        summary.integer("bilinear_pairs", c.pairs[b]).integer("bilinear_flips", c.flips[b]);
        summary.integer("bilinear_left_out", c.bilinearLeftOut);
    }
    summary.integer("probe_overflow", c.probeOverflow).real("pages_allocated_mean", pagesMean(c), "%.1f");
    std::printf("%s\n", summary.str().c_str());
    const bool clean = c.mismatches == 0 && c.notResident == 0 && c.missing == 0 && c.probeOverflow == 0 &&
                       c.unknownLight == 0;
    return sums->pairs > 0 && clean ? 0 : 1;
}

} // namespace ml
