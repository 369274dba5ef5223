// `manylights bench flicker`: temporal stability of the static shadow methods along a camera path and
// with moving lights (issue 11, item 6). For each frame of a straight camera path, every pixel's receiver
// is the surface its camera ray hits (Embree, double-precision pixel rays: the same exact receivers as
// bench static); for each measured spot light, the method's visibility (the CPU twin of the shader's
// lookup, one tap or PCF) and the rays' visibility are computed per pixel. A pixel "flickers" between two
// consecutive frames when the method's binary answer (visibility >= 0.5) changes while the rays' does
// not. The share is over (pixel, light) pairs that count (in the cone, facing the light) in both frames.
// The graded measure is the mean |change of visibility| over the pairs whose rays do not flip: PCF
// changes below the 0.5 threshold show there.
// Moving lights (--light-move, --light-turn): each measured light is translated sideways and/or turned
// a little every frame, and every method's map is re-rendered and re-encoded for the light's pose of
// that frame (what a user baking per frame would get). --map-jitter renders the maps from a light
// position jittered every frame while the rays use the true one: a deliberately unstable map, for the
// test that the measure sees instability. --vsm hands over to bench_flicker_vsm.cpp (the module's
// virtual shadow maps on a GPU path). CPU only here (the maps come from the CPU rasteriser, identical
// to what the bake renders).
#include "apps/cli.h"
#include "bake/scene_casters.h"
#include "apps/commands.h"
#include "scenes/scenes.h"
#include "bake/reference/raytrace.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ml {

int runBenchFlickerVsm(int argc, char** argv); // apps/bench_flicker_vsm.cpp

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
  --light-move M   metres each measured light moves sideways per frame (default 0: static lights)
  --light-turn D   degrees each measured light turns about the vertical per frame (default 0)
  --map-jitter M   render each frame's maps from the light moved M metres in a pseudo-random direction
                   (the rays keep the true light): a deliberately unstable map (default 0)
  --seed S         scene seed, default 1
  --out DIR        bench_flicker.csv (default out/bench_flicker)
Last stdout line: {"pairs": N, "truth_flips": T, "flips": F, "graded": G} summed over configurations
(G: the largest mean |delta visibility| of a configuration where the rays do not flip).
With --vsm (first option): the module's virtual shadow maps on a GPU path; `bench flicker --vsm --help`.
)";

namespace {
// A number in [lo, hi]: the whole text must parse (strtod), nan and inf are refused.
Result<float> floatArg(const std::string& flag, const std::string& text, float lo, float hi) {
    char* end = nullptr;
    const double d = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(d) || d < lo || d > hi)
        return fail(flag + ": '" + text + "' is not a number in [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]");
    return float(d);
}

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

// The light's pose in frame f: moved `move` metres per frame along its horizontal side axis and turned
// `turnDeg` degrees per frame about the vertical.
Light posed(const Light& base, uint32_t f, float move, float turnDeg) {
    Light l = base;
    glm::vec3 side = glm::cross(l.direction, glm::vec3(0, 1, 0));
    side = glm::length(side) > 1e-4f ? glm::normalize(side) : glm::vec3(1, 0, 0);
    l.position += side * (move * float(f));
    if (turnDeg == 0.0f || f == 0) return l; // static lights stay bit-identical to the scene's
    float a = glm::radians(turnDeg * float(f)), c = std::cos(a), s = std::sin(a);
    l.direction = glm::normalize(glm::vec3(c * l.direction.x + s * l.direction.z, l.direction.y,
                                           -s * l.direction.x + c * l.direction.z));
    return l;
}

// A unit vector that changes every frame and light (deterministic): the map jitter's direction.
glm::vec3 jitterDirection(uint32_t f, uint32_t light) {
    uint32_t h = f * 0x9E3779B9u ^ (light + 1) * 0x85EBCA6Bu;
    glm::vec3 v;
    for (int i = 0; i < 3; ++i) {
        h ^= h >> 16, h *= 0x7FEB352Du, h ^= h >> 15, h *= 0x846CA68Bu, h ^= h >> 16;
        v[i] = float(h & 0xFFFF) / 32767.5f - 1.0f;
    }
    return glm::length(v) > 1e-3f ? glm::normalize(v) : glm::vec3(1, 0, 0);
}
} // namespace

