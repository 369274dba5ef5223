// `manylights bench static --need REGION`: fixed against need-based resolution (issue 11, item 5).
// Views along a camera path (evenly spaced samples of the region's path); every pixel's receiver is the
// static surface its centre ray hits (Embree, double precision: exact receivers, as bench static and
// bench flicker). The static spot lights that reach some receiver are baked twice per cap R and method:
// every light at R (fixed), and each light at its need-based resolution capped at R (bake --need). Both
// are measured on the same (pixel, light) pairs against the rays: total bytes, wrong % (one tap) and the
// resolution-class share (bake/reference/error_classes.h). Table on stdout, CSV in --out.
#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/gpu_dual_renderer.h"
#include "apps/need_region.h"
#include "gpu/device_types.h"
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

} // namespace

int runBenchStaticNeed(int argc, char** argv) {
    auto args = cli::parse(argc, argv, 3,
                           {"--need", "--need-samples", "--need-seconds", "--need-size", "--need-min",
                            "--views", "--size", "--res", "--methods", "--lights", "--scene",
                            "--scene-lights", "--seed", "--renderer", "--out"},
                           {});
    if (!args) return usageError("bench static", args.error());
    if (args->help) {
        std::fputs(kNeedHelp, stdout);
        return 0;
    }
    auto samples = cli::parseUint("--need-samples", args->get("--need-samples", "120"), 1, 100000);
    auto secondsArg = cli::parseUint("--need-seconds", args->get("--need-seconds", "60"), 1, 86400);
    auto needSize = cli::parseSize("--need-size", args->get("--need-size", args->get("--size", "640x360")));
    auto needMin = cli::parseUint("--need-min", args->get("--need-min", "64"), 1, kBakeMaxResolution);
    auto views = cli::parseUint("--views", args->get("--views", "8"), 1, 1000);
    auto size = cli::parseSize("--size", args->get("--size", "640x360"));
    auto maxLights = cli::parseUint("--lights", args->get("--lights", "64"), 1, 4096);
    auto sceneLights = cli::parseUint("--scene-lights", args->get("--scene-lights", "256"), 1, 4096);
    auto seed = cli::parseUint("--seed", args->get("--seed", "1"), 0, 0xFFFFFFFFu);
    for (const std::string* e :
         {&samples.error(), &secondsArg.error(), &needSize.error(), &needMin.error(), &views.error(),
          &size.error(), &maxLights.error(), &sceneLights.error(), &seed.error()})
        if (!e->empty()) return usageError("bench static", *e);
    if ((needMin.value() & (needMin.value() - 1)) != 0)
        return usageError("bench static", "--need-min: not a power of two");
    std::vector<uint32_t> caps;
    {
        std::stringstream ss(args->get("--res", "512,1024,2048"));
        std::string item;
        while (std::getline(ss, item, ',')) {
            auto r = cli::parseUint("--res", item, needMin.value(), kBakeMaxResolution);
            if (!r) return usageError("bench static", r.error());
            caps.push_back(r.value());
        }
    }
    std::vector<StaticMethod> methods;
    {
        std::stringstream ss(args->get("--methods", "dagmh"));
        std::string item;
        while (std::getline(ss, item, ',')) {
            auto m = parseStaticMethod(item);
            if (!m || m.value() == StaticMethod::None)
                return usageError("bench static", "--methods: " + (m ? std::string("none") : m.error()));
            methods.push_back(m.value());
        }
    }
    if (caps.empty() || methods.empty()) return usageError("bench static", "--res and --methods: empty list");
    for (StaticMethod m : methods)
        for (uint32_t r : caps)
            if (m == StaticMethod::CPVS)
                if (auto s = makeCpvsSpace(r, 1.0f, 2.0f); !s)
                    return usageError("bench static", "--res: " + s.error());
    const std::string regionSpec = args->get("--need", "");
    if (regionSpec.rfind("path:", 0) != 0)
        return usageError("bench static",
                          "--need: '" + regionSpec + "': the comparison needs a path (its views)");
    const std::string out = args->get("--out", "out/bench_need");
    if (auto r = cli::makeDirectory(out); !r) return runError("bench static", r.error());
    const std::string rendererName = args->get("--renderer", "gpu");
    if (rendererName != "gpu" && rendererName != "cpu")
        return usageError("bench static", "--renderer: '" + rendererName + "' is not gpu or cpu");
    GpuRendererFn gpu;
    DualRenderFn render = cpuDualRenderer();
    if (rendererName == "gpu") {
        auto fn = gpu.make();
        if (!fn) return runError("bench static", fn.error());
        render = fn.value();
    }

    const SceneSpec spec{args->get("--scene", "night-city"), sceneLights.value(), seed.value()};
    auto scene = loadBakeScene(spec);
    if (!scene) return usageError("bench static", scene.error());
    auto rays = RayReference::build(scene.value(), true);
    if (!rays) return runError("bench static", rays.error());
    const auto [needW, needH] = needSize.value();
    auto region =
        makeNeedRegion(scene.value(), regionSpec, samples.value(), double(secondsArg.value()), needW, needH);
    if (!region) return usageError("bench static", region.error());

    // Exact receivers of the measured views.
    const auto [width, height] = size.value();
    const uint32_t V = std::min<uint32_t>(views.value(), uint32_t(region->views.size()));
    std::vector<std::vector<Receiver>> viewReceivers(V);
    std::vector<uint32_t> viewSample(V);
    for (uint32_t v = 0; v < V; ++v) {
        viewSample[v] = uint32_t(uint64_t(v) * region->views.size() / V);
        const Camera& cam = region->views[viewSample[v]];
        const glm::dvec3 eye(cam.position);
        glm::dmat4 view = glm::lookAt(eye, glm::dvec3(cam.target), glm::dvec3(0, 1, 0));
        glm::dmat4 proj = glm::perspective(double(cam.fovY), double(width) / height, double(cam.nearPlane),
                                           double(cam.farPlane));
        glm::dmat4 inv = glm::inverse(proj * view);
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x) {
                double nx = (x + 0.5) / width * 2.0 - 1.0, ny = 1.0 - (y + 0.5) / height * 2.0;
                glm::dvec4 a = inv * glm::dvec4(nx, ny, 0.0, 1.0), b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
                glm::dvec3 dir = glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w);
                RayHit h = rays->firstHit(glm::vec3(eye), glm::vec3(dir), 0.0f, cam.farPlane);
                if (!h.hit) continue;
                glm::vec3 n = glm::normalize(h.ng);
                if (glm::dot(n, glm::vec3(dir)) > 0.0f) n = -n;
                viewReceivers[v].push_back({glm::vec3(eye + dir * double(h.t)), n});
            }
    }

    // Lights: static spots reaching the most receivers over all views.
    std::vector<std::pair<size_t, uint32_t>> ranked;
    for (uint32_t i = 0; i < scene->lights.size(); ++i) {
        const Light& l = scene->lights[i];
        if (l.type != LightKind::Spot || !bakeSkipReason(scene.value(), l).empty()) continue;
        size_t n = 0;
        for (const auto& rs : viewReceivers)
            for (const Receiver& r : rs) n += inLightCone(l, r.p) && glm::dot(r.n, l.position - r.p) > 0.0f;
        if (n) ranked.push_back({n, i});
    }
    std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    if (ranked.size() > maxLights.value()) ranked.resize(maxLights.value());
    if (ranked.empty()) return runError("bench static", "no static spot light reaches the views");
    std::vector<uint32_t> lights;
    for (auto [n, i] : ranked) lights.push_back(i);
    std::sort(lights.begin(), lights.end());
    std::vector<PairSet> sets;
    for (uint32_t v = 0; v < V; ++v)
        for (uint32_t li : lights) {
            const Light& l = scene->lights[li];
            PairSet s;
            s.light = li;
            std::vector<glm::vec3> ps, ns;
            for (const Receiver& r : viewReceivers[v])
                if (inLightCone(l, r.p) && glm::dot(r.n, l.position - r.p) > 0.0f) {
                    s.receivers.push_back(r);
                    ps.push_back(r.p), ns.push_back(r.n);
                }
            if (s.receivers.empty()) continue;
            s.truth.resize(ps.size());
            rays->visibleBatch(ps.data(), ns.data(), ps.size(), l.position, kNeedRayBias, s.truth.data());
            sets.push_back(std::move(s));
        }
    size_t pairs = 0;
    for (const PairSet& s : sets) pairs += s.receivers.size();
    std::fprintf(stderr, "bench static --need: %s, %u views of %s, %zu lights, %zu (pixel, light) pairs\n",
                 scene->name.c_str(), V, region->text.c_str(), lights.size(), pairs);

    std::printf(
        "bench static --need: %s; views: %u of the %zu samples of %s at %ux%u, exact receivers; need for "
        "%ux%u, minimum %u; %zu lights, %zu (pixel, light) pairs\n",
        scene->name.c_str(), V, region->views.size(), region->text.c_str(), width, height, needW, needH,
        needMin.value(), lights.size(), pairs);
    std::printf(
        "| method | cap | fixed bytes | need bytes | need / fixed | fixed wrong %% | need wrong %% | fixed "
        "resolution %% | need resolution %% | need-based resolutions (lights) |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    std::ostringstream csv;
    csv << "method,cap,lights,pairs,fixed_bytes,need_bytes,fixed_wrong,need_wrong,fixed_resolution_class,"
           "need_resolution_class,need_resolutions";
    for (const char* which : {"fixed", "need"})
        for (uint32_t c = 0; c < kErrorClassCount; ++c)
            csv << "," << which << "_" << errorClassName(ErrorClass(c));
    csv << "\n";
    std::vector<std::tuple<std::string, uint32_t, Measure, Measure>> classRows;
    for (uint32_t cap : caps) {
        NeedOptions o;
        o.width = needW, o.height = needH, o.minRes = needMin.value(), o.maxRes = cap;
        auto needs = estimateNeedWithRays(scene.value(), lights, region.value(), o);
        if (!needs) return runError("bench static", needs.error());
        BakeNeed bn;
        bn.region = region->text, bn.width = needW, bn.height = needH, bn.minRes = o.minRes, bn.maxRes = cap;
        bn.samples = uint32_t(region->cameras.size());
        bn.lights = needs.value();
        for (StaticMethod method : methods) {
            auto t0 = std::chrono::steady_clock::now();
            auto fixed = bakeScene(scene.value(), spec, method, cap, lights, {}, render);
            if (!fixed) return runError("bench static", fixed.error());
            auto byNeed = bakeSceneNeed(scene.value(), spec, method, bn, lights, {}, render);
            if (!byNeed) return runError("bench static", byNeed.error());
            const Measure a = measure(fixed->file, sets, rays.value(), scene.value());
            const Measure b = measure(byNeed->file, sets, rays.value(), scene.value());
            auto pct = [](uint64_t n, uint64_t d) { return d ? 100.0 * double(n) / double(d) : 0.0; };
            std::printf("| %s | %u | %llu | %llu | %.2f | %.4f | %.4f | %.4f | %.4f | %s |\n",
                        staticMethodName(method), cap, (unsigned long long)a.bytes,
                        (unsigned long long)b.bytes, double(b.bytes) / double(a.bytes),
                        pct(a.wrong, a.compared), pct(b.wrong, b.compared),
                        pct(a.resolutionClass, a.compared), pct(b.resolutionClass, b.compared),
                        histogram(b.resolutions).c_str());
            std::fflush(stdout);
            csv << staticMethodName(method) << "," << cap << "," << lights.size() << "," << pairs << ","
                << a.bytes << "," << b.bytes << "," << double(a.wrong) / double(a.compared) << ","
                << double(b.wrong) / double(b.compared) << ","
                << double(a.resolutionClass) / double(a.compared) << ","
                << double(b.resolutionClass) / double(b.compared) << ",\"" << histogram(b.resolutions)
                << "\"";
            for (const Measure* x : {&a, &b})
                for (uint32_t c = 0; c < kErrorClassCount; ++c)
                    csv << "," << double(x->classes[c]) / double(x->compared);
            csv << "\n";
            classRows.push_back({staticMethodName(method), cap, a, b});
            std::fprintf(stderr, "  %s cap %u: %.1f s\n", staticMethodName(method), cap,
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
    }
    // Every disagreement by cause (first match wins, as bench static), fixed / need-based.
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
    if (auto w = io::writeFileAtomically(out + "/bench_need.csv", csv.str()); !w)
        return runError("bench static", w.error());
    std::printf("wrote %s/bench_need.csv\n", out.c_str());
    if (validationErrors())
        return runError("bench static", std::to_string(validationErrors()) + " Vulkan validation errors");
    return 0;
}

} // namespace ml
