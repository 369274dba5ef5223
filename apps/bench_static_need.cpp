// `manylights bench static --need REGION`: fixed against need-based resolution.
// Views along a camera path (evenly spaced samples of the region's path); every pixel's receiver is the
// static surface its centre ray hits (Embree, double precision: exact receivers, as bench static and
// bench flicker). The static spot lights that reach some receiver are baked twice per cap R and method:
// every light at R (fixed), and each light at its need-based resolution capped at R (bake --need). Both
// are measured on the same (pixel, light) pairs against the rays: total bytes, wrong % (one tap) and the
// resolution-class share (bake/reference/error_classes.h). Table on stdout, CSV in --out.
#include "apps/bake_renderer.h"
#include "apps/commands.h"
#include "apps/exact_receivers.h"
#include "apps/need_region.h"
#include "apps/options.h"
#include "manylights/device.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "bake/reference/error_classes.h"
#include "bake/reference/raytrace.h"
#include "bake/bake.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <sstream>
#include <tuple>

namespace ml {

// The rays' normal offset, as bench static's default (apps/bench_static.cpp, kRayBias): 1 mm. A 2 cm
// offset carries the ray past shadow edges at grazing incidence (docs/accuracy.md, section 1).
constexpr float kNeedRayBias = 0.001f;

static const char* kNeedHelp = R"(usage: manylights bench static --need REGION [options]
Fixed against need-based bake resolution at the same camera path: per cap R and method, every measured
light baked at R and at its need-based resolution (bake --need, capped at R); total bytes, share of
(pixel, light) pairs whose one-tap visibility disagrees with Embree rays, and its resolution class.
  --need REGION      path:static|drive|orbit (the views are this path's samples)
  --need-samples N   camera samples of the need estimate (default 120)
  --need-seconds S   path duration sampled (default 60)
  --need-size WxH    image the need is computed for (default: --size, the measured views')
  --need-min N       smallest need-based resolution (default 64)
  --views N          views measured, evenly spaced among the samples (default 8)
  --size WxH         size of each measured view (default 640x360; receivers are exact at any size)
  --res LIST         caps R, comma-separated (default 512,1024,2048)
  --methods LIST     default dagmh
  --lights N         at most N lights measured (those reaching the most receivers), default 64
  --scene S          night-city (default) or a .gltf / .glb file;  --scene-lights N (default 256)
  --seed S           scene seed, default 1
  --renderer R       gpu (default) or cpu, as for bake
  --out DIR          bench_need.csv (default out/bench_need)
)";

namespace {

struct Receiver {
    glm::vec3 p, n;
};

// One (view, light) set: the receivers of the view the light reaches (in cone and range, facing it) and
// the rays' answer for each.
struct PairSet {
    uint32_t light = 0;
    std::vector<Receiver> receivers;
    std::vector<uint8_t> truth;
};

struct Measure {
    uint64_t bytes = 0, compared = 0, wrong = 0, resolutionClass = 0;
    uint64_t classes[kErrorClassCount] = {};  // every disagreement by cause (none: no record)
    std::map<uint32_t, uint32_t> resolutions; // resolution -> lights
};

Measure measure(const BakeFile& f, const std::vector<PairSet>& sets, const RayReference& rays,
                const Scene& scene) {
    Measure m;
    m.bytes = bakeFileBytes(f).total();
    std::map<uint32_t, const BakeRecord*> byLight;
    for (const BakeRecord& r : f.records) {
        byLight[r.light] = &r;
        ++m.resolutions[r.resolution];
    }
    for (const PairSet& s : sets) {
        auto it = byLight.find(s.light);
        const BakeRecord* r = it == byLight.end() ? nullptr : it->second;
        auto rec = r ? makeShadowRecord(r->method, r->frustum, 0, r->resolution, 0) : gpu::GpuShadowRecord{};
        ErrorContext ctx{&rays, rec, r ? r->data.data() : nullptr, scene.lights[s.light].position,
                         kNeedRayBias};
        for (size_t i = 0; i < s.receivers.size(); ++i) {
            // No record (no caster in the volume): lit, as the module treats a light without one.
            const float v =
                r ? staticVisibility(rec, r->data.data(), s.receivers[i].p, s.receivers[i].n) : 1.0f;
            ++m.compared;
            if ((v >= 0.5f) == (s.truth[i] != 0)) continue;
            ++m.wrong;
            if (!r) continue;
            const ErrorClass c = classifyDisagreement(ctx, s.receivers[i].p, s.receivers[i].n);
            ++m.classes[uint32_t(c)];
            m.resolutionClass += c == ErrorClass::Resolution;
        }
    }
    return m;
}

std::string histogram(const std::map<uint32_t, uint32_t>& h) {
    std::string s;
    for (auto [res, n] : h) s += (s.empty() ? "" : ", ") + std::to_string(n) + "x" + std::to_string(res);
    return s;
}

struct NeedBench {
    opts::Need need;
    uint32_t views = 8, maxLights = 64, sceneLights = 256, width = 0, height = 0;
    opts::Scene scene;
    std::vector<uint32_t> caps;
    std::vector<StaticMethod> methods;
    std::string region, out;
    BakeRenderer renderer = BakeRenderer::Gpu;
};

Result<NeedBench> parseNeedBench(const cli::Args& args) {
    NeedBench o;
    auto need = opts::need(args, args.get("--size", "640x360"));
    auto views = cli::parseUint("--views", args.get("--views", "8"), 1, 1000);
    auto size = cli::parseSize("--size", args.get("--size", "640x360"));
    auto maxLights = cli::parseUint("--lights", args.get("--lights", "64"), 1, 4096);
    auto sceneLights = cli::parseUint("--scene-lights", args.get("--scene-lights", "256"), 1, 4096);
    auto scene = opts::scene(args);
    for (const std::string* e : {&need.error(), &views.error(), &size.error(), &maxLights.error(),
                                 &sceneLights.error(), &scene.error()})
        if (!e->empty()) return fail(*e);
    if (auto r = opts::checkNeedMin(need->minRes); !r) return fail(r.error());
    auto caps = opts::uintList("--res", args.get("--res", "512,1024,2048"), need->minRes, kBakeMaxResolution);
    auto methods = opts::methodList("--methods", args.get("--methods", "dagmh"));
    for (const std::string* e : {&caps.error(), &methods.error()})
        if (!e->empty()) return fail(*e);
    for (StaticMethod m : methods.value())
        for (uint32_t r : caps.value())
            if (m == StaticMethod::CPVS)
                if (auto s = makeCpvsSpace(r, 1.0f, 2.0f); !s) return fail("--res: " + s.error());
    o.region = args.get("--need", "");
    if (o.region.rfind("path:", 0) != 0)
        return fail("--need: '" + o.region + "': the comparison needs a path (its views)");
    auto renderer = parseRenderer(args);
    if (!renderer) return fail(renderer.error());
    o.need = need.value(), o.views = views.value(), o.maxLights = maxLights.value();
    o.sceneLights = sceneLights.value(), o.scene = scene.value();
    std::tie(o.width, o.height) = size.value();
    o.caps = caps.value(), o.methods = methods.value(), o.renderer = renderer.value();
    o.out = args.get("--out", "out/bench_need");
    return o;
}

// Exact receivers of each measured view (evenly spaced among the region's samples).
std::vector<std::vector<Receiver>> viewReceivers(const NeedBench& o, const NeedRegion& region,
                                                 const RayReference& rays) {
    const uint32_t V = std::min<uint32_t>(o.views, uint32_t(region.views.size()));
    std::vector<std::vector<Receiver>> receivers(V);
    for (uint32_t v = 0; v < V; ++v) {
        const Camera& cam = region.views[uint32_t(uint64_t(v) * region.views.size() / V)];
        const glm::dvec3 eye(cam.position);
        glm::dmat4 view = glm::lookAt(eye, glm::dvec3(cam.target), glm::dvec3(0, 1, 0));
        glm::dmat4 proj = glm::perspective(double(cam.fovY), double(o.width) / o.height,
                                           double(cam.nearPlane), double(cam.farPlane));
        glm::dmat4 inv = glm::inverse(proj * view);
        for (uint32_t y = 0; y < o.height; ++y)
            for (uint32_t x = 0; x < o.width; ++x) {
                const glm::dvec3 dir =
                    pixelRayDirection(inv, x, y, o.width, o.height, PixelConvention::Standard);
                const SurfaceHit h = traceSurface(rays, eye, dir, cam.farPlane);
                if (h.hit) receivers[v].push_back({h.p, h.n});
            }
    }
    return receivers;
}

// Static spots reaching the most receivers over all views (at most `maxLights`), in index order.
std::vector<uint32_t> rankLights(const Scene& scene, const std::vector<std::vector<Receiver>>& views,
                                 uint32_t maxLights) {
    std::vector<std::pair<size_t, uint32_t>> ranked;
    for (uint32_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        if (l.type != LightKind::Spot || !bakeSkipReason(scene, l).empty()) continue;
        size_t n = 0;
        for (const auto& rs : views)
            for (const Receiver& r : rs) n += inLightCone(l, r.p) && glm::dot(r.n, l.position - r.p) > 0.0f;
        if (n) ranked.push_back({n, i});
    }
    std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    if (ranked.size() > maxLights) ranked.resize(maxLights);
    std::vector<uint32_t> lights;
    for (auto [n, i] : ranked) lights.push_back(i);
    std::sort(lights.begin(), lights.end());
    return lights;
}

// Per view and light: the receivers it reaches and the rays' answer.
std::vector<PairSet> pairSets(const Scene& scene, const RayReference& rays,
                              const std::vector<std::vector<Receiver>>& views,
                              const std::vector<uint32_t>& lights) {
    std::vector<PairSet> sets;
    for (const auto& receivers : views)
        for (uint32_t li : lights) {
            const Light& l = scene.lights[li];
            PairSet s;
            s.light = li;
            std::vector<glm::vec3> ps, ns;
            for (const Receiver& r : receivers)
                if (inLightCone(l, r.p) && glm::dot(r.n, l.position - r.p) > 0.0f) {
                    s.receivers.push_back(r);
                    ps.push_back(r.p), ns.push_back(r.n);
                }
            if (s.receivers.empty()) continue;
            s.truth.resize(ps.size());
            rays.visibleBatch(ps.data(), ns.data(), ps.size(), l.position, kNeedRayBias, s.truth.data());
            sets.push_back(std::move(s));
        }
    return sets;
}

// What the caps are compared over.
struct NeedSetup {
    const NeedBench& o;
    SceneSpec spec;
    const Scene& scene;
    const RayReference& rays;
    const NeedRegion& region;
    std::vector<uint32_t> lights;
    std::vector<PairSet> sets;
    size_t pairs = 0;
    DualRenderFn render;
};

using ClassRow = std::tuple<std::string, uint32_t, Measure, Measure>;

// One method at one cap: baked fixed and by need, both measured; a table row and a CSV line.
Result<ClassRow> compareMethod(const NeedSetup& u, StaticMethod method, uint32_t cap, const BakeNeed& bn,
                               std::ostringstream& csv) {
    auto t0 = std::chrono::steady_clock::now();
    auto fixed = bakeScene(u.scene, u.spec, method, cap, u.lights, {}, u.render);
    if (!fixed) return fail(fixed.error());
    auto byNeed = bakeSceneNeed(u.scene, u.spec, method, bn, u.lights, {}, u.render);
    if (!byNeed) return fail(byNeed.error());
    const Measure a = measure(fixed->file, u.sets, u.rays, u.scene);
    const Measure b = measure(byNeed->file, u.sets, u.rays, u.scene);
    auto pct = [](uint64_t n, uint64_t d) { return d ? 100.0 * double(n) / double(d) : 0.0; };
    std::printf("| %s | %u | %llu | %llu | %.2f | %.4f | %.4f | %.4f | %.4f | %s |\n",
                staticMethodName(method), cap, (unsigned long long)a.bytes, (unsigned long long)b.bytes,
                double(b.bytes) / double(a.bytes), pct(a.wrong, a.compared), pct(b.wrong, b.compared),
                pct(a.resolutionClass, a.compared), pct(b.resolutionClass, b.compared),
                histogram(b.resolutions).c_str());
    std::fflush(stdout);
    csv << staticMethodName(method) << "," << cap << "," << u.lights.size() << "," << u.pairs << ","
        << a.bytes << "," << b.bytes << "," << double(a.wrong) / double(a.compared) << ","
        << double(b.wrong) / double(b.compared) << "," << double(a.resolutionClass) / double(a.compared)
        << "," << double(b.resolutionClass) / double(b.compared) << ",\"" << histogram(b.resolutions) << "\"";
    for (const Measure* x : {&a, &b})
        for (uint32_t c = 0; c < kErrorClassCount; ++c)
            csv << "," << double(x->classes[c]) / double(x->compared);
    csv << "\n";
    std::fprintf(stderr, "  %s cap %u: %.1f s\n", staticMethodName(method), cap,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return ClassRow{staticMethodName(method), cap, a, b};
}

// Every cap and method; the CSV's text, and the rows of the table by cause.
Result<std::string> compareCaps(const NeedSetup& u, std::vector<ClassRow>& classRows) {
    const NeedBench& o = u.o;
    std::ostringstream csv;
    csv << "method,cap,lights,pairs,fixed_bytes,need_bytes,fixed_wrong,need_wrong,fixed_resolution_class,"
           "need_resolution_class,need_resolutions";
    for (const char* which : {"fixed", "need"})
        for (uint32_t c = 0; c < kErrorClassCount; ++c)
            csv << "," << which << "_" << errorClassName(ErrorClass(c));
    csv << "\n";
    for (uint32_t cap : o.caps) {
        NeedOptions no;
        no.width = o.need.width, no.height = o.need.height, no.minRes = o.need.minRes, no.maxRes = cap;
        auto needs = estimateNeedWithRays(u.scene, u.lights, u.region, no);
        if (!needs) return fail(needs.error());
        BakeNeed bn;
        bn.region = u.region.text, bn.width = no.width, bn.height = no.height, bn.minRes = no.minRes;
        bn.maxRes = cap, bn.samples = uint32_t(u.region.cameras.size()), bn.lights = needs.value();
        for (StaticMethod method : o.methods) {
            auto row = compareMethod(u, method, cap, bn, csv);
            if (!row) return fail(row.error());
            classRows.push_back(std::move(row.value()));
        }
    }
    return csv.str();
}

// Every disagreement by cause (first match wins, as bench static), fixed / need-based.
void printClassRows(const std::vector<ClassRow>& classRows) {
    std::printf("\nDisagreements by cause, %% of pairs, fixed / need-based:\n| method | cap |");
    for (uint32_t c = 0; c < kErrorClassCount; ++c) std::printf(" %s |", errorClassName(ErrorClass(c)));
    std::printf("\n|---|---:|");
    for (uint32_t c = 0; c < kErrorClassCount; ++c) std::printf("---:|");
    std::printf("\n");
    for (const auto& [method, cap, a, b] : classRows) {
        std::printf("| %s | %u |", method.c_str(), cap);
        for (uint32_t c = 0; c < kErrorClassCount; ++c)
            std::printf(" %.4f / %.4f |", 100.0 * double(a.classes[c]) / double(a.compared),
                        100.0 * double(b.classes[c]) / double(b.compared));
        std::printf("\n");
    }
}
} // namespace

// The flags of `bench static --need` beside its option groups.
const cli::Flags kNeedBenchFlags{{"--need", "--views", "--size", "--res", "--methods", "--lights",
                                  "--scene-lights", "--renderer", "--out"},
                                 {}};

int runBenchStaticNeed(int argc, char** argv) {
    int status = 0;
    const auto args = commandArgs(
        "bench static", kNeedHelp,
        cli::parse(argc, argv, 3, {opts::kSceneFlags, opts::kNeedFlags, kNeedBenchFlags}), status);
    if (!args) return status;
    auto parsed = parseNeedBench(*args);
    if (!parsed) return usageError("bench static", parsed.error());
    const NeedBench& o = parsed.value();
    if (auto r = cli::checkOutputDirectory("--out", o.out); !r) return usageError("bench static", r.error());
    auto rendering = makeRendering(o.renderer);
    if (!rendering) return runError("bench static", rendering.error());
    const SceneSpec spec{o.scene.name, o.sceneLights, o.scene.seed};
    auto scene = loadBakeScene(spec);
    if (!scene) return inputError("bench static", scene.error());
    auto rays = RayReference::build(scene.value(), true);
    if (!rays) return runError("bench static", rays.error());
    auto region = makeNeedRegion(scene.value(), o.region, o.need.samples, double(o.need.seconds),
                                 o.need.width, o.need.height);
    if (!region) return usageError("bench static", region.error());
    const auto views = viewReceivers(o, region.value(), rays.value());
    NeedSetup u{o,
                spec,
                scene.value(),
                rays.value(),
                region.value(),
                rankLights(scene.value(), views, o.maxLights),
                {},
                0,
                rendering->render};
    if (u.lights.empty()) return runError("bench static", "no static spot light reaches the views");
    u.sets = pairSets(scene.value(), rays.value(), views, u.lights);
    for (const PairSet& s : u.sets) u.pairs += s.receivers.size();
    const uint32_t V = uint32_t(views.size());
    std::fprintf(stderr, "bench static --need: %s, %u views of %s, %zu lights, %zu (pixel, light) pairs\n",
                 scene->name.c_str(), V, region->text.c_str(), u.lights.size(), u.pairs);
    std::printf(
        "bench static --need: %s; views: %u of the %zu samples of %s at %ux%u, exact receivers; need for "
        "%ux%u, minimum %u; %zu lights, %zu (pixel, light) pairs\n",
        scene->name.c_str(), V, region->views.size(), region->text.c_str(), o.width, o.height, o.need.width,
        o.need.height, o.need.minRes, u.lights.size(), u.pairs);
    std::printf(
        "| method | cap | fixed bytes | need bytes | need / fixed | fixed wrong %% | need wrong %% | fixed "
        "resolution %% | need resolution %% | need-based resolutions (lights) |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    std::vector<ClassRow> classRows;
    auto csv = compareCaps(u, classRows);
    if (!csv) return runError("bench static", csv.error());
    printClassRows(classRows);
    if (auto w = io::writeFileAtomically(o.out + "/bench_need.csv", csv.value()); !w)
        return runError("bench static", w.error());
    std::printf("wrote %s/bench_need.csv\n", o.out.c_str());
    if (validationErrors())
        return runError("bench static", std::to_string(validationErrors()) + " Vulkan validation errors");
    return 0;
}

} // namespace ml