int runBenchFlicker(int argc, char** argv) {
    if (argc > 3 && std::string(argv[3]) == "--vsm") return runBenchFlickerVsm(argc, argv);
    auto args =
        cli::parse(argc, argv, 3,
                   {"--scene", "--methods", "--res", "--pcf", "--lights", "--size", "--frames", "--camera",
                    "--camera-end", "--seed", "--out", "--light-move", "--light-turn", "--map-jitter"},
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
    auto move = floatArg("--light-move", args->get("--light-move", "0"), 0.0f, 10.0f);
    auto turn = floatArg("--light-turn", args->get("--light-turn", "0"), 0.0f, 45.0f);
    auto jitter = floatArg("--map-jitter", args->get("--map-jitter", "0"), 0.0f, 10.0f);
    for (const std::string* e :
         {&resList.error(), &pcfList.error(), &count.error(), &size.error(), &frames.error(), &seed.error(),
          &move.error(), &turn.error(), &jitter.error()})
        if (!e->empty()) return usageError("bench flicker", *e);
    const bool mapsMove = move.value() > 0.0f || turn.value() > 0.0f || jitter.value() > 0.0f;
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
        if (l.dynamic || l.type != LightKind::Spot) continue;
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
    // Per measured light: its pose this frame (the rays' light), the frustum its maps were rendered
    // with, and words[res index][method index]. Static lights bake once; moving or jittered ones every frame.
    struct LightMaps {
        Light light;
        LightFrustum frustum;
        std::vector<std::vector<std::vector<uint32_t>>> words;
    };
    std::vector<LightMaps> maps(ranked.size());
    auto bake = [&](size_t k, uint32_t f) -> Result<void> {
        const Light base = scene->lights[ranked[k].second];
        LightMaps& lm = maps[k];
        lm.light = posed(base, f, move.value(), turn.value());
        Light mapLight = lm.light;
        mapLight.position += jitterDirection(f, uint32_t(k)) * jitter.value();
        lm.frustum = spotLightFrustum(mapLight);
        lm.words.clear();
        for (uint32_t res : resList.value()) {
            DualDepthMap map = rasterizeDual(casters, lm.frustum, res);
            std::vector<std::vector<uint32_t>> perMethod;
            for (StaticMethod m : methods) {
                auto w = encodeStatic(m, map, {lm.frustum.nearPlane, lm.frustum.farPlane, {}});
                if (!w) return fail(std::string(staticMethodName(m)) + ": " + w.error());
                perMethod.push_back(std::move(w.value()));
            }
            lm.words.push_back(std::move(perMethod));
        }
        return {};
    };
    std::fprintf(stderr, "bench flicker: %s, %zu lights, %u frames %ux%u, %zu configurations%s\n",
                 scene->name.c_str(), ranked.size(), F, width, height, configs.size(),
                 mapsMove ? ", maps re-rendered every frame" : "");

    std::vector<uint64_t> pairs(configs.size(), 0), flips(configs.size(), 0), truthFlips(configs.size(), 0);
    std::vector<double> graded(configs.size(), 0.0); // sum of |delta visibility| where the rays do not flip
    std::vector<Sample> prev, cur;
    for (uint32_t f = 0; f < F; ++f) {
        if (f) receiversOf(f, ps, ns);
        for (size_t k = 0; k < ranked.size(); ++k)
            if (f == 0 || mapsMove)
                if (auto r = bake(k, f); !r) return runError("bench flicker", r.error());
        cur.assign(ps.size() * ranked.size(), {});
        for (size_t k = 0; k < ranked.size(); ++k) {
            const Light& l = maps[k].light;
            const LightFrustum& fr = maps[k].frustum;
            std::vector<glm::vec3> qp, qn;
            std::vector<size_t> idx;
            for (size_t i = 0; i < ps.size(); ++i)
                if (ns[i] != glm::vec3(0.0f) && inLightCone(l, ps[i]) &&
                    glm::dot(ns[i], l.position - ps[i]) > 0.0f)
                    qp.push_back(ps[i]), qn.push_back(ns[i]), idx.push_back(i);
            std::vector<uint8_t> truth(qp.size());
            rays->visibleBatch(qp.data(), qn.data(), qp.size(), l.position, 0.001f,
                               truth.data()); // 1 mm, as bench static (docs/accuracy.md section 1)
            for (size_t j = 0; j < idx.size(); ++j) {
                Sample& s = cur[idx[j] * ranked.size() + k];
                s.counts = true;
                s.truth = truth[j] != 0;
                for (const Config& c : configs) {
                    size_t ri = size_t(std::find(resList->begin(), resList->end(), c.res) - resList->begin());
                    size_t mi = size_t(std::find(methods.begin(), methods.end(), c.method) - methods.begin());
                    auto rec = makeShadowRecord(c.method, fr, 0, c.res, c.pcf);
                    s.vis.push_back(staticVisibility(rec, maps[k].words[ri][mi].data(), qp[j], qn[j]));
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
                    graded[c] += std::abs(double(a.vis[c]) - double(b.vis[c]));
                }
            }
        std::swap(prev, cur);
    }

    std::printf("bench flicker: %s, %zu lights, %u frames %ux%u from %.1f,%.1f,%.1f to %.1f,%.1f,%.1f\n",
                scene->name.c_str(), ranked.size(), F, width, height, eye0.x, eye0.y, eye0.z, eye1.x, eye1.y,
                eye1.z);
    if (mapsMove)
        std::printf(
            "lights move %.3f m and turn %.3f deg per frame, maps jittered by %.3f m; maps re-rendered "
            "every frame\n",
            move.value(), turn.value(), jitter.value());
    std::printf(
        "| method | res | pcf | pixel-light pairs in consecutive frames | rays flip %% | method flips "
        "where rays do not %% | mean abs delta visibility where rays do not flip %% |\n"
        "|---|---:|---|---:|---:|---:|---:|\n");
    std::ostringstream csv;
    csv << "method,res,pcf_radius,pairs,truth_flips,flicker,graded_sum\n";
    uint64_t allPairs = 0, allTruth = 0, allFlips = 0;
    double worstGraded = 0.0;
    for (size_t c = 0; c < configs.size(); ++c) {
        const Config& g = configs[c];
        double rate = pairs[c] ? double(flips[c]) / double(pairs[c]) : 0.0;
        const uint64_t stable = pairs[c] - truthFlips[c];
        const double meanDelta = stable ? graded[c] / double(stable) : 0.0;
        worstGraded = std::max(worstGraded, meanDelta);
        allPairs += pairs[c], allTruth += truthFlips[c], allFlips += flips[c];
        std::printf("| %s | %u | %ux%u | %llu | %.3f | %.4f | %.4f |\n", staticMethodName(g.method), g.res,
                    2 * g.pcf + 1, 2 * g.pcf + 1, (unsigned long long)pairs[c],
                    pairs[c] ? 100.0 * double(truthFlips[c]) / double(pairs[c]) : 0.0, 100.0 * rate,
                    100.0 * meanDelta);
        csv << staticMethodName(g.method) << "," << g.res << "," << g.pcf << "," << pairs[c] << ","
            << truthFlips[c] << "," << flips[c] << "," << graded[c] << "\n";
    }
    std::ofstream file(out + "/bench_flicker.csv");
    if (!file || !(file << csv.str()))
        return runError("bench flicker", out + "/bench_flicker.csv: cannot write");
    std::printf("wrote %s/bench_flicker.csv\n", out.c_str());
    std::printf("{\"pairs\": %llu, \"truth_flips\": %llu, \"flips\": %llu, \"graded\": %.6f}\n",
                (unsigned long long)allPairs, (unsigned long long)allTruth, (unsigned long long)allFlips,
                worstGraded);
    return 0;
}

} // namespace ml
