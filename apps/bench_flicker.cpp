// `manylights bench flicker`: temporal stability of the static shadow methods along a camera path and
// with moving lights. For each frame of a straight camera path, every pixel's receiver
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
#include "apps/commands.h"
#include "bake/scene_casters.h"
#include "apps/exact_receivers.h"
#include "apps/json.h"
#include "apps/options.h"
#include "scenes/scenes.h"
#include "bake/reference/raytrace.h"
#include "shadows/static/bake_file.h"
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
ray-traced visibility does not, per method, resolution and PCF size, and the share of samples whose
shadow (lit at visibility >= 0.5) is not the ray's. Table on stdout, CSV in --out.
  --scene S        night-city (default), night-city-closed or a .gltf / .glb file
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
  --bake A[,B...]  instead of baking: the stored records of one light (the first file's first record's
                   light, e.g. the moon at 4096^2 and at 65536^2), one row per file and PCF radius
  --by-level       MH, MMH, DAG-MH and CPVS also filtered by level (the coarsest hierarchy level whose
                   texel is at most a quarter of the pixel: Module::setShadowFilter's byLevel), one
                   more row each
  --map-jitter M   render each frame's maps from the light moved M metres in a pseudo-random direction
                   (the rays keep the true light): a deliberately unstable map (default 0)
  --seed S         scene seed, default 1
  --out DIR        bench_flicker.csv (default out/bench_flicker)
Last stdout line: {"pairs": N, "truth_flips": T, "flips": F, "graded": G} summed over configurations
(G: the largest mean |delta visibility| of a configuration where the rays do not flip).
With --vsm (first option): the module's virtual shadow maps on a GPU path; `bench flicker --vsm --help`.
)";

