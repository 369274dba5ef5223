// `manylights bench static`: every static shadow method at every resolution on the same lights of one
// scene, measured in one run: bytes (against the 32-bit map), bake seconds split into rendering the dual
// maps (Vulkan, tiles of <= 4096^2) and encoding, the one evaluation pass's GPU time with the method
// (same lights, same view), and the disagreement with ray-traced visibility (Embree) over the pixels the
// lights reach. Prints a table, writes a CSV and, with gnuplot, charts of accuracy against memory and
// against time. Also: every disagreement's cause (bake/reference/error_classes.h) with
// the resolution class's convergence slope per method, and the isolated cost of one lookup per method,
// resolution and PCF size (shadows/tools/lookup_timer.h). Receivers are moved onto the traced surface
// by default (--receivers); since the G-buffer is reversed Z (engine/camera.h) they move by millimetres.
#include "apps/bench_static_tables.h"
#include "apps/commands.h"
#include "bake/scene_casters.h"
#include "apps/exact_receivers.h"
#include "apps/options.h"
#include "io/safe_io.h"
#include "engine/manylights_diagnostics.h"
#include "host/scene_host.h"
#include "scenes/scenes.h"
#include "shaders/shared/light_math.h"
#include "bake/reference/error_classes.h"
#include "bake/reference/raytrace.h"
#include "shadows/static/static_visibility.h"
#include "shadows/tools/gpu_dual_renderer.h"
#include "shadows/tools/lookup_timer.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <sstream>

