// `manylights bench flicker --vsm`: temporal stability of the virtual shadow maps along a camera path
// with moving lights (the drive path: the followed car's headlights and the other cars' move every frame,
// the street lamps stand still), issue 11 item 6. The module runs with VSM on and without a bake, so
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
// Reads the G-buffer, frame constants and VSM state through engine/manylights_diagnostics.h.
#include "apps/cli.h"
#include "bake/scene_casters.h"
#include "apps/commands.h"
#include "apps/vsm_args.h"
#include "engine/manylights_diagnostics.h"
#include "host/vsm_session.h"
#include "shaders/shared/light_math.h"
#include "bake/reference/raytrace.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cstdio>
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
  --vsm-texels T shadow texels per pixel footprint: 0.25, 0.5, 1 (default), 2, 4 or 8
  --pcf LIST     PCF radii evaluated (0 = one tap .. 4 = 9x9), default 0,2; the module runs with the largest
  --vsm-raster R auto (default), mesh or vertex
  --compare-res N  also a plain shadow map (sm) of N^2 per static spot light, re-rendered every frame
                 with that frame's casters (cars included, as the VSM draws them), looked up at the same
                 receivers and radii: extra rows "static, sm N^2" over the same pairs (default 0: off)
  --out DIR      bench_flicker_vsm.csv (default out/bench_flicker_vsm)
Last stdout line: {"pairs": N, "truth_flips": T, "flips": F, "mismatches": M, ...}; exit 0 only when pairs
were compared and the CPU kernel agreed with every probe (M == 0, no non-resident tap, no probe overflow).
)";

namespace {

struct Sample {
    uint32_t kind = 0;         // 0 moving light, 1 static light
    uint32_t map = 0, mip = 0; // where the lookup ended (after any fallback)
    bool truth = false;
    std::vector<float> vis;    // per PCF radius of the list
    std::vector<float> cmpVis; // --compare-res: the per-frame sm map's, per radius (static spots only)
};

Result<std::vector<uint32_t>> radiusList(const std::string& text) {
    std::vector<uint32_t> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        auto v = cli::parseUint("--pcf", item, 0, ML_MAX_PCF_RADIUS);
        if (!v) return fail(v.error());
        out.push_back(v.value());
    }
    if (out.empty()) return fail("--pcf: empty list");
    return out;
}

} // namespace