namespace {
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
struct Config {
    StaticMethod method;
    uint32_t res, pcf;
    bool byLevel = false; // filtering by level (MH, MMH, DAG-MH, CPVS; setShadowFilter)
};
// The methods whose lookups filter by level (static_visibility.glsl): the MH family's hierarchies and CPVS.
bool filtersByLevel(StaticMethod m) {
    return m == StaticMethod::MH || m == StaticMethod::MMH || m == StaticMethod::DAGMH ||
           m == StaticMethod::CPVS;
}

struct Options {
    std::vector<StaticMethod> methods;
    std::vector<uint32_t> res, pcf;
    bool byLevel = false;
    std::vector<std::string> bakes; // --bake: stored records instead of maps baked here
    uint32_t lights = 8;
    opts::View view;
    opts::Scene scene;
    float move = 0, turn = 0, jitter = 0;
    std::string out;
    bool mapsMove() const { return move > 0.0f || turn > 0.0f || jitter > 0.0f; }
};

Result<Options> parseOptions(const cli::Args& args) {
    Options o;
    auto res = opts::uintList("--res", args.get("--res", "1024,2048"), 16, 16384);
    auto pcf = opts::uintList("--pcf", args.get("--pcf", "0,2"), 0, ML_MAX_PCF_RADIUS);
    auto count = cli::parseUint("--lights", args.get("--lights", "8"), 1, 4096);
    auto view = opts::view(args, {16, 2, 1000, "320x180"});
    auto scene = opts::scene(args);
    auto move = opts::number("--light-move", args.get("--light-move", "0"), 0.0f, 10.0f);
    auto turn = opts::number("--light-turn", args.get("--light-turn", "0"), 0.0f, 45.0f);
    auto jitter = opts::number("--map-jitter", args.get("--map-jitter", "0"), 0.0f, 10.0f);
    auto methods = opts::methodList("--methods", args.get("--methods", "sm,mh,mmh,dagmh,cpvs"));
    for (const std::string* e : {&res.error(), &pcf.error(), &count.error(), &view.error(), &scene.error(),
                                 &move.error(), &turn.error(), &jitter.error(), &methods.error()})
        if (!e->empty()) return fail(*e);
    o.methods = methods.value(), o.res = res.value(), o.pcf = pcf.value(), o.lights = count.value();
    o.view = view.value(), o.scene = scene.value();
    o.move = move.value(), o.turn = turn.value(), o.jitter = jitter.value();
    o.out = args.get("--out", "out/bench_flicker");
    o.byLevel = args.has("--by-level");
    if (args.has("--bake")) {
        if (args.has("--methods") || args.has("--res") || args.has("--lights") || o.mapsMove())
            return fail("--bake: the records' methods, resolutions and light are the files'; drop --methods, "
                        "--res, --lights and the moving-light options");
        std::stringstream list(args.get("--bake", ""));
        for (std::string f; std::getline(list, f, ',');) o.bakes.push_back(f);
    }
    return o;
}

// The straight camera path: from the start to the end eye and target.
struct Path {
    glm::vec3 eye0, target0, eye1, target1;
};

Result<Path> parsePath(const cli::Args& args, const Scene& scene) {
    Path p{scene.camera.position, scene.camera.target, {}, {}};
    if (args.has("--camera")) {
        auto v = cli::parseCamera("--camera", args.get("--camera", ""));
        if (!v) return fail(v.error());
        p.eye0 = {v.value()[0], v.value()[1], v.value()[2]},
        p.target0 = {v.value()[3], v.value()[4], v.value()[5]};
    }
    glm::vec3 side = glm::normalize(glm::cross(p.target0 - p.eye0, glm::vec3(0, 1, 0)));
    p.eye1 = p.eye0 + side * 2.0f, p.target1 = p.target0 + side * 2.0f;
    if (args.has("--camera-end")) {
        auto v = cli::parseCamera("--camera-end", args.get("--camera-end", ""));
        if (!v) return fail(v.error());
        p.eye1 = {v.value()[0], v.value()[1], v.value()[2]},
        p.target1 = {v.value()[3], v.value()[4], v.value()[5]};
    }
    return p;
}

// Exact receivers of frame f: the static surface each pixel's centre ray hits (position, normal facing
// the camera, the pixel's squared footprint there as the module computes it: gpu::shadowFootprint2);
// pixels that see nothing get a zero normal.
void receiversOf(const Options& o, const Path& path, const Scene& scene, const RayReference& rays, uint32_t f,
                 std::vector<glm::vec3>& ps, std::vector<glm::vec3>& ns, std::vector<float>& f2) {
    const uint32_t width = o.view.width, height = o.view.height, F = o.view.frames;
    float t = F > 1 ? float(f) / float(F - 1) : 0.0f;
    glm::dvec3 eye = glm::dvec3(glm::mix(path.eye0, path.eye1, t)),
               target = glm::dvec3(glm::mix(path.target0, path.target1, t));
    glm::dmat4 view = glm::lookAt(eye, target, glm::dvec3(0, 1, 0));
    glm::dmat4 proj = glm::perspective(double(scene.camera.fovY), double(width) / height, 0.1, 1000.0);
    glm::dmat4 inv = glm::inverse(proj * view);
    ps.assign(size_t(width) * height, glm::vec3(0.0f));
    ns.assign(ps.size(), glm::vec3(0.0f));
    f2.assign(ps.size(), 0.0f);
    const float pixelAngle = 2.0f * std::tan(scene.camera.fovY * 0.5f) / float(height);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const glm::dvec3 dir = pixelRayDirection(inv, x, y, width, height, PixelConvention::Standard);
            const SurfaceHit h = traceSurface(rays, eye, dir, 1e4f);
            if (!h.hit) continue;
            const size_t i = size_t(y) * width + x;
            ps[i] = h.p, ns[i] = h.n;
            f2[i] = gpu::shadowFootprint2(glm::vec3(eye), ps[i], pixelAngle * pixelAngle);
        }
}

// Static spots reaching the most pixels of frame 0: their scene indices, at most `count`.
std::vector<uint32_t> rankLights(const Scene& scene, const std::vector<glm::vec3>& ps,
                                 const std::vector<glm::vec3>& ns, uint32_t count) {
    return firstLights(rankStaticSpots(scene,
                                       [&](const Light& l) {
                                           size_t n = 0;
                                           for (size_t k = 0; k < ps.size(); ++k)
                                               n += ns[k] != glm::vec3(0.0f) && inLightCone(l, ps[k]);
                                           return n;
                                       }),
                       count);
}

// A measured light in one frame: its pose (the rays' light), the frustum its maps were rendered with,
// and words[res index][method index]. Static lights bake once; moving or jittered ones every frame.
struct LightMaps {
    Light light;
    LightFrustum frustum;
    std::vector<std::vector<std::vector<uint32_t>>> words;
};

