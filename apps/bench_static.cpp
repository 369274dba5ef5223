// `manylights bench static`: every static shadow method at every resolution on the same lights of one
// scene, measured in one run: bytes (against the 32-bit map), bake seconds split into rendering the dual
// maps (Vulkan, tiles of <= 4096^2) and encoding, the one evaluation pass's GPU time with the method
// (same lights, same view), and the disagreement with ray-traced visibility (Embree) over the pixels the
// lights reach. Prints a table, writes a CSV and, with gnuplot, charts of accuracy against memory and
// against time. Also (issue 11): every disagreement's cause (bake/reference/error_classes.h) with
// the resolution class's convergence slope per method, and the isolated cost of one lookup per method,
// resolution and PCF size (shadows/tools/lookup_timer.h). Receivers are moved onto the traced surface
// by default (--receivers); since the G-buffer is reversed Z (engine/camera.h) they move by millimetres.
#include "apps/cli.h"
#include "bake/scene_casters.h"
#include "apps/commands.h"
#include "apps/bench_static_tables.h"
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
  --scene S        night-city (default) or a .gltf / .glb file
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
Result<std::vector<std::string>> splitList(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) out.push_back(item);
    if (out.empty()) return fail("empty list '" + text + "'");
    return out;
}

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
    for (size_t i = 1; i < reports.size(); ++i, ++n) sum += reports[i].times.ms[uint32_t(Pass::Evaluate)];
    return n ? sum / n : 0.0;
}

// One data file per method (gnuplot joins the points of a file with lines), then two charts.
Result<void> writeCharts(const std::string& dir, const std::vector<Row>& rows) {
    std::vector<std::string> methods;
    for (const Row& r : rows)
        if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);
    std::string script = dir + "/charts.gp";
    std::ostringstream gp;
    gp << "set terminal pngcairo size 900,600\nset key outside right\nset grid\nset logscale x 2\n"
          "set ylabel 'disagreement with ray-traced visibility (%)'\n";
    for (const auto& m : methods) {
        std::ostringstream dat;
        dat << "# bytes_per_light eval_ms disagreement_percent res one_tap_lookup_ns\n";
        for (const Row& r : rows)
            if (r.method == m && r.evalMs >= 0 && r.failed.empty()) {
                // The isolated one-tap lookup cost, or NaN (gnuplot skips it) when not measured.
                double ns = std::nan("");
                for (const LookupTiming& t : r.lookup)
                    if (t.radius == 0) ns = t.nsPerLookup;
                dat << double(r.bytes) / r.lights << " " << r.evalMs << " "
                    << (r.compared ? 100.0 * double(r.mismatches) / r.compared : 0.0) << " " << r.res << " "
                    << ns << "\n";
            }
        if (auto w = io::writeFileAtomically(dir + "/" + m + ".dat", dat.str()); !w) return w;
    }
    const bool anyLookup = std::any_of(rows.begin(), rows.end(), [](const Row& r) {
        return std::any_of(r.lookup.begin(), r.lookup.end(),
                           [](const LookupTiming& t) { return t.radius == 0; });
    });
    for (int chart = 0; chart < (anyLookup ? 3 : 2); ++chart) {
        const char* names[3] = {"/accuracy_vs_bytes.png'\n", "/accuracy_vs_time.png'\n",
                                "/accuracy_vs_lookup.png'\n"};
        const char* xlabels[3] = {
            "set xlabel 'bytes per light'\n",
            "unset logscale x\nset xlabel 'evaluation pass, GPU ms (same lights, same view)'\n",
            "set xlabel 'one-tap lookup, ns (isolated pass)'\n"};
        const int column[3] = {1, 2, 5};
        gp << "set output '" << dir << names[chart] << xlabels[chart] << "plot ";
        for (size_t i = 0; i < methods.size(); ++i)
            gp << (i ? ", " : "") << "'" << dir << "/" << methods[i] << ".dat' using " << column[chart]
               << ":3 with linespoints title '" << methods[i] << "'";
        gp << "\n";
    }
    if (auto w = io::writeFileAtomically(script, gp.str()); !w) return w;
    std::string cmd = "gnuplot '" + script + "' 2>&1";
    if (std::system(cmd.c_str()) != 0)
        return fail("gnuplot failed on " + script + " (is gnuplot-nox installed?)");
    return {};
}
} // namespace

