// `manylights bench flicker`: temporal stability of the static shadow methods along a camera path
// (issue 11, item 6). For each frame of a straight camera path, every pixel's receiver is the surface
// its camera ray hits (Embree, double-precision pixel rays: the same exact receivers as bench static);
// for each measured static spot light, the method's visibility (the CPU twin of the shader's lookup,
// one tap or PCF) and the rays' visibility are computed per pixel. A pixel "flickers" between two
// consecutive frames when the method's binary answer (visibility >= 0.5) changes while the rays' does
// not. The share is over (pixel, light) pairs that count (in the cone, facing the light) in both frames.
// Static lights only: the bakes do not move; moving lights and virtual shadow maps are not covered.
// CPU only (the maps come from the CPU rasteriser, identical to what the bake renders).
#include "apps/cli.h"
#include "apps/commands.h"
#include "scenes/scenes.h"
#include "shadows/reference/raytrace.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ml {

static const char* kFlickerHelp = R"(usage: manylights bench flicker [options]
Share of pixels whose static shadow flips between consecutive frames of a camera path while the
ray-traced visibility does not, per method, resolution and PCF size. Table on stdout, CSV in --out.
  --scene S        night-city (default) or a .gltf / .glb file
  --methods LIST   comma-separated, default sm,mh,mmh,dagmh,cpvs
  --res LIST       comma-separated resolutions, default 1024,2048
  --pcf LIST       PCF radii (0 = one tap .. 4 = 9x9), default 0,2
  --lights N       static spot lights measured (those reaching the most pixels of frame 0), default 8
  --size WxH       frame size, default 320x180
  --frames N       frames along the path (>= 2), default 16
  --camera X,Y,Z,TX,TY,TZ      path start (default: the scene's camera)
  --camera-end X,Y,Z,TX,TY,TZ  path end (default: the start moved 2 m sideways)
  --seed S         scene seed, default 1
  --out DIR        bench_flicker.csv (default out/bench_flicker)
)";

namespace {
Result<std::vector<uint32_t>> uintList(const std::string& flag, const std::string& text, uint32_t lo,
                                       uint32_t hi) {
    std::vector<uint32_t> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        auto v = cli::parseUint(flag, item, lo, hi);
        if (!v) return fail(v.error());
        out.push_back(v.value());
    }
    if (out.empty()) return fail(flag + ": empty list");
    return out;
}

struct Sample {
    bool counts = false; // in the cone and facing the light
    bool truth = false;
    std::vector<float> vis; // per (method, res, pcf) configuration
};
} // namespace