int runBenchFlickerVsm(int argc, char** argv) {
    auto args =
        cli::parse(argc, argv, 4, vsmSessionFlags({"--pcf", "--vsm-raster", "--out", "--compare-res"}), {});
    if (!args) return usageError("bench flicker --vsm", args.error());
    if (args->help) {
        std::fputs(kFlickerVsmHelp, stdout);
        return 0;
    }
    uint32_t frameCount = 0;
    auto options = vsmSessionOptions(*args, {16, 2, "320x180", 1024}, frameCount);
    if (!options) return usageError("bench flicker --vsm", options.error());
    if (args->has("--bake"))
        return usageError("bench flicker --vsm",
                          "--bake is not taken: every light's maps must hold every caster");
    auto radii = radiusList(args->get("--pcf", "0,2"));
    auto compareRes = cli::parseUint("--compare-res", args->get("--compare-res", "0"), 0, 8192);
    for (const std::string* e : {&radii.error(), &compareRes.error()})
        if (!e->empty()) return usageError("bench flicker --vsm", *e);
    VsmRaster raster = VsmRaster::Auto;
    if (!parseVsmRaster(args->get("--vsm-raster", "auto"), raster))
        return usageError("bench flicker --vsm", "--vsm-raster: '" + args->get("--vsm-raster", "") +
                                                     "' is not auto, mesh or vertex");
    const std::string out = args->get("--out", "out/bench_flicker_vsm");
    if (auto r = cli::makeDirectory(out); !r) return runError("bench flicker --vsm", r.error());
    const std::vector<uint32_t>& R = radii.value();
    const uint32_t moduleRadius = *std::max_element(R.begin(), R.end());

    VsmSessionOptions o = options.value();
    o.module.vsm.probeCapacity = o.width * o.height * 8;
    o.module.vsm.raster = raster;
    auto session = VsmSession::create(o);
    if (!session) return runError("bench flicker --vsm", session.error());
    VsmSession& s = *session.value();
    if (auto r = s.module->setShadowFilter(moduleRadius); !r)
        return usageError("bench flicker --vsm", r.error());
    // Module light index -> scene light (bindScene adds them in order to a fresh module).
    std::unordered_map<uint32_t, uint32_t> sceneLight;
    for (uint32_t k = 0; k < s.binding.lights.size(); ++k) sceneLight[s.binding.lights[k]] = k;

    const size_t K = R.size();
    // Per kind (moving, static, static with the per-frame sm map of --compare-res) and radius.
    constexpr uint32_t kKinds = 3;
    std::vector<uint64_t> pairs(kKinds * K, 0), truthFlips(kKinds * K, 0), flips(kKinds * K, 0);
    std::vector<double> graded(kKinds * K, 0.0);
    // Pairs (rays stable) whose lookup changed map or mip between the frames, and the flips among them:
    // the VSM picks the mip from the camera's footprint, so a moving camera moves receivers across mips.
    std::vector<uint64_t> mipChanged(kKinds * K, 0), mipChangedFlips(kKinds * K, 0);
    uint64_t lookups = 0, mismatches = 0, notResident = 0, missing = 0, directional = 0, backFacing = 0,
             fallbacks = 0, unknownLight = 0;
    uint32_t probeOverflow = 0;
    std::vector<uint64_t> perMip(16, 0); // lookups (spot and point maps) per mip they ended at
    std::unordered_map<uint64_t, Sample> prev, cur;
    for (uint32_t f = 0; f < frameCount; ++f) {
        auto report = s.frame(f);
        if (!report) return runError("bench flicker --vsm", report.error());
        uint32_t overflow = 0;
        const auto probes = diag::readVsmProbes(*s.module, &overflow);
        probeOverflow += overflow;
        const auto st = diag::readVsmPageState(*s.module);
        const auto vsmMaps = diag::vsmMaps(*s.module);
        const diag::LastFrame fc = diag::lastFrame(*s.module);
        std::vector<float> depth;
        std::vector<glm::vec3> normal;
        if (auto r = diag::readGBuffer(*s.module, depth, normal); !r)
            return runError("bench flicker --vsm", r.error());
        auto rays = RayReference::build(s.scene, false); // this frame's cars too: the VSM draws them
        if (!rays) return runError("bench flicker --vsm", rays.error());

        // Per light: the receivers to trace, and their samples' keys.
        struct Batch {
            std::vector<glm::vec3> p, n;
            std::vector<uint64_t> keys;
        };
        std::unordered_map<uint32_t, Batch> batches;
        cur.clear();
        for (const diag::VsmProbe& p : probes) {
            const uint32_t map = p.map, mip = p.mip, pixel = p.pixel, light = p.light;
            if (p.status == diag::VsmProbeStatus::Missing) {
                ++missing;
                continue;
            }
            if (vsmMaps[map].orthographic) {
                ++directional;
                continue;
            }
            auto sl = sceneLight.find(light);
            if (sl == sceneLight.end()) {
                ++unknownLight;
                continue;
            }
            ++lookups;
            ++perMip[std::min<uint32_t>(mip, 15)];
            fallbacks += p.status == diag::VsmProbeStatus::Fallback;
            const Light& L = s.scene.lights[sl->second];
            const uint32_t px = pixel % o.width, py = pixel / o.width;
            const glm::vec3 P = gpu::worldFromPixel(px, py, depth[pixel], fc.invViewProj, fc.size);
            glm::vec3 N = normal[pixel];
            const float len = glm::length(N);
            N = len > 0.0f ? N / len : glm::vec3(0, 1, 0);

            // The CPU kernel at the probe's place, checked against what the probe read.
            Sample smp;
            smp.kind = L.dynamic ? 0 : 1;
            smp.map = map, smp.mip = mip;
            const int tx = int(p.x), ty = int(p.y);
            const uint32_t receiver = p.receiverDepth;
            uint32_t centre = 0;
            const int full = diag::vsmKernelLit(*st, map, mip, tx, ty, receiver, int(moduleRadius), centre);
            const bool centreNeedsPage = diag::vsmTexelNeedsPage(*st, map, mip, tx, ty);
            bool ok = full >= 0 &&
                      (p.status == diag::VsmProbeStatus::NoCaster ? !centreNeedsPage
                                                                  : centreNeedsPage && centre == p.depth);
            notResident += full < 0;
            for (uint32_t r : R) {
                const int lit = diag::vsmKernelLit(*st, map, mip, tx, ty, receiver, int(r), centre);
                ok = ok && lit >= 0;
                smp.vis.push_back(lit < 0 ? 1.0f : float(lit) / float((2 * r + 1) * (2 * r + 1)));
            }
            if (!ok) {
                if (++mismatches <= 3)
                    std::fprintf(stderr,
                                 "  frame %u: map %u mip %u texel (%d, %d): probe depth %u status %u, cpu "
                                 "kernel %d centre %u\n",
                                 f, map, mip, tx, ty, p.depth, uint32_t(p.status), full, centre);
                continue;
            }
            if (!(glm::dot(N, L.position - P) > 0.0f)) {
                ++backFacing; // unlit by N.L whatever the shadow says
                continue;
            }
            const uint64_t key = (uint64_t(pixel) << 32) | light;
            Batch& b = batches[sl->second];
            b.p.push_back(P), b.n.push_back(N), b.keys.push_back(key);
            cur.emplace(key, std::move(smp));
        }
        // --compare-res: every instance of this frame is a caster (castersFromScene takes the static
        // ones: the dynamic flags are lifted for the call).
        CasterTriangles frameCasters;
        if (compareRes.value()) {
            std::vector<uint8_t> wasDynamic;
            for (Instance& inst : s.scene.instances) wasDynamic.push_back(inst.dynamic), inst.dynamic = false;
            frameCasters = castersFromScene(s.scene);
            for (size_t i = 0; i < wasDynamic.size(); ++i) s.scene.instances[i].dynamic = wasDynamic[i] != 0;
        }
        for (auto& [k, b] : batches) {
            const Light& L = s.scene.lights[k];
            std::vector<uint8_t> truth(b.p.size());
            rays->visibleBatch(b.p.data(), b.n.data(), b.p.size(), L.position, 0.001f,
                               truth.data()); // 1 mm, as bench static
            for (size_t i = 0; i < b.keys.size(); ++i) cur[b.keys[i]].truth = truth[i] != 0;
            if (!compareRes.value() || L.dynamic || L.type != LightKind::Spot) continue;
            const LightFrustum fr = spotLightFrustum(L);
            const DualDepthMap map = rasterizeDual(frameCasters, fr, compareRes.value());
            auto words = encodeStatic(StaticMethod::SM, map, {fr.nearPlane, fr.farPlane, {}});
            if (!words) return runError("bench flicker --vsm", "sm: " + words.error());
            for (size_t i = 0; i < b.keys.size(); ++i)
                for (uint32_t r : R) {
                    auto rec = makeShadowRecord(StaticMethod::SM, fr, 0, compareRes.value(), r);
                    cur[b.keys[i]].cmpVis.push_back(staticVisibility(rec, words->data(), b.p[i], b.n[i]));
                }
        }
        if (f)
            for (const auto& [key, b] : cur) {
                auto it = prev.find(key);
                if (it == prev.end()) continue;
                const Sample& a = it->second;
                const bool compared = !a.cmpVis.empty() && !b.cmpVis.empty();
                for (size_t r = 0; r < K * (compared ? 2 : 1); ++r) {
                    // r < K: the VSM's answer; r >= K: the per-frame sm map's, as kind 2
                    const size_t c = r < K ? b.kind * K + r : 2 * K + (r - K);
                    const float va = r < K ? a.vis[r] : a.cmpVis[r - K],
                                vb = r < K ? b.vis[r] : b.cmpVis[r - K];
                    ++pairs[c];
                    if (a.truth != b.truth) {
                        ++truthFlips[c];
                        continue;
                    }
                    const bool flip = (va >= 0.5f) != (vb >= 0.5f);
                    const bool moved = r < K && (a.map != b.map || a.mip != b.mip); // the VSM rows only
                    flips[c] += flip;
                    mipChanged[c] += moved;
                    mipChangedFlips[c] += flip && moved;
                    graded[c] += std::abs(double(va) - double(vb));
                }
            }
        std::fprintf(stderr, "frame %u: %zu probes, %zu pairs with rays\n", f, probes.size(), cur.size());
        std::swap(prev, cur);
    }
    if (s.module->deviceInfo().validation && validationErrors())
        std::fprintf(stderr, "manylights bench flicker --vsm: %u validation messages\n", validationErrors());

    std::printf("bench flicker --vsm: %s, path %s, %u frames %ux%u, virtual %u^2, module PCF radius %u\n",
                s.scene.name.c_str(), cameraPathName(o.path), frameCount, o.width, o.height,
                o.module.vsm.resolution, moduleRadius);
    std::printf("| lights | pcf | pixel-light pairs in consecutive frames | rays flip %% | VSM flips where "
                "rays do not %% "
                "| mean abs delta visibility where rays do not flip %% | pairs at another mip %% | flips at "
                "another mip %% "
                "|\n|---|---|---:|---:|---:|---:|---:|---:|\n");
    std::printf("lookups per mip (virtual %u^2, mip m is %u^2 >> m):", o.module.vsm.resolution,
                o.module.vsm.resolution);
    for (uint32_t m = 0; m < 16; ++m)
        if (perMip[m]) std::printf(" %u: %llu", m, (unsigned long long)perMip[m]);
    std::printf("\n");
    std::ostringstream csv;
    csv << "lights,pcf_radius,pairs,truth_flips,flicker,graded_sum,mip_changed,mip_changed_flips\n";
    uint64_t allPairs = 0, allTruth = 0, allFlips = 0;
    const std::string smName = "static, sm " + std::to_string(compareRes.value()) + "^2";
    for (uint32_t kind = 0; kind < (compareRes.value() ? kKinds : 2); ++kind)
        for (size_t r = 0; r < K; ++r) {
            const size_t c = kind * K + r;
            const uint64_t stable = pairs[c] - truthFlips[c];
            const char* name = kind == 0 ? "moving" : kind == 1 ? "static" : smName.c_str();
            std::printf("| %s | %ux%u | %llu | %.3f | %.4f | %.4f | %.2f | %.1f |\n", name, 2 * R[r] + 1,
                        2 * R[r] + 1, (unsigned long long)pairs[c],
                        pairs[c] ? 100.0 * double(truthFlips[c]) / double(pairs[c]) : 0.0,
                        pairs[c] ? 100.0 * double(flips[c]) / double(pairs[c]) : 0.0,
                        stable ? 100.0 * graded[c] / double(stable) : 0.0,
                        stable ? 100.0 * double(mipChanged[c]) / double(stable) : 0.0,
                        flips[c] ? 100.0 * double(mipChangedFlips[c]) / double(flips[c]) : 0.0);
            csv << name << "," << R[r] << "," << pairs[c] << "," << truthFlips[c] << "," << flips[c] << ","
                << graded[c] << "," << mipChanged[c] << "," << mipChangedFlips[c] << "\n";
            if (kind < 2) allPairs += pairs[c], allTruth += truthFlips[c], allFlips += flips[c];
        }
    std::ofstream file(out + "/bench_flicker_vsm.csv");
    if (!file || !(file << csv.str()))
        return runError("bench flicker --vsm", out + "/bench_flicker_vsm.csv: cannot write");
    std::printf("wrote %s/bench_flicker_vsm.csv\n", out.c_str());
    std::printf(
        "{\"pairs\": %llu, \"truth_flips\": %llu, \"flips\": %llu, \"lookups\": %llu, \"mismatches\": %llu, "
        "\"not_resident\": %llu, \"missing\": %llu, \"fallbacks\": %llu, \"directional\": %llu, "
        "\"back_facing\": %llu, \"unknown_light\": %llu, \"probe_overflow\": %u}\n",
        (unsigned long long)allPairs, (unsigned long long)allTruth, (unsigned long long)allFlips,
        (unsigned long long)lookups, (unsigned long long)mismatches, (unsigned long long)notResident,
        (unsigned long long)missing, (unsigned long long)fallbacks, (unsigned long long)directional,
        (unsigned long long)backFacing, (unsigned long long)unknownLight, probeOverflow);
    return allPairs > 0 && mismatches == 0 && notResident == 0 && missing == 0 && probeOverflow == 0 &&
                   unknownLight == 0
               ? 0
               : 1;
}

} // namespace ml