int runBenchStatic(int argc, char** argv) {
    // --- bench static --need: fixed against need-based resolution, its own options (bench_static_need.cpp).
    for (int i = 3; i < argc; ++i)
        if (std::string(argv[i]) == "--need") return runBenchStaticNeed(argc, argv);
    auto args = cli::parse(argc, argv, 3,
                           {"--scene", "--methods", "--res", "--lights", "--size", "--frames", "--pcf",
                            "--seed", "--out", "--camera", "--lookup-pcf", "--lookups", "--lookup-pairs",
                            "--receivers", "--print-class", "--ray-bias"},
                           {"--allow-outside-scene-dir"});
    if (!args) return usageError("bench static", args.error());
    if (args->help) {
        std::fputs(kHelp, stdout);
        return 0;
    }
    auto methodNames = splitList(args->get("--methods", "sm,mh,mmh,dagmh,cpvs"));
    auto resNames = splitList(args->get("--res", "1024,2048,4096,8192"));
    auto count = cli::parseUint("--lights", args->get("--lights", "8"), 1, 4096);
    auto size = cli::parseSize("--size", args->get("--size", "640x360"));
    auto frames = cli::parseUint("--frames", args->get("--frames", "3"), 1, 100);
    auto pcf = cli::parseUint("--pcf", args->get("--pcf", "0"), 0, ML_MAX_PCF_RADIUS);
    auto seed = cli::parseUint("--seed", args->get("--seed", "1"), 0, 0xFFFFFFFFu);
    auto extraLookups = cli::parseUint("--lookups", args->get("--lookups", "8"), 1, 1024);
    auto lookupPairs = cli::parseUint("--lookup-pairs", args->get("--lookup-pairs", "16384"), 1, 1u << 24);
    for (const std::string* e :
         {&methodNames.error(), &resNames.error(), &count.error(), &size.error(), &frames.error(),
          &pcf.error(), &seed.error(), &extraLookups.error(), &lookupPairs.error()})
        if (!e->empty()) return usageError("bench static", *e);
    const std::string receiverMode = args->get("--receivers", "exact");
    float rayBias = kRayBias;
    if (args->has("--ray-bias")) {
        const std::string v = args->get("--ray-bias", "");
        char* end = nullptr;
        rayBias = std::strtof(v.c_str(), &end);
        if (v.empty() || *end || !(rayBias >= 0.0f && rayBias <= 1.0f))
            return usageError("bench static", "--ray-bias: '" + v + "' is not a distance in [0, 1] m");
    }
    uint32_t printClass = kErrorClassCount; // none
    if (args->has("--print-class")) {
        const std::string name = args->get("--print-class", "");
        for (uint32_t c = 0; c < kErrorClassCount; ++c)
            if (name == errorClassName(ErrorClass(c))) printClass = c;
        if (printClass == kErrorClassCount)
            return usageError("bench static", "--print-class: '" + name +
                                                  "' is not inside, contact, resolution, thin-open or other");
    }
    if (receiverMode != "exact" && receiverMode != "gbuffer")
        return usageError("bench static", "--receivers: '" + receiverMode + "' is not exact or gbuffer");
    std::vector<uint32_t> lookupRadii;
    if (args->get("--lookup-pcf", "0,1,2,3,4") != "none") {
        auto names = splitList(args->get("--lookup-pcf", "0,1,2,3,4"));
        if (!names) return usageError("bench static", names.error());
        for (const auto& n : names.value()) {
            auto r = cli::parseUint("--lookup-pcf", n, 0, ML_MAX_PCF_RADIUS);
            if (!r) return usageError("bench static", r.error());
            lookupRadii.push_back(r.value());
        }
    }
    std::vector<StaticMethod> methods;
    for (const auto& n : methodNames.value()) {
        auto m = parseStaticMethod(n);
        if (!m || m.value() == StaticMethod::None)
            return usageError("bench static", m ? "method none" : m.error());
        methods.push_back(m.value());
    }
    std::vector<uint32_t> resolutions;
    for (const auto& n : resNames.value()) {
        auto r = cli::parseUint("--res", n, 16, 65536);
        if (!r) return usageError("bench static", r.error());
        resolutions.push_back(r.value());
    }
    const std::string out = args->get("--out", "out/bench_static");
    if (auto r = cli::makeDirectory(out); !r) return runError("bench static", r.error());
    const std::string sceneName = args->get("--scene", "night-city");

    auto scene = loadScene(sceneName, sceneName == "night-city" ? 256 : 32, seed.value(),
                           {args->has("--allow-outside-scene-dir")});
    if (!scene) return runError("bench static", scene.error());
    // Fenced: each pass in its own submission, timed with the host clock. GPU timestamps do not bracket
    // compute work on lavapipe (engine/manylights.h, TimingChoice), so the eval column would be noise.
    ModuleOptions moduleOptions;
    moduleOptions.timing = TimingChoice::Fenced;
    auto module = Module::create(moduleOptions);
    if (!module) return runError("bench static", module.error());
    Module& m = *module.value();
    auto binding = bindScene(m, scene.value());
    if (!binding) return runError("bench static", binding.error());
    auto [width, height] = size.value();
    if (auto r = m.createTargets(width, height); !r) return runError("bench static", r.error());
    m.setStatistics(false);
    if (args->has("--camera")) {
        auto v = cli::parseCamera("--camera", args->get("--camera", ""));
        if (!v) return usageError("bench static", v.error());
        scene->camera.position = {v.value()[0], v.value()[1], v.value()[2]};
        scene->camera.target = {v.value()[3], v.value()[4], v.value()[5]};
        if (auto r = m.setCamera(toCameraDesc(scene->camera)); !r)
            return usageError("bench static", r.error());
    }
    if (auto r = m.setShadowFilter(pcf.value()); !r) return usageError("bench static", r.error());

    auto rays = RayReference::build(scene.value(), true);
    if (!rays) return runError("bench static", rays.error());

    // Receivers: the G-buffer of one frame.
    evaluateMs(m, 1);
    const diag::LastFrame fc = diag::lastFrame(m);
    std::vector<Receiver> receivers;
    {
        std::vector<float> depth;
        std::vector<glm::vec3> normal;
        if (auto r = diag::readGBuffer(m, depth, normal); !r) return runError("bench static", r.error());
        // Exact receivers: the pixel centre's camera ray in double, traced against the static scene.
        const glm::dmat4 inv = glm::inverse(glm::dmat4(fc.viewProj));
        const glm::dvec3 eye(fc.cameraPosition);
        uint64_t moved = 0, kept = 0;
        double maxMove = 0;
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x) {
                size_t i = size_t(y) * width + x;
                if (!gpu::hasSurface(depth[i])) continue;
                glm::vec3 p = gpu::worldFromPixel(x, y, depth[i], fc.invViewProj, fc.size);
                glm::vec3 n = normal[i];
                if (receiverMode == "exact") {
                    double nx = (x + 0.5) / width * 2.0 - 1.0, ny = (y + 0.5) / height * 2.0 - 1.0;
                    // Reversed Z: depth 1 is the near plane, 0 the far plane.
                    glm::dvec4 a = inv * glm::dvec4(nx, ny, 1.0, 1.0), b = inv * glm::dvec4(nx, ny, 0.0, 1.0);
                    glm::dvec3 dir = glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w);
                    double t0 = glm::length(glm::dvec3(p) - eye);
                    RayHit h = rays->firstHit(glm::vec3(eye), glm::vec3(dir), 0.0f, float(t0 * 1.5 + 1.0));
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
        if (receiverMode == "exact")
            std::fprintf(stderr,
                         "  receivers: %llu moved onto the traced surface (at most %.3f m), %llu kept\n",
                         (unsigned long long)moved, maxMove, (unsigned long long)kept);
    }

    // Lights: static spots reaching the most receivers.
    std::vector<std::pair<size_t, uint32_t>> ranked;
    for (uint32_t i = 0; i < scene->lights.size(); ++i) {
        const Light& l = scene->lights[i];
        if (l.dynamic || l.type != LightKind::Spot) continue;
        size_t n = 0;
        for (const Receiver& r : receivers) n += inLightCone(l, r.p);
        if (n) ranked.push_back({n, i});
    }
    std::sort(ranked.rbegin(), ranked.rend());
    for (size_t k = 0; k < ranked.size() && k < 3; ++k) {
        const Light& l = scene->lights[ranked[k].second];
        std::fprintf(stderr, "  light %u at %.1f,%.1f,%.1f reaches %zu receivers\n", ranked[k].second,
                     l.position.x, l.position.y, l.position.z, ranked[k].first);
    }
    if (ranked.size() > count.value()) ranked.resize(count.value());
    if (ranked.empty())
        return runError("bench static", sceneName + ": no static spot light reaches the view");

    // Ray-traced truth per light, over the receivers in its cone.
    struct LightSet {
        uint32_t light;
        LightFrustum frustum;
        std::vector<uint32_t> receivers;
        std::vector<uint8_t> truth;
    };
    std::vector<LightSet> sets;
    for (auto [n, i] : ranked) {
        LightSet s{i, spotLightFrustum(scene->lights[i]), {}, {}};
        std::vector<glm::vec3> ps, ns;
        for (uint32_t r = 0; r < receivers.size(); ++r)
            // Receivers that face the light: elsewhere the shading is zero whatever the visibility.
            if (inLightCone(scene->lights[i], receivers[r].p) &&
                glm::dot(receivers[r].n, scene->lights[i].position - receivers[r].p) > 0.0f) {
                s.receivers.push_back(r);
                ps.push_back(receivers[r].p);
                ns.push_back(receivers[r].n);
            }
        s.truth.resize(ps.size());
        rays->visibleBatch(ps.data(), ns.data(), ps.size(), scene->lights[i].position, rayBias,
                           s.truth.data());
        sets.push_back(std::move(s));
    }
    std::fprintf(stderr, "bench static: %s, %zu lights, %zu receivers in their cones\n", scene->name.c_str(),
                 sets.size(), [&] {
                     size_t n = 0;
                     for (auto& s : sets) n += s.receivers.size();
                     return n;
                 }());

    // Lookup timing pairs: the same (receiver, light) pairs for every method and resolution, evenly
    // sampled from the compared ones.
    std::vector<LookupPair> pairs;
    {
        size_t total = 0;
        for (auto& s : sets) total += s.receivers.size();
        const double step = std::max(1.0, double(total) / lookupPairs.value());
        double next = 0;
        size_t index = 0;
        for (uint32_t k = 0; k < sets.size(); ++k)
            for (uint32_t r : sets[k].receivers) {
                if (double(index++) >= next) {
                    pairs.push_back({receivers[r].p, receivers[r].n, k});
                    next += step;
                }
            }
    }
    std::unique_ptr<LookupTimer> timer;
    if (!lookupRadii.empty()) {
        auto t = LookupTimer::create();
        if (!t) return runError("bench static", t.error());
        timer = std::move(t.value());
    }

    auto renderer = GpuDualRenderer::create();
    if (!renderer) return runError("bench static", renderer.error());
    CasterTriangles casters = castersFromScene(scene.value());
    std::vector<Row> rows;
    for (uint32_t res : resolutions) {
        // One light's dual map at a time (a 16K map is 2 GiB): render it, encode it with every method,
        // keep the encodings. The 32-bit map itself is kept only while it fits in 512 MiB per light.
        const bool keepPlain = uint64_t(res) * res * 4 <= (512ull << 20);
        std::vector<Row> resRows(methods.size());
        std::vector<std::vector<std::vector<uint32_t>>> encoded(
            methods.size(), std::vector<std::vector<uint32_t>>(sets.size()));
        double renderS = 0;
        for (size_t k = 0; k < sets.size(); ++k) {
            auto t0 = std::chrono::steady_clock::now();
            auto map = renderer.value()->render(casters, sets[k].frustum, res);
            if (!map) return runError("bench static", map.error());
            renderS += seconds(t0);
            for (size_t mi = 0; mi < methods.size(); ++mi) {
                Row& row = resRows[mi];
                auto t1 = std::chrono::steady_clock::now();
                CpvsStats cs;
                auto words = encodeStatic(methods[mi], map.value(),
                                          {sets[k].frustum.nearPlane, sets[k].frustum.farPlane, {}, &cs});
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
            const StaticMethod method = methods[mi];
            Row& row = resRows[mi];
            row.method = staticMethodName(method);
            row.res = res;
            row.lights = uint32_t(sets.size());
            row.renderS = renderS;
            row.mapBytes = uint64_t(res) * res * 4 * sets.size();
            if (!row.failed.empty()) {
                std::fprintf(stderr, "  %-5s %5u^2: cannot encode: %s\n", row.method.c_str(), res,
                             row.failed.c_str());
                rows.push_back(row);
                continue;
            }
            if (encoded[mi][0].empty()) { // the plain map past 512 MiB per light: bytes only
                row.evalMs = -1.0;
                rows.push_back(row);
                continue;
            }
            for (size_t k = 0; k < sets.size(); ++k)
                if (auto r = m.setStaticShadow(binding->lights[sets[k].light],
                                               {method, sets[k].frustum, encoded[mi][k]});
                    !r)
                    return runError("bench static", r.error());
            row.evalMs = evaluateMs(m, frames.value());
            for (const LightSet& ls : sets) m.clearStaticShadow(binding->lights[ls.light]);
            if (timer) {
                std::vector<gpu::GpuShadowRecord> records;
                std::vector<uint32_t> all;
                for (size_t k = 0; k < sets.size(); ++k) {
                    records.push_back(
                        makeShadowRecord(method, sets[k].frustum, uint32_t(all.size()), res, 0));
                    all.insert(all.end(), encoded[mi][k].begin(), encoded[mi][k].end());
                }
                const uint64_t range = timer->maxStorageBufferRange();
                if (all.size() * 4 > range) {
                    row.lookupSkipped = std::to_string(all.size() * 4 >> 20) +
                                        " MiB of words > the device's " + std::to_string(range >> 20) +
                                        " MiB storage buffer range";
                } else {
                    auto t = timer->measure(records, all, pairs, lookupRadii, extraLookups.value(), 3);
                    if (!t) return runError("bench static", t.error());
                    row.lookup = std::move(t.value());
                }
            }
            // Accuracy: the method's visibility (the CPU twin of the shader's lookup) against the rays.
            Disagreement total;
            for (size_t k = 0; k < sets.size(); ++k) {
                auto rec = makeShadowRecord(method, sets[k].frustum, 0, res, pcf.value());
                std::vector<float> vis;
                for (uint32_t r : sets[k].receivers)
                    vis.push_back(
                        staticVisibility(rec, encoded[mi][k].data(), receivers[r].p, receivers[r].n));
                total.merge(compareVisibility(vis, sets[k].truth));
                // Each disagreement's cause.
                ErrorContext ctx{&rays.value(), rec, encoded[mi][k].data(),
                                 scene->lights[sets[k].light].position, rayBias};
                for (size_t j = 0; j < vis.size(); ++j)
                    if ((vis[j] >= 0.5f) != (sets[k].truth[j] != 0)) {
                        const Receiver& rc = receivers[sets[k].receivers[j]];
                        ErrorClass ec = classifyDisagreement(ctx, rc.p, rc.n);
                        ++row.classes[uint32_t(ec)];
                        if (uint32_t(ec) == printClass) {
                            const glm::vec3 lp = scene->lights[sets[k].light].position;
                            std::fprintf(stderr,
                                         "  %s %s %u light %u receiver %.2f,%.2f,%.2f normal %.2f,%.2f,%.2f "
                                         "%.2f m from the light: map %.2f, rays %s\n",
                                         errorClassName(ec), row.method.c_str(), res, sets[k].light, rc.p.x,
                                         rc.p.y, rc.p.z, rc.n.x, rc.n.y, rc.n.z, glm::length(lp - rc.p),
                                         vis[j], sets[k].truth[j] ? "lit" : "shadowed");
                        }
                    }
            }
            encoded[mi] = {};
            row.compared = total.compared;
            row.mismatches = total.mismatches;
            row.meanAbs = total.meanAbsDiff;
            rows.push_back(row);
            std::fprintf(
                stderr,
                "  %-5s %5u^2: %10llu bytes, render %.2f s, encode %.2f s, eval %.1f ms, %.3f%% wrong\n",
                row.method.c_str(), res, (unsigned long long)row.bytes, row.renderS, row.encodeS, row.evalMs,
                100.0 * total.rate());
        }
    }
    // Unshadowed evaluation time, same lights and view, for reference.
    double noneMs = evaluateMs(m, frames.value());

    std::printf("bench static: %s, %zu lights, view %ux%u, pcf %u, %s\n", scene->name.c_str(), sets.size(),
                width, height, pcf.value(), m.deviceInfo().name.c_str());
    std::printf("| method | res | bytes/light | vs 32-bit map | render s | encode s | eval ms | eval vs sm | "
                "wrong %% |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    std::ostringstream csv;
    csv << "method,res,lights,bytes_total,map32_bytes,render_s,encode_s,eval_ms,eval_vs_sm,compared,"
           "disagreement,"
           "mean_abs_diff,cpvs_precompute_s,cpvs_insert_s,cpvs_compress_s\n";
    for (const Row& r : rows) {
        if (!r.failed.empty()) {
            std::printf("| %s | %u | %s |\n", r.method.c_str(), r.res, r.failed.c_str());
            csv << r.method << "," << r.res << "," << r.lights << ",,,,,,,,,,,,\n";
            continue;
        }
        double smMs = -1;
        for (const Row& s : rows)
            if (s.method == "sm" && s.res == r.res) smMs = s.evalMs;
        const bool measured = r.evalMs >= 0;
        double vsSm = smMs > 0 && measured ? r.evalMs / smMs : 0;
        double rate = r.compared ? double(r.mismatches) / r.compared : 0;
        char eval[32] = "-", ratio[32] = "-", wrong[32] = "-";
        if (measured) {
            std::snprintf(eval, sizeof(eval), "%.1f", r.evalMs);
            std::snprintf(wrong, sizeof(wrong), "%.3f", 100.0 * rate);
        }
        if (vsSm > 0) std::snprintf(ratio, sizeof(ratio), "%.2fx", vsSm);
        std::printf("| %s | %u | %.0f | 1/%.1f | %.2f | %.2f | %s | %s | %s |\n", r.method.c_str(), r.res,
                    double(r.bytes) / r.lights, double(r.mapBytes) / r.bytes, r.renderS, r.encodeS, eval,
                    ratio, wrong);
        csv << r.method << "," << r.res << "," << r.lights << "," << r.bytes << "," << r.mapBytes << ","
            << r.renderS << "," << r.encodeS << "," << r.evalMs << "," << vsSm << "," << r.compared << ","
            << rate << "," << r.meanAbs << "," << r.precomputeS << "," << r.insertS << "," << r.compressS
            << "\n";
    }
    std::printf("(sm past 512 MiB per light is sized, not loaded: eval and wrong are '-')\n");
    std::printf("evaluation pass without static shadows: %.1f ms\n", noneMs);
    bool anyCpvs = false;
    for (const Row& r : rows) anyCpvs |= r.method == "cpvs";
    if (anyCpvs) {
        std::printf("\nCPVS bake split (paper Table 3), seconds over all lights; bytes per light against a "
                    "16-bit map:\n");
        std::printf("| res | render maps | precompute | insert | compress | insert+compress vs render | "
                    "bytes/light | vs 16-bit map |\n");
        std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (const Row& r : rows)
            if (r.method == "cpvs")
                std::printf("| %u | %.3f | %.3f | %.3f | %.3f | %.2fx | %.0f | 1/%.0f |\n", r.res, r.renderS,
                            r.precomputeS, r.insertS, r.compressS, (r.insertS + r.compressS) / r.renderS,
                            double(r.bytes) / r.lights,
                            double(r.res) * r.res * 2.0 / (double(r.bytes) / r.lights));
    }
    if (auto r = printClassTables(out, rows, methods); !r) return runError("bench static", r.error());
    if (!lookupRadii.empty())
        if (auto r = printLookupTable(out, rows, lookupRadii, pairs.size(), extraLookups.value()); !r)
            return runError("bench static", r.error());
    if (auto w = io::writeFileAtomically(out + "/bench_static.csv", csv.str()); !w)
        return runError("bench static", w.error());
    if (auto r = writeCharts(out, rows); !r) return runError("bench static", r.error());
    std::printf("wrote %s/bench_static.csv, bench_classes.csv, bench_lookup.csv and the charts\n",
                out.c_str());
    return 0;
}

} // namespace ml