int runBenchFlicker(int argc, char** argv) {
    auto args = cli::parse(argc, argv, 3,
                           {"--scene", "--methods", "--res", "--pcf", "--lights", "--size", "--frames",
                            "--camera", "--camera-end", "--seed", "--out"},
                           {});
    if (!args) return usageError("bench flicker", args.error());
    if (args->help) {
        std::fputs(kFlickerHelp, stdout);
        return 0;
    }
    auto resList = uintList("--res", args->get("--res", "1024,2048"), 16, 16384);
    auto pcfList = uintList("--pcf", args->get("--pcf", "0,2"), 0, ML_MAX_PCF_RADIUS);
    auto count = cli::parseUint("--lights", args->get("--lights", "8"), 1, 4096);
    auto size = cli::parseSize("--size", args->get("--size", "320x180"));
    auto frames = cli::parseUint("--frames", args->get("--frames", "16"), 2, 1000);
    auto seed = cli::parseUint("--seed", args->get("--seed", "1"), 0, 0xFFFFFFFFu);
    for (const std::string* e :
         {&resList.error(), &pcfList.error(), &count.error(), &size.error(), &frames.error(), &seed.error()})
        if (!e->empty()) return usageError("bench flicker", *e);
    std::vector<StaticMethod> methods;
    {
        std::stringstream ss(args->get("--methods", "sm,mh,mmh,dagmh,cpvs"));
        std::string item;
        while (std::getline(ss, item, ',')) {
            auto m = parseStaticMethod(item);
            if (!m || m.value() == StaticMethod::None)
                return usageError("bench flicker", m ? "method none" : m.error());
            methods.push_back(m.value());
        }
    }
    const std::string sceneName = args->get("--scene", "night-city");
    auto scene = loadScene(sceneName, sceneName == "night-city" ? 256 : 32, seed.value());
    if (!scene) return runError("bench flicker", scene.error());
    glm::vec3 eye0 = scene->camera.position, target0 = scene->camera.target;
    if (args->has("--camera")) {
        auto v = cli::parseCamera("--camera", args->get("--camera", ""));
        if (!v) return usageError("bench flicker", v.error());
        eye0 = {v.value()[0], v.value()[1], v.value()[2]},
        target0 = {v.value()[3], v.value()[4], v.value()[5]};
    }
    glm::vec3 side = glm::normalize(glm::cross(target0 - eye0, glm::vec3(0, 1, 0)));
    glm::vec3 eye1 = eye0 + side * 2.0f, target1 = target0 + side * 2.0f;
    if (args->has("--camera-end")) {
        auto v = cli::parseCamera("--camera-end", args->get("--camera-end", ""));
        if (!v) return usageError("bench flicker", v.error());
        eye1 = {v.value()[0], v.value()[1], v.value()[2]},
        target1 = {v.value()[3], v.value()[4], v.value()[5]};
    }
    const std::string out = args->get("--out", "out/bench_flicker");
    if (auto r = cli::makeDirectory(out); !r) return runError("bench flicker", r.error());
    auto rays = RayReference::build(scene.value(), true);
    if (!rays) return runError("bench flicker", rays.error());
    const auto [width, height] = size.value();
    const uint32_t F = frames.value();

    // Exact receivers of frame f: the static surface each pixel's centre ray hits (position, normal
    // facing the camera); pixels that see nothing get a zero normal.
    auto receiversOf = [&](uint32_t f, std::vector<glm::vec3>& ps, std::vector<glm::vec3>& ns) {
        float t = F > 1 ? float(f) / float(F - 1) : 0.0f;
        glm::dvec3 eye = glm::dvec3(glm::mix(eye0, eye1, t)),
                   target = glm::dvec3(glm::mix(target0, target1, t));
        glm::dmat4 view = glm::lookAt(eye, target, glm::dvec3(0, 1, 0));
        glm::dmat4 proj = glm::perspective(double(scene->camera.fovY), double(width) / height, 0.1, 1000.0);
        glm::dmat4 inv = glm::inverse(proj * view);
        ps.assign(size_t(width) * height, glm::vec3(0.0f));
        ns.assign(ps.size(), glm::vec3(0.0f));
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x) {
                double nx = (x + 0.5) / width * 2.0 - 1.0, ny = 1.0 - (y + 0.5) / height * 2.0;
                glm::dvec4 a = inv * glm::dvec4(nx, ny, 0.0, 1.0), b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
                glm::dvec3 dir = glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w);
                RayHit h = rays->firstHit(glm::vec3(eye), glm::vec3(dir), 0.0f, 1e4f);
                if (!h.hit) continue;
                size_t i = size_t(y) * width + x;
                ps[i] = glm::vec3(eye + dir * double(h.t));
                glm::vec3 n = glm::normalize(h.ng);
                ns[i] = glm::dot(n, glm::vec3(dir)) > 0.0f ? -n : n;
            }
    };

    // Lights: static spots reaching the most pixels of frame 0.
    std::vector<glm::vec3> ps, ns;
    receiversOf(0, ps, ns);
    std::vector<std::pair<size_t, uint32_t>> ranked;
    for (uint32_t i = 0; i < scene->lights.size(); ++i) {
        const Light& l = scene->lights[i];
        if (l.dynamic || l.type != LightType::Spot) continue;
        size_t n = 0;
        for (size_t k = 0; k < ps.size(); ++k) n += ns[k] != glm::vec3(0.0f) && inLightCone(l, ps[k]);
        if (n) ranked.push_back({n, i});
    }
    std::sort(ranked.rbegin(), ranked.rend());
    if (ranked.size() > count.value()) ranked.resize(count.value());
    if (ranked.empty())
        return runError("bench flicker", sceneName + ": no static spot light reaches the view");

    // Bakes: per light, per resolution, per method.
    struct Config {
        StaticMethod method;
        uint32_t res, pcf;
    };
    std::vector<Config> configs;
    for (uint32_t res : resList.value())
        for (StaticMethod m : methods)
            for (uint32_t r : pcfList.value()) configs.push_back({m, res, r});
    const CasterTriangles casters = castersFromScene(scene.value());
    // words[light][res index][method index]
    std::vector<std::vector<std::vector<std::vector<uint32_t>>>> words(ranked.size());
    for (size_t k = 0; k < ranked.size(); ++k) {
        LightFrustum fr = spotLightFrustum(scene->lights[ranked[k].second]);
        for (uint32_t res : resList.value()) {
            DualDepthMap map = rasterizeDual(casters, fr, res);
            std::vector<std::vector<uint32_t>> perMethod;
            for (StaticMethod m : methods) {
                auto w = encodeStatic(m, map, {fr.nearPlane, fr.farPlane, {}});
                if (!w) return runError("bench flicker", std::string(staticMethodName(m)) + ": " + w.error());
                perMethod.push_back(std::move(w.value()));
            }
            words[k].push_back(std::move(perMethod));
        }
    }
    std::fprintf(stderr, "bench flicker: %s, %zu lights, %u frames %ux%u, %zu configurations\n",
                 scene->name.c_str(), ranked.size(), F, width, height, configs.size());

    std::vector<uint64_t> pairs(configs.size(), 0), flips(configs.size(), 0), truthFlips(configs.size(), 0);
    std::vector<Sample> prev, cur;
    for (uint32_t f = 0; f < F; ++f) {
        if (f) receiversOf(f, ps, ns);
        cur.assign(ps.size() * ranked.size(), {});
        for (size_t k = 0; k < ranked.size(); ++k) {
            const Light& l = scene->lights[ranked[k].second];
            LightFrustum fr = spotLightFrustum(l);
            std::vector<glm::vec3> qp, qn;
            std::vector<size_t> idx;
            for (size_t i = 0; i < ps.size(); ++i)
                if (ns[i] != glm::vec3(0.0f) && inLightCone(l, ps[i]) &&
                    glm::dot(ns[i], l.position - ps[i]) > 0.0f)
                    qp.push_back(ps[i]), qn.push_back(ns[i]), idx.push_back(i);
            std::vector<uint8_t> truth(qp.size());
            rays->visibleBatch(qp.data(), qn.data(), qp.size(), l.position, 0.02f, truth.data());
            for (size_t j = 0; j < idx.size(); ++j) {
                Sample& s = cur[idx[j] * ranked.size() + k];
                s.counts = true;
                s.truth = truth[j] != 0;
                for (const Config& c : configs) {
                    size_t ri = size_t(std::find(resList->begin(), resList->end(), c.res) - resList->begin());
                    size_t mi = size_t(std::find(methods.begin(), methods.end(), c.method) - methods.begin());
                    auto rec = makeShadowRecord(c.method, fr, 0, c.res, c.pcf);
                    s.vis.push_back(staticVisibility(rec, words[k][ri][mi].data(), qp[j], qn[j]));
                }
            }
        }
        if (f)
            for (size_t i = 0; i < cur.size(); ++i) {
                const Sample &a = prev[i], &b = cur[i];
                if (!a.counts || !b.counts) continue;
                for (size_t c = 0; c < configs.size(); ++c) {
                    ++pairs[c];
                    if (a.truth != b.truth) {
                        ++truthFlips[c];
                        continue;
                    }
                    flips[c] += (a.vis[c] >= 0.5f) != (b.vis[c] >= 0.5f);
                }
            }
        std::swap(prev, cur);
    }

    std::printf("bench flicker: %s, %zu lights, %u frames %ux%u from %.1f,%.1f,%.1f to %.1f,%.1f,%.1f\n",
                scene->name.c_str(), ranked.size(), F, width, height, eye0.x, eye0.y, eye0.z, eye1.x, eye1.y,
                eye1.z);
    std::printf(
        "| method | res | pcf | pixel-light pairs in consecutive frames | rays flip %% | method flips "
        "where rays do not %% |\n|---|---:|---|---:|---:|---:|\n");
    std::ostringstream csv;
    csv << "method,res,pcf_radius,pairs,truth_flips,flicker\n";
    for (size_t c = 0; c < configs.size(); ++c) {
        const Config& g = configs[c];
        double rate = pairs[c] ? double(flips[c]) / double(pairs[c]) : 0.0;
        std::printf("| %s | %u | %ux%u | %llu | %.3f | %.4f |\n", staticMethodName(g.method), g.res,
                    2 * g.pcf + 1, 2 * g.pcf + 1, (unsigned long long)pairs[c],
                    pairs[c] ? 100.0 * double(truthFlips[c]) / double(pairs[c]) : 0.0, 100.0 * rate);
        csv << staticMethodName(g.method) << "," << g.res << "," << g.pcf << "," << pairs[c] << ","
            << truthFlips[c] << "," << flips[c] << "\n";
    }
    std::ofstream file(out + "/bench_flicker.csv");
    if (!file || !(file << csv.str()))
        return runError("bench flicker", out + "/bench_flicker.csv: cannot write");
    std::printf("wrote %s/bench_flicker.csv\n", out.c_str());
    return 0;
}

} // namespace ml