Result<void> bakeLight(const Options& o, const CasterTriangles& casters, const Light& base, uint32_t k,
                       uint32_t f, LightMaps& lm) {
    lm.light = posed(base, f, o.move, o.turn);
    Light mapLight = lm.light;
    mapLight.position += jitterDirection(f, k) * o.jitter;
    lm.frustum = spotLightFrustum(mapLight);
    lm.words.clear();
    for (uint32_t res : o.res) {
        DualDepthMap map = rasterizeDual(casters, lm.frustum, res);
        std::vector<std::vector<uint32_t>> perMethod;
        for (StaticMethod m : o.methods) {
            auto w = encodeStatic(m, map, {lm.frustum.nearPlane, lm.frustum.farPlane, {}});
            if (!w) return fail(std::string(staticMethodName(m)) + ": " + w.error());
            perMethod.push_back(std::move(w.value()));
        }
        lm.words.push_back(std::move(perMethod));
    }
    return {};
}

// The samples of one light's receivers (in the cone, facing it) in this frame, every configuration.
void sampleLight(const Options& o, const std::vector<Config>& configs, const RayReference& rays,
                 const LightMaps& lm, const std::vector<glm::vec3>& ps, const std::vector<glm::vec3>& ns,
                 const std::vector<float>& f2, size_t k, size_t lightCount, std::vector<Sample>& cur) {
    const Light& l = lm.light;
    std::vector<glm::vec3> qp, qn;
    std::vector<size_t> idx;
    std::vector<float> qf;
    for (size_t i = 0; i < ps.size(); ++i)
        if (ns[i] != glm::vec3(0.0f) && inLightCone(l, ps[i]) && glm::dot(ns[i], l.position - ps[i]) > 0.0f)
            qp.push_back(ps[i]), qn.push_back(ns[i]), qf.push_back(f2[i]), idx.push_back(i);
    std::vector<uint8_t> truth(qp.size());
    rays.visibleBatch(qp.data(), qn.data(), qp.size(), l.position, 0.001f,
                      truth.data()); // 1 mm, as bench static (docs/accuracy.md section 1)
    for (size_t j = 0; j < idx.size(); ++j) {
        Sample& s = cur[idx[j] * lightCount + k];
        s.counts = true;
        s.truth = truth[j] != 0;
        for (const Config& c : configs) {
            size_t ri = size_t(std::find(o.res.begin(), o.res.end(), c.res) - o.res.begin());
            size_t mi = size_t(std::find(o.methods.begin(), o.methods.end(), c.method) - o.methods.begin());
            auto rec = makeShadowRecord(c.method, lm.frustum, 0, c.res, c.pcf);
            rec.info.z = c.byLevel ? 1u : 0u;
            s.vis.push_back(staticVisibility(rec, lm.words[ri][mi].data(), qp[j], qn[j], qf[j]));
        }
    }
}

// Per configuration: pairs counted in consecutive frames, the rays' flips, the method's flips where the
// rays do not, and the sum of |delta visibility| there; and over every frame's samples, those whose
// visibility (lit when >= 0.5) is not the ray's.
struct Counts {
    explicit Counts(size_t n)
        : pairs(n, 0), flips(n, 0), truthFlips(n, 0), samples(n, 0), wrong(n, 0), graded(n, 0.0) {}
    std::vector<uint64_t> pairs, flips, truthFlips, samples, wrong;
    std::vector<double> graded;
};

void compareWithRays(const std::vector<Sample>& cur, Counts& n) {
    for (const Sample& a : cur) {
        if (!a.counts) continue;
        for (size_t c = 0; c < n.samples.size(); ++c) {
            ++n.samples[c];
            n.wrong[c] += (a.vis[c] >= 0.5f) != a.truth;
        }
    }
}

void comparePairs(const std::vector<Sample>& prev, const std::vector<Sample>& cur, Counts& n) {
    for (size_t i = 0; i < cur.size(); ++i) {
        const Sample &a = prev[i], &b = cur[i];
        if (!a.counts || !b.counts) continue;
        for (size_t c = 0; c < n.pairs.size(); ++c) {
            ++n.pairs[c];
            if (a.truth != b.truth) {
                ++n.truthFlips[c];
                continue;
            }
            n.flips[c] += (a.vis[c] >= 0.5f) != (b.vis[c] >= 0.5f);
            n.graded[c] += std::abs(double(a.vis[c]) - double(b.vis[c]));
        }
    }
}