namespace ml {

static const char* kHelp = R"(usage: manylights bench static [options]
Static shadow methods x resolutions on the same lights, in one run: bytes, bake time (render, encode),
evaluation-pass GPU time, disagreement with ray-traced truth. Table on stdout, CSV and charts in --out.
With DAG-MH rows, also the share of lookups its value bounds answer from one word (one tap, 3x3 PCF).
  --scene S        night-city (default), night-city-closed or a .gltf / .glb file
  --methods LIST   comma-separated, default sm,mh,mmh,dagmh,cpvs
  --res LIST       comma-separated resolutions, default 1024,2048,4096,8192
  --lights N       static spot lights measured (the N in view that light the most pixels), default 8
  --size WxH       view for the evaluation time and the accuracy receivers, default 640x360
  --frames N       timed frames per configuration, default 3
  --camera X,Y,Z,TX,TY,TZ  view for the evaluation time and receivers (default: the scene's)
  --pcf R          filter radius for the evaluation and accuracy (0 = one tap), default 0
  --receivers R    exact (default): each G-buffer pixel's receiver is moved onto the surface the
                   camera ray through the pixel centre hits (Embree), when that hit lies within
                   max(5 cm, 0.2 %) of the G-buffer depth; gbuffer: the G-buffer's reconstruction
                   (reversed-Z D32 through invViewProj in float: within millimetres; the
                   standard Z used before put them centimetres off at 100 m, inside walls)
  --lookup-pcf LIST  PCF radii of the isolated lookup timing (0 = one tap .. 4 = 9x9), default
                   0,1,2,3,4; 'none' skips it
  --lookups K      extra lookups per pair in the timing pass (timed at 1 and 1 + K), default 8;
                   K grows x4 until the extra lookups take >= 40 ms
  --lookup-pairs N (receiver, light) pairs timed, evenly sampled from the compared ones, default 16384
  --seed S         scene seed, default 1
  --ray-bias M     the rays' origin offset along the receiver's normal, metres, default 0.001. At
                   grazing incidence the offset moves the ray's line across shadow edges by about
                   M / tan(incidence): keep it below the maps' normal offset (one texel) there
  --print-class C  print every disagreement of class C (inside, contact, resolution, thin-open,
                   other) to stderr: method, res, light, receiver, normal, distance, both answers
  --out DIR        bench_static.csv, bench_classes.csv (disagreements by cause), bench_lookup.csv
                   (isolated lookup cost), accuracy_vs_bytes.png, accuracy_vs_time.png,
                   accuracy_vs_lookup.png (default out/bench_static)
  --allow-outside-scene-dir  let the glTF's buffer/image URIs leave its folder (trusted scenes only)
  --need REGION    instead: fixed against need-based resolution along a camera path (its own options:
                   bench static --need path:drive --help)
)";

namespace {
// The rays' normal offset, metres (default of --ray-bias). It must stay below the maps' own normal
// offset (one texel footprint: 3 mm for a 4096^2, 90-degree map 6 m away), or at grazing incidence
// the truth's ray passes shadow edges that the map's lookup resolves (docs/accuracy.md, section 1:
// 2 cm made 0.39 % of receivers disagree at 4096^2, growing with resolution).
constexpr float kRayBias = 0.001f;

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Receiver {
    glm::vec3 p, n;
};

using Row = BenchStaticRow;

double evaluateMs(Module& m, uint32_t frames) {
    m.takeReports();
    for (uint32_t i = 0; i < frames + 1; ++i) // one warm-up frame
        (void)m.submitFrame();
    vkDeviceWaitIdle(m.deviceInfo().device);
    m.collect();
    auto reports = m.takeReports();
    double sum = 0;
    uint32_t n = 0;
    for (size_t i = 1; i < reports.size(); ++i, ++n) sum += reports[i].times.ms("evaluate");
    return n ? sum / n : 0.0;
}

struct StaticOptions {
    std::vector<StaticMethod> methods;
    std::vector<uint32_t> resolutions, lookupRadii;
    uint32_t lights = 8, pcf = 0, extraLookups = 8, lookupPairs = 16384;
    opts::View view;
    opts::Scene scene;
    bool exactReceivers = true;
    float rayBias = kRayBias;
    uint32_t printClass = kErrorClassCount; // none
    std::string out;
};

// --receivers, --ray-bias and --print-class: how the truth is made and which disagreements are shown.
Result<void> parseTruth(const cli::Args& args, StaticOptions& o) {
    if (args.has("--ray-bias")) {
        const std::string v = args.get("--ray-bias", "");
        auto bias = opts::number("--ray-bias", v, 0.0f, 1.0f);
        if (!bias) return fail("--ray-bias: '" + v + "' is not a distance in [0, 1] m");
        o.rayBias = bias.value();
    }
    if (args.has("--print-class")) {
        const std::string name = args.get("--print-class", "");
        for (uint32_t c = 0; c < kErrorClassCount; ++c)
            if (name == errorClassName(ErrorClass(c))) o.printClass = c;
        if (o.printClass == kErrorClassCount)
            return fail("--print-class: '" + name +
                        "' is not inside, contact, resolution, thin-open or other");
    }
    const std::string receiverMode = args.get("--receivers", "exact");
    if (receiverMode != "exact" && receiverMode != "gbuffer")
        return fail("--receivers: '" + receiverMode + "' is not exact or gbuffer");
    o.exactReceivers = receiverMode == "exact";
    return {};
}

Result<StaticOptions> parseStatic(const cli::Args& args) {
    StaticOptions o;
    auto methods = opts::methodList("--methods", args.get("--methods", "sm,mh,mmh,dagmh,cpvs"));
    auto resolutions = opts::uintList("--res", args.get("--res", "1024,2048,4096,8192"), 16, 65536);
    auto count = cli::parseUint("--lights", args.get("--lights", "8"), 1, 4096);
    auto view = opts::view(args, {3, 1, 100, "640x360"});
    auto pcf = cli::parseUint("--pcf", args.get("--pcf", "0"), 0, ML_MAX_PCF_RADIUS);
    auto scene = opts::scene(args);
    auto extraLookups = cli::parseUint("--lookups", args.get("--lookups", "8"), 1, 1024);
    auto lookupPairs = cli::parseUint("--lookup-pairs", args.get("--lookup-pairs", "16384"), 1, 1u << 24);
    for (const std::string* e : {&methods.error(), &resolutions.error(), &count.error(), &view.error(),
                                 &pcf.error(), &scene.error(), &extraLookups.error(), &lookupPairs.error()})
        if (!e->empty()) return fail(*e);
    if (auto r = parseTruth(args, o); !r) return fail(r.error());
    if (const std::string radii = args.get("--lookup-pcf", "0,1,2,3,4"); radii != "none") {
        auto r = opts::uintList("--lookup-pcf", radii, 0, ML_MAX_PCF_RADIUS);
        if (!r) return fail(r.error());
        o.lookupRadii = r.value();
    }
    o.methods = methods.value(), o.resolutions = resolutions.value(), o.lights = count.value();
    o.view = view.value(), o.pcf = pcf.value(), o.scene = scene.value();
    o.extraLookups = extraLookups.value(), o.lookupPairs = lookupPairs.value();
    o.out = args.get("--out", "out/bench_static");
    return o;
}

// Receivers: the G-buffer of one frame. Exact receivers (the default) are moved onto the surface the
// pixel centre's camera ray (in double) hits in the static scene, when it is near the G-buffer's depth.
Result<std::vector<Receiver>> gatherReceivers(Module& m, const RayReference& rays, const StaticOptions& o) {
    evaluateMs(m, 1);
    const diag::LastFrame fc = diag::lastFrame(m);
    std::vector<float> depth;
    std::vector<glm::vec3> normal;
    if (auto r = diag::readGBuffer(m, depth, normal); !r) return fail(r.error());
    const uint32_t width = o.view.width, height = o.view.height;
    const glm::dmat4 inv = glm::inverse(glm::dmat4(fc.viewProj));
    const glm::dvec3 eye(fc.cameraPosition);
    uint64_t moved = 0, kept = 0;
    double maxMove = 0;
    std::vector<Receiver> receivers;
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            size_t i = size_t(y) * width + x;
            if (!gpu::hasSurface(depth[i])) continue;
            glm::vec3 p = gpu::worldFromPixel(x, y, depth[i], fc.invViewProj, fc.size);
            glm::vec3 n = normal[i];
            if (o.exactReceivers) {
                const glm::dvec3 dir = pixelRayDirection(inv, x, y, width, height, PixelConvention::GBuffer);
                double t0 = glm::length(glm::dvec3(p) - eye);
                RayHit h = rays.firstHit(glm::vec3(eye), glm::vec3(dir), 0.0f, float(t0 * 1.5 + 1.0));
                if (h.hit && std::abs(double(h.t) - t0) < std::max(0.05, 0.002 * t0)) {
                    glm::vec3 q = glm::vec3(eye + dir * double(h.t));
                    maxMove = std::max(maxMove, double(glm::length(q - p)));
                    p = q;
                    ++moved;
                } else {
                    ++kept; // a dynamic instance (not in the rays) or a silhouette pixel
                }
            }
            receivers.push_back({p, glm::normalize(n)});
        }
    if (o.exactReceivers)
        std::fprintf(stderr, "  receivers: %llu moved onto the traced surface (at most %.3f m), %llu kept\n",
                     (unsigned long long)moved, maxMove, (unsigned long long)kept);
    return receivers;
}

// Lights: static spots reaching the most receivers, at most `count`.
std::vector<uint32_t> rankLights(const Scene& scene, const std::vector<Receiver>& receivers, uint32_t count) {
    const auto ranked = rankStaticSpots(scene, [&](const Light& l) {
        size_t n = 0;
        for (const Receiver& r : receivers) n += inLightCone(l, r.p);
        return n;
    });
    for (size_t k = 0; k < ranked.size() && k < 3; ++k) {
        const Light& l = scene.lights[ranked[k].second];
        std::fprintf(stderr, "  light %u at %.1f,%.1f,%.1f reaches %zu receivers\n", ranked[k].second,
                     l.position.x, l.position.y, l.position.z, ranked[k].first);
    }
    return firstLights(ranked, count);
}

// Ray-traced truth per light, over the receivers in its cone.
struct LightSet {
    uint32_t light;
    LightFrustum frustum;
    std::vector<uint32_t> receivers;
    std::vector<uint8_t> truth;
};

std::vector<LightSet> lightSets(const Scene& scene, const RayReference& rays,
                                const std::vector<Receiver>& receivers, const std::vector<uint32_t>& lights,
                                float rayBias) {
    std::vector<LightSet> sets;
    for (uint32_t i : lights) {
        const Light& l = scene.lights[i];
        LightSet s{i, spotLightFrustum(l), {}, {}};
        std::vector<glm::vec3> ps, ns;
        for (uint32_t r = 0; r < receivers.size(); ++r)
            // Receivers that face the light: elsewhere the shading is zero whatever the visibility.
            if (inLightCone(l, receivers[r].p) &&
                glm::dot(receivers[r].n, l.position - receivers[r].p) > 0.0f) {
                s.receivers.push_back(r);
                ps.push_back(receivers[r].p);
                ns.push_back(receivers[r].n);
            }
        s.truth.resize(ps.size());
        rays.visibleBatch(ps.data(), ns.data(), ps.size(), l.position, rayBias, s.truth.data());
        sets.push_back(std::move(s));
    }
    return sets;
}

// Lookup timing pairs: the same (receiver, light) pairs for every method and resolution, evenly
// sampled from the compared ones.
std::vector<LookupPair> lookupPairs(const std::vector<LightSet>& sets, const std::vector<Receiver>& receivers,
                                    uint32_t count) {
    std::vector<LookupPair> pairs;
    size_t total = 0;
    for (auto& s : sets) total += s.receivers.size();
    const double step = std::max(1.0, double(total) / count);
    double next = 0;
    size_t index = 0;
    for (uint32_t k = 0; k < sets.size(); ++k)
        for (uint32_t r : sets[k].receivers) {
            if (double(index++) >= next) {
                pairs.push_back({receivers[r].p, receivers[r].n, k});
                next += step;
            }
        }
    return pairs;
}

// Everything the configurations are measured against.
struct Bench {
    const StaticOptions& o;
    Scene& scene;
    Module& m;
    const SceneBinding& binding;
    const RayReference& rays;
    std::vector<Receiver> receivers;
    std::vector<LightSet> sets;
    std::vector<LookupPair> pairs;
    std::unique_ptr<LookupTimer> timer;
    std::unique_ptr<GpuDualRenderer> renderer;
    CasterTriangles casters;
};

// Encoded words per method and light (empty: the plain map past 512 MiB per light, sized only).
using Encodings = std::vector<std::vector<std::vector<uint32_t>>>;

// One light's dual map at a time (a 16K map is 2 GiB): render it, encode it with every method, keep
// the encodings. The 32-bit map itself is kept only while it fits in 512 MiB per light.
Result<void> encodeAll(Bench& b, uint32_t res, std::vector<Row>& resRows, Encodings& encoded) {
    const bool keepPlain = uint64_t(res) * res * 4 <= (512ull << 20);
    const std::vector<StaticMethod>& methods = b.o.methods;
    double renderS = 0;
    for (size_t k = 0; k < b.sets.size(); ++k) {
        auto t0 = std::chrono::steady_clock::now();
        auto map = b.renderer->render(b.casters, b.sets[k].frustum, res);
        if (!map) return fail(map.error());
        renderS += seconds(t0);
        for (size_t mi = 0; mi < methods.size(); ++mi) {
            Row& row = resRows[mi];
            auto t1 = std::chrono::steady_clock::now();
            CpvsStats cs;
            auto words = encodeStatic(methods[mi], map.value(),
                                      {b.sets[k].frustum.nearPlane, b.sets[k].frustum.farPlane, {}, &cs});
            if (!words) { // reported in the table, the other methods go on
                if (row.failed.empty()) row.failed = words.error();
                continue;
            }
            row.encodeS += seconds(t1);
            if (methods[mi] == StaticMethod::CPVS) {
                row.precomputeS += cs.precomputeMs / 1000.0;
                row.insertS += cs.insertMs / 1000.0;
                row.compressS += (cs.compressMs + cs.layoutMs) / 1000.0;
            }
            row.bytes += words->size() * 4;
            if (methods[mi] != StaticMethod::SM || keepPlain) encoded[mi][k] = std::move(words.value());
        }
    }
    for (size_t mi = 0; mi < methods.size(); ++mi) {
        Row& row = resRows[mi];
        row.method = staticMethodName(methods[mi]);
        row.res = res;
        row.lights = uint32_t(b.sets.size());
        row.renderS = renderS;
        row.mapBytes = uint64_t(res) * res * 4 * b.sets.size();
    }
    return {};
}

// The isolated cost of one lookup per PCF radius, over every light's words in one buffer.
Result<void> timeLookups(Bench& b, StaticMethod method, uint32_t res,
                         const std::vector<std::vector<uint32_t>>& words, Row& row) {
    std::vector<gpu::GpuShadowRecord> records;
    std::vector<uint32_t> all;
    for (size_t k = 0; k < b.sets.size(); ++k) {
        records.push_back(makeShadowRecord(method, b.sets[k].frustum, uint32_t(all.size()), res, 0));
        all.insert(all.end(), words[k].begin(), words[k].end());
    }
    const uint64_t range = b.timer->maxStorageBufferRange();
    if (all.size() * 4 > range) {
        row.lookupSkipped = std::to_string(all.size() * 4 >> 20) + " MiB of words > the device's " +
                            std::to_string(range >> 20) + " MiB storage buffer range";
        return {};
    }
    auto t = b.timer->measure(records, all, b.pairs, b.o.lookupRadii, b.o.extraLookups, 3);
    if (!t) return fail(t.error());
    row.lookup = std::move(t.value());
    return {};
}

// Accuracy: the method's visibility (the CPU twin of the shader's lookup) against the rays, and each
// disagreement's cause.
Disagreement measureAccuracy(const Bench& b, StaticMethod method, uint32_t res,
                             const std::vector<std::vector<uint32_t>>& words, Row& row) {
    Disagreement total;
    for (size_t k = 0; k < b.sets.size(); ++k) {
        const LightSet& set = b.sets[k];
        auto rec = makeShadowRecord(method, set.frustum, 0, res, b.o.pcf);
        std::vector<float> vis;
        for (uint32_t r : set.receivers)
            vis.push_back(staticVisibility(rec, words[k].data(), b.receivers[r].p, b.receivers[r].n));
        total.merge(compareVisibility(vis, set.truth));
        if (method == StaticMethod::DAGMH) {
            const auto one = makeShadowRecord(method, set.frustum, 0, res, 0);
            const auto pcf = makeShadowRecord(method, set.frustum, 0, res, 1);
            for (uint32_t r : set.receivers) {
                const Receiver& rc = b.receivers[r];
                ++row.boundsOneTap[dagmhBoundsDecision(one, words[k].data(), rc.p, rc.n)];
                ++row.bounds3x3[dagmhBoundsDecision(pcf, words[k].data(), rc.p, rc.n)];
            }
        }
        const glm::vec3 lp = b.scene.lights[set.light].position;
        ErrorContext ctx{&b.rays, rec, words[k].data(), lp, b.o.rayBias};
        for (size_t j = 0; j < vis.size(); ++j) {
            if ((vis[j] >= 0.5f) == (set.truth[j] != 0)) continue;
            const Receiver& rc = b.receivers[set.receivers[j]];
            ErrorClass ec = classifyDisagreement(ctx, rc.p, rc.n);
            ++row.classes[uint32_t(ec)];
            if (uint32_t(ec) == b.o.printClass)
                std::fprintf(stderr,
                             "  %s %s %u light %u receiver %.2f,%.2f,%.2f normal %.2f,%.2f,%.2f "
                             "%.2f m from the light: map %.2f, rays %s\n",
                             errorClassName(ec), row.method.c_str(), res, set.light, rc.p.x, rc.p.y, rc.p.z,
                             rc.n.x, rc.n.y, rc.n.z, glm::length(lp - rc.p), vis[j],
                             set.truth[j] ? "lit" : "shadowed");
        }
    }
    return total;
}

// One method at one resolution: the evaluation pass with its maps loaded, the lookup timing and the
// accuracy.
Result<void> measureMethod(Bench& b, StaticMethod method, uint32_t res,
                           const std::vector<std::vector<uint32_t>>& words, Row& row) {
    for (size_t k = 0; k < b.sets.size(); ++k)
        if (auto r =
                b.m.setStaticShadow(b.binding.lights[b.sets[k].light], {method, b.sets[k].frustum, words[k]});
            !r) {
            // The device cannot hold these maps (e.g. plain maps past the storage buffer range): the
            // row says so and the other methods and resolutions still run.
            for (size_t j = 0; j < k; ++j) b.m.clearStaticShadow(b.binding.lights[b.sets[j].light]);
            row.failed = "not loaded: " + r.error();
            return {};
        }
    row.evalMs = evaluateMs(b.m, b.o.view.frames);
    for (const LightSet& ls : b.sets) b.m.clearStaticShadow(b.binding.lights[ls.light]);
    if (b.timer)
        if (auto r = timeLookups(b, method, res, words, row); !r) return r;
    const Disagreement total = measureAccuracy(b, method, res, words, row);
    row.compared = total.compared;
    row.mismatches = total.mismatches;
    row.meanAbs = total.meanAbsDiff;
    std::fprintf(stderr,
                 "  %-5s %5u^2: %10llu bytes, render %.2f s, encode %.2f s, eval %.1f ms, %.3f%% wrong\n",
                 row.method.c_str(), res, (unsigned long long)row.bytes, row.renderS, row.encodeS, row.evalMs,
                 100.0 * total.rate());
    return {};
}

Result<void> measureResolution(Bench& b, uint32_t res, std::vector<Row>& rows) {
    const std::vector<StaticMethod>& methods = b.o.methods;
    std::vector<Row> resRows(methods.size());
    Encodings encoded(methods.size(), std::vector<std::vector<uint32_t>>(b.sets.size()));
    if (auto r = encodeAll(b, res, resRows, encoded); !r) return r;
    for (size_t mi = 0; mi < methods.size(); ++mi) {
        Row& row = resRows[mi];
        if (!row.failed.empty()) {
            std::fprintf(stderr, "  %-5s %5u^2: cannot encode: %s\n", row.method.c_str(), res,
                         row.failed.c_str());
        } else if (encoded[mi][0].empty()) { // the plain map past 512 MiB per light: bytes only
            row.evalMs = -1.0;
        } else {
            if (auto r = measureMethod(b, methods[mi], res, encoded[mi], row); !r) return r;
            if (!row.failed.empty())
                std::fprintf(stderr, "  %-5s %5u^2: %s\n", row.method.c_str(), res, row.failed.c_str());
            encoded[mi] = {};
        }
        rows.push_back(row);
    }
    return {};
}

// The scene's module: fenced timing, the scene bound, the view's targets, the camera and the filter.
// Each pass in its own submission, timed with the host clock: GPU timestamps do not bracket compute
// work on lavapipe (manylights/module.h, TimingChoice), so the eval column would be noise.
int setupModule(const cli::Args& args, const StaticOptions& o, Scene& scene, std::unique_ptr<Module>& module,
                SceneBinding& binding) {
    ModuleOptions moduleOptions;
    moduleOptions.timing = TimingChoice::Fenced;
    auto created = Module::create(moduleOptions);
    if (!created) return runError("bench static", created.error());
    module = std::move(created.value());
    Module& m = *module;
    auto bound = bindScene(m, scene);
    if (!bound) return runError("bench static", bound.error());
    binding = std::move(bound.value());
    if (auto r = m.createTargets(o.view.width, o.view.height); !r) return runError("bench static", r.error());
    m.setStatistics(false);
    if (args.has("--camera")) {
        auto v = cli::parseCamera("--camera", args.get("--camera", ""));
        if (!v) return usageError("bench static", v.error());
        scene.camera.position = {v.value()[0], v.value()[1], v.value()[2]};
        scene.camera.target = {v.value()[3], v.value()[4], v.value()[5]};
        if (auto r = m.setCamera(toCameraDesc(scene.camera)); !r)
            return usageError("bench static", r.error());
    }
    if (auto r = m.setShadowFilter(o.pcf); !r) return usageError("bench static", r.error());
    return 0;
}

// Receivers, lights, their truth, the lookup pairs and timer, and the renderer of the maps.
Result<void> prepare(Bench& b) {
    auto receivers = gatherReceivers(b.m, b.rays, b.o);
    if (!receivers) return fail(receivers.error());
    b.receivers = std::move(receivers.value());
    const std::vector<uint32_t> lights = rankLights(b.scene, b.receivers, b.o.lights);
    if (lights.empty()) return fail(b.o.scene.name + ": no static spot light reaches the view");
    b.sets = lightSets(b.scene, b.rays, b.receivers, lights, b.o.rayBias);
    size_t compared = 0;
    for (auto& s : b.sets) compared += s.receivers.size();
    std::fprintf(stderr, "bench static: %s, %zu lights, %zu receivers in their cones\n", b.scene.name.c_str(),
                 b.sets.size(), compared);
    b.pairs = lookupPairs(b.sets, b.receivers, b.o.lookupPairs);
    if (!b.o.lookupRadii.empty()) {
        auto t = LookupTimer::create();
        if (!t) return fail(t.error());
        b.timer = std::move(t.value());
    }
    auto renderer = GpuDualRenderer::create();
    if (!renderer) return fail(renderer.error());
    b.renderer = std::move(renderer.value());
    b.casters = castersFromScene(b.scene);
    return {};
}

// The tables, bench_static.csv, the cause and lookup tables and the charts.
int report(const Bench& b, const std::vector<Row>& rows, double noneMs) {
    const StaticOptions& o = b.o;
    std::printf("bench static: %s, %zu lights, view %ux%u, pcf %u, %s\n", b.scene.name.c_str(), b.sets.size(),
                o.view.width, o.view.height, o.pcf, b.m.deviceInfo().name.c_str());
    const std::string csv = printMainTable(rows);
    std::printf("(sm past 512 MiB per light is sized, not loaded: eval and wrong are '-')\n");
    std::printf("evaluation pass without static shadows: %.1f ms\n", noneMs);
    printCpvsSplit(rows);
    printBoundsTable(rows);
    if (auto r = printClassTables(o.out, rows, o.methods); !r) return runError("bench static", r.error());
    if (!o.lookupRadii.empty())
        if (auto r = printLookupTable(o.out, rows, o.lookupRadii, b.pairs.size(), o.extraLookups); !r)
            return runError("bench static", r.error());
    if (auto w = io::writeFileAtomically(o.out + "/bench_static.csv", csv); !w)
        return runError("bench static", w.error());
    if (auto r = writeCharts(o.out, rows); !r) return runError("bench static", r.error());
    std::printf("wrote %s/bench_static.csv, bench_classes.csv, bench_lookup.csv and the charts\n",
                o.out.c_str());
    return 0;
}
} // namespace