// The table and CSV per configuration; the summary line's object.
Result<json::Object> report(const Options& o, const std::vector<Config>& configs, const Counts& n) {
    std::printf(
        "| method | res | filter | pixel-light pairs in consecutive frames | rays flip %% | method flips "
        "where rays do not %% | mean abs delta visibility where rays do not flip %% | wrong against rays %% "
        "|\n"
        "|---|---:|---|---:|---:|---:|---:|---:|\n");
    std::ostringstream csv;
    csv << "method,res,pcf_radius,by_level,pairs,truth_flips,flicker,graded_sum,samples,wrong\n";
    uint64_t allPairs = 0, allTruth = 0, allFlips = 0;
    double worstGraded = 0.0;
    for (size_t c = 0; c < configs.size(); ++c) {
        const Config& g = configs[c];
        const uint64_t pairs = n.pairs[c], stable = pairs - n.truthFlips[c];
        double rate = pairs ? double(n.flips[c]) / double(pairs) : 0.0;
        const double meanDelta = stable ? n.graded[c] / double(stable) : 0.0;
        worstGraded = std::max(worstGraded, meanDelta);
        allPairs += pairs, allTruth += n.truthFlips[c], allFlips += n.flips[c];
        std::printf("| %s | %u | %ux%u%s | %llu | %.3f | %.4f | %.4f | %.3f |\n", staticMethodName(g.method),
                    g.res, 2 * g.pcf + 1, 2 * g.pcf + 1, g.byLevel ? " by level" : "",
                    (unsigned long long)pairs, pairs ? 100.0 * double(n.truthFlips[c]) / double(pairs) : 0.0,
                    100.0 * rate, 100.0 * meanDelta,
                    n.samples[c] ? 100.0 * double(n.wrong[c]) / double(n.samples[c]) : 0.0);
        csv << staticMethodName(g.method) << "," << g.res << "," << g.pcf << "," << int(g.byLevel) << ","
            << pairs << "," << n.truthFlips[c] << "," << n.flips[c] << "," << n.graded[c] << ","
            << n.samples[c] << "," << n.wrong[c] << "\n";
    }
    std::ofstream file(o.out + "/bench_flicker.csv");
    if (!file || !(file << csv.str())) return fail(o.out + "/bench_flicker.csv: cannot write");
    std::printf("wrote %s/bench_flicker.csv\n", o.out.c_str());
    json::Object summary;
    summary.integer("pairs", allPairs).integer("truth_flips", allTruth).integer("flips", allFlips);
    summary.real("graded", worstGraded, "%.6f");
    return summary;
}

// The frames of the path: each frame's receivers, the lights' maps when they move, the samples, and
// the pairs against the frame before.
Result<Counts> measure(const Options& o, const std::vector<Config>& configs, const Path& path,
                       const Scene& scene, const RayReference& rays, const std::vector<uint32_t>& lights,
                       std::vector<glm::vec3>& ps, std::vector<glm::vec3>& ns, std::vector<float>& f2) {
    const CasterTriangles casters = castersFromScene(scene);
    std::vector<LightMaps> maps(lights.size());
    Counts n(configs.size());
    std::vector<Sample> prev, cur;
    for (uint32_t f = 0; f < o.view.frames; ++f) {
        if (f) receiversOf(o, path, scene, rays, f, ps, ns, f2);
        for (size_t k = 0; k < lights.size(); ++k)
            if (f == 0 || o.mapsMove())
                if (auto r = bakeLight(o, casters, scene.lights[lights[k]], uint32_t(k), f, maps[k]); !r)
                    return fail(r.error());
        cur.assign(ps.size() * lights.size(), {});
        for (size_t k = 0; k < lights.size(); ++k)
            sampleLight(o, configs, rays, maps[k], ps, ns, f2, k, lights.size(), cur);
        compareWithRays(cur, n);
        if (f) comparePairs(prev, cur, n);
        std::swap(prev, cur);
    }
    return n;
}
// --bake: one light's stored records (the first file's first record's light, in every file), each file
// a row per PCF radius (and by level for the methods filtersByLevel names). Truth: a ray 1,000 m towards
// a directional light (the night city's box is 455 m wide) or to a spot's position, from 1 mm off the
// surface.
struct Baked {
    uint32_t light = 0;
    std::vector<BakeRecord> records; // one per file
};

Result<Baked> loadBaked(const Options& o, const Scene& scene) {
    Baked b;
    for (size_t k = 0; k < o.bakes.size(); ++k) {
        auto f = readBakeFile(o.bakes[k]);
        if (!f) return fail(f.error());
        if (f->scene.scene != scene.name || f->scene.lights != scene.lights.size() ||
            f->scene.seed != o.scene.seed)
            return fail(o.bakes[k] + ": baked for " + f->scene.scene + " with " +
                        std::to_string(f->scene.lights) + " lights, seed " + std::to_string(f->scene.seed) +
                        ", not this scene");
        if (f->records.empty()) return fail(o.bakes[k] + ": no records");
        if (k == 0) b.light = f->records[0].light;
        auto r = std::find_if(f->records.begin(), f->records.end(),
                              [&](const BakeRecord& x) { return x.light == b.light && x.face == 0; });
        if (r == f->records.end())
            return fail(o.bakes[k] + ": no record of light " + std::to_string(b.light) +
                        " (the first file's)");
        if (scene.lights[b.light].type == LightKind::Point)
            return fail(o.bakes[k] + ": light " + std::to_string(b.light) +
                        " is a point light (six faces): not measured");
        b.records.push_back(std::move(*r));
    }
    return b;
}

Result<Counts> measureBaked(const Options& o, const Baked& b, const std::vector<Config>& configs,
                            const std::vector<size_t>& fileOf, const Path& path, const Scene& scene,
                            const RayReference& rays) {
    const Light& l = scene.lights[b.light];
    const bool directional = l.type == LightKind::Directional;
    Counts n(configs.size());
    std::vector<Sample> prev, cur;
    std::vector<glm::vec3> ps, ns;
    std::vector<float> f2;
    for (uint32_t f = 0; f < o.view.frames; ++f) {
        receiversOf(o, path, scene, rays, f, ps, ns, f2);
        cur.assign(ps.size(), {});
        for (size_t i = 0; i < ps.size(); ++i) {
            if (ns[i] == glm::vec3(0.0f)) continue;
            const glm::vec3 toLight = directional ? -glm::normalize(l.direction) : l.position - ps[i];
            if (glm::dot(ns[i], toLight) <= 0.0f || (!directional && !inLightCone(l, ps[i]))) continue;
            Sample& s = cur[i];
            s.counts = true;
            const glm::vec3 origin = ps[i] + ns[i] * 0.001f;
            s.truth = rays.visible(origin, directional ? origin + toLight * 1000.0f : l.position, 0.0f);
            for (size_t c = 0; c < configs.size(); ++c) {
                const BakeRecord& r = b.records[fileOf[c]];
                auto rec = makeShadowRecord(r.method, r.frustum, 0, staticResolution(r.method, r.data.data()),
                                            configs[c].pcf);
                rec.info.z = configs[c].byLevel ? 1u : 0u;
                s.vis.push_back(staticVisibility(rec, r.data.data(), ps[i], ns[i], f2[i]));
            }
        }
        compareWithRays(cur, n);
        if (f) comparePairs(prev, cur, n);
        std::swap(prev, cur);
        std::fprintf(stderr, "bench flicker: frame %u of %u\n", f + 1, o.view.frames);
    }
    return n;
}