// The flags of `bench static` beside its option groups.
const cli::Flags kStaticFlags{{"--methods", "--res", "--lights", "--pcf", "--out", "--camera", "--lookup-pcf",
                               "--lookups", "--lookup-pairs", "--receivers", "--print-class", "--ray-bias"},
                              {}};

int runBenchStatic(int argc, char** argv) {
    // --- bench static --need: fixed against need-based resolution, its own options (bench_static_need.cpp).
    for (int i = 3; i < argc; ++i)
        if (std::string(argv[i]) == "--need") return runBenchStaticNeed(argc, argv);
    int status = 0;
    const auto args = commandArgs(
        "bench static", kHelp,
        cli::parse(argc, argv, 3, {opts::kSceneFlags, opts::kSceneDirFlags, opts::kViewFlags, kStaticFlags}),
        status);
    if (!args) return status;
    auto options = parseStatic(*args);
    if (!options) return usageError("bench static", options.error());
    const StaticOptions& o = options.value();
    if (auto r = cli::checkOutputDirectory("--out", o.out); !r) return usageError("bench static", r.error());
    auto scene = loadScene(o.scene.name, o.scene.name.rfind("night-city", 0) == 0 ? 256 : 32, o.scene.seed,
                           {o.scene.allowOutside});
    if (!scene) return inputError("bench static", scene.error());
    std::unique_ptr<Module> module;
    SceneBinding binding;
    if (int status = setupModule(*args, o, scene.value(), module, binding)) return status;
    auto rays = RayReference::build(scene.value(), true);
    if (!rays) return runError("bench static", rays.error());
    Bench b{o, scene.value(), *module, binding, rays.value(), {}, {}, {}, {}, {}, {}};
    if (auto r = prepare(b); !r) return runError("bench static", r.error());
    std::vector<Row> rows;
    for (uint32_t res : o.resolutions)
        if (auto r = measureResolution(b, res, rows); !r) return runError("bench static", r.error());
    // Unshadowed evaluation time, same lights and view, for reference.
    const double noneMs = evaluateMs(b.m, o.view.frames);
    return report(b, rows, noneMs);
}

} // namespace ml