int runBaked(const Options& o, const Scene& scene, const Path& path, const RayReference& rays) {
    auto b = loadBaked(o, scene);
    if (!b) return inputError("bench flicker", b.error());
    std::vector<Config> configs;
    std::vector<size_t> fileOf;
    for (size_t k = 0; k < b->records.size(); ++k)
        for (uint32_t r : o.pcf)
            for (bool level : {false, true}) {
                const StaticMethod m = b->records[k].method;
                if (level && !(o.byLevel && filtersByLevel(m))) continue;
                configs.push_back({m, b->records[k].resolution, r, level});
                fileOf.push_back(k);
            }
    std::fprintf(stderr,
                 "bench flicker: %s, light %u from %zu bake files, %u frames %ux%u, %zu configurations\n",
                 scene.name.c_str(), b->light, o.bakes.size(), o.view.frames, o.view.width, o.view.height,
                 configs.size());
    auto counts = measureBaked(o, *b, configs, fileOf, path, scene, rays);
    if (!counts) return runError("bench flicker", counts.error());
    std::printf("bench flicker: %s, light %u, %u frames %ux%u from %.1f,%.1f,%.1f to %.1f,%.1f,%.1f\n",
                scene.name.c_str(), b->light, o.view.frames, o.view.width, o.view.height, path.eye0.x,
                path.eye0.y, path.eye0.z, path.eye1.x, path.eye1.y, path.eye1.z);
    auto summary = report(o, configs, *counts);
    if (!summary) return runError("bench flicker", summary.error());
    std::printf("%s\n", summary->str().c_str());
    return 0;
}
} // namespace

// The flags of `bench flicker` beside its option groups.
const cli::Flags kFlickerFlags{{"--methods", "--res", "--pcf", "--lights", "--camera", "--camera-end",
                                "--out", "--light-move", "--light-turn", "--map-jitter", "--bake"},
                               {"--by-level"}};

int runBenchFlicker(int argc, char** argv) {
    if (argc > 3 && std::string(argv[3]) == "--vsm") return runBenchFlickerVsm(argc, argv);
    int status = 0;
    const auto args =
        commandArgs("bench flicker", kFlickerHelp,
                    cli::parse(argc, argv, 3, {opts::kSceneFlags, opts::kViewFlags, kFlickerFlags}), status);
    if (!args) return status;
    auto options = parseOptions(*args);
    if (!options) return usageError("bench flicker", options.error());
    const Options& o = options.value();
    auto scene = loadScene(o.scene.name, o.scene.name.rfind("night-city", 0) == 0 ? 256 : 32, o.scene.seed);
    if (!scene) return inputError("bench flicker", scene.error());
    auto path = parsePath(*args, scene.value());
    if (!path) return usageError("bench flicker", path.error());
    if (auto r = cli::checkOutputDirectory("--out", o.out); !r) return usageError("bench flicker", r.error());
    auto rays = RayReference::build(scene.value(), true);
    if (!rays) return runError("bench flicker", rays.error());

    if (!o.bakes.empty()) return runBaked(o, scene.value(), path.value(), rays.value());
    std::vector<glm::vec3> ps, ns;
    std::vector<float> f2;
    receiversOf(o, path.value(), scene.value(), rays.value(), 0, ps, ns, f2);
    const std::vector<uint32_t> lights = rankLights(scene.value(), ps, ns, o.lights);
    if (lights.empty())
        return runError("bench flicker", o.scene.name + ": no static spot light reaches the view");
    std::vector<Config> configs;
    for (uint32_t res : o.res)
        for (StaticMethod m : o.methods)
            for (uint32_t r : o.pcf) {
                configs.push_back({m, res, r, false});
                if (o.byLevel && filtersByLevel(m)) configs.push_back({m, res, r, true});
            }
    std::fprintf(stderr, "bench flicker: %s, %zu lights, %u frames %ux%u, %zu configurations%s\n",
                 scene->name.c_str(), lights.size(), o.view.frames, o.view.width, o.view.height,
                 configs.size(), o.mapsMove() ? ", maps re-rendered every frame" : "");
    auto counts = measure(o, configs, path.value(), scene.value(), rays.value(), lights, ps, ns, f2);
    if (!counts) return runError("bench flicker", counts.error());

    const Path& p = path.value();
    std::printf("bench flicker: %s, %zu lights, %u frames %ux%u from %.1f,%.1f,%.1f to %.1f,%.1f,%.1f\n",
                scene->name.c_str(), lights.size(), o.view.frames, o.view.width, o.view.height, p.eye0.x,
                p.eye0.y, p.eye0.z, p.eye1.x, p.eye1.y, p.eye1.z);
    if (o.mapsMove())
        std::printf(
            "lights move %.3f m and turn %.3f deg per frame, maps jittered by %.3f m; maps re-rendered "
            "every frame\n",
            o.move, o.turn, o.jitter);
    auto summary = report(o, configs, counts.value());
    if (!summary) return runError("bench flicker", summary.error());
    std::printf("%s\n", summary->str().c_str());
    return 0;
}

} // namespace ml
