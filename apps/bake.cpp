// `manylights bake`, `inspect` and `verify`: the static shadow bake file from the command line.
//   bake     renders each selected static light's dual depth maps (a spot: one; a point light: six cube
//            faces) and encodes them (one file per scene);
//   inspect  validates a bake file and reports its method, resolution, lights and bytes per part;
//   verify   re-creates the scene, re-renders every light and checks every texel (or voxel).
// Progress goes to stderr, results to stdout; verify's last stdout line is JSON.
#include "apps/commands.h"
#include "apps/bake_renderer.h"
#include "apps/bake_tiles.h"
#include "apps/json.h"
#include "apps/need_region.h"
#include "apps/options.h"
#include "gpu/device_types.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "bake/bake.h"
#include "bake/bake_estimate.h"
#include "bake/bake_tiled.h"
#include "bake/bake_shard.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

namespace ml {

namespace {

const char* kBakeHelp = R"(usage: manylights bake --method M --res N --lights SEL --out FILE [options]
Bakes the static shadows of a scene's static spot and point lights (six cube faces each) into one bake file.
  --scene S          night-city (default), night-city-large (40x40 blocks, 520K triangles), either
                     with -closed (awnings, fences, foliage as thin closed boxes), indoor (rooms and
                     corridors) or a .gltf / .glb file
  --scene-lights N   lights the scene is created with, 1..4096 (default 256)
  --seed S           scene seed (default 1)
  --method M         sm, mh, mmh, dagmh or cpvs
  --res N            dual depth map resolution per light, 1..16384 (cpvs: a power of two, 64..262144);
                     mh, mmh, dagmh and cpvs up to 262144: past 16384 they bake in tiles (see --tile);
                     sm stops at 16384: its output is 4 B a texel (4 GiB at 32768^2: past what devices bind)
  --tile T           sm, mh, mmh, dagmh, cpvs: bake tile by tile, T x T texels a tile (a power of two,
                     64..16384; default 512 past --res 16384, whole maps below it). The map is never held
                     whole: memory is a tile per hardware thread (about 30 B a tile texel and 68 B of
                     rasteriser hit slots) and the output (sm: 4 B a texel, without the whole map's 8 B).
                     Tiles render on the CPU rasteriser, so with --renderer gpu only directional lights
                     may be selected; the words equal a whole-map bake's. The last line on stderr
                     gives the measured peak memory.
  --lights SEL       scene lights to bake: all, N, A-B, or a comma list (e.g. 0-7,12)
  --out FILE         the bake file to write
  --renderer R       gpu (default: Vulkan, tiles of <= 4096^2) or cpu (the reference rasteriser);
                     the file records it and verify re-renders with the same one
  --shard I/N        bake only shard I (0-based) of N of the selected lights into a part file for
                     `manylights merge` (same flags in every shard; each computes the same split:
                     lights dealt costliest first, 6 faces for a point light, to the least loaded shard).
                     A tiled bake (--tile, or --res past 16384) of one light splits its tiles instead:
                     shard I builds tiles k with k mod N = I into a tile part; merge assembles them
  --light-dir X,Y,Z  also bake a static directional light shining along X,Y,Z (appended after the
                     scene's lights and selected): one orthographic map fitted to the scene bounds
  --bounds X0,Y0,Z0,X1,Y1,Z1  the box directional lights' maps cover (default: the scene's bounds)
                     (directional maps are rendered by the CPU rasteriser with either --renderer;
                     the file's scene string records these, so verify re-creates the same scene)
  --need REGION      resolution from need: each light's resolution is the one its receivers need
                     from where the camera can be (one texel per pixel at the receiver seen largest,
                     occlusion by Embree rays), a power of two in --need-min..--res (--res is then
                     the cap). REGION: path:static|drive|orbit (the camera path sampled over
                     --need-seconds) or box:X0,Y0,Z0,X1,Y1,Z1 (a grid of positions looking anywhere).
                     Lights whose volume holds no triangle get no record (an empty map: lit
                     everywhere), counted and listed. The file (version 2) keeps each light's
                     resolution and reason; `inspect` shows them. Not with --shard.
  --need-size WxH    the image the need is computed for (default 1280x720)
  --need-min N       smallest resolution (default 64, a power of two)
  --need-samples N   camera samples (default 120; box: a grid of cbrt(N)^3)
  --need-seconds S   duration of the path sampled (default 60)
  --allow-outside-scene-dir  let the glTF's buffer/image URIs leave its folder (trusted scenes only)
  --max-memory M     peak memory allowed, MiB (default: half of this machine's memory). The bake
                     estimates its peak from the method, resolutions and lights (every record is held
                     until the file is written) and prints it; past the limit it refuses before any work
                     (--need: at the cap, then at the need's resolutions); a tiled bake goes on, held to it
  --quiet            no progress lines on stderr
Dynamic lights among the selection are skipped and listed, never silently. Directional lights (the
glTF's, or --light-dir) bake one orthographic map each.
)";

const char* kInspectHelp = R"(usage: manylights inspect FILE [--json]
Validates a bake file (every offset, count and checksum) and reports method, resolution, lights and
bytes per part (headers, skip list, value bounds, nodes, treelets, values, factors), in total and per light.
A need-based bake (bake --need, version 2) also shows each light's resolution and why (the receiver and
camera sample that decided, the cap or the minimum, no caster: not baked), and lights per resolution.
A part of a sharded bake (bake --shard) is reported as its shard, its lights and its records; a tile
part (one light's tiles) as its shard, light, tiles and tree nodes.
  --json   one JSON object: method, resolution, lights, bytes_total, bytes{...}, per_light[...]
           (and part{shard, shards, selected, own[...], device} for a part; need{region, width,
           height, min, max, samples, lights[{light, resolution, reason, why, ...}]} when need-based)
)";

const char* kVerifyHelp = R"(usage: manylights verify FILE [--quiet]
Re-creates the baked scene, re-renders every light's dual depth map (at its record's resolution:
need-based bakes differ per light) and checks every texel
(sm, mh, mmh, dagmh: enter <= decoded depth <= exit, empty texels exactly empty) or every voxel
(cpvs: against the voxelisation of the maps; undefined voxels inside closed objects are not counted).
The last line on stdout is {"checked": N, "mismatches": M}.
Exit status: 0 all agree, 1 usage error, 2 bad input (unreadable or invalid file, scene changed, no
records: nothing checked is not a pass), 3 mismatches found (or the renderer failed).
  --allow-outside-scene-dir  let the named glTF's buffer/image URIs leave its folder (trusted files only)
  --tile T  check sm, mh, mmh, dagmh, cpvs records tile by tile (T x T texels, a power of two 64..16384) on the
            CPU rasteriser, in bounded memory; records past 16384^2 always are (tiles of 512). Not for
            perspective maps the Vulkan renderer made (its depths round differently)
  --quiet   no progress lines on stderr
)";

// Progress on stderr, at most one line a second, so short runs stay quiet and long ones show the light,
// the phase, the overall percentage and the elapsed time.
BakeProgressFn progressPrinter(const char* command, bool quiet) {
    if (quiet) return {};
    auto lastPrint = std::make_shared<double>(0.0);
    return [command, lastPrint](const BakeProgress& p) {
        if (p.elapsedSeconds - *lastPrint < 1.0) return;
        *lastPrint = p.elapsedSeconds;
        // Time left: the elapsed time scaled by the fraction left (a guess: a map's tiles and lights differ
        // in cost), once there is something to scale.
        char left[48] = "";
        if (p.fraction >= 0.02 && p.fraction < 1.0)
            std::snprintf(left, sizeof(left), ", about %.0f s left",
                          p.elapsedSeconds * (1.0 - p.fraction) / p.fraction);
        std::fprintf(stderr, "manylights %s: [%3.0f%%] light %u (%u/%u) %-6s %8.1f s%s\n", command,
                     100.0 * p.fraction, p.light, p.ordinal + 1, p.count, p.phase, p.elapsedSeconds, left);
    };
}

// The positional FILE of inspect / verify, and the remaining flags.
Result<std::pair<std::string, cli::Args>> fileAndFlags(int argc, char** argv,
                                                       const std::set<std::string>& switches,
                                                       const std::set<std::string>& valued = {}) {
    std::string file;
    std::vector<char*> rest = {argv[0], argv[1]};
    for (int i = 2; i < argc; ++i) {
        std::string s = argv[i];
        if (!s.empty() && s[0] == '-') {
            rest.push_back(argv[i]);
            if (valued.count(s) && i + 1 < argc) rest.push_back(argv[++i]);
        } else if (file.empty()) {
            file = s;
        } else {
            return fail("more than one FILE ('" + file + "' and '" + s + "')");
        }
    }
    auto args = cli::parse(int(rest.size()), rest.data(), 2, valued, switches);
    if (!args) return fail(args.error());
    if (file.empty() && !args->help) return fail("missing FILE (see --help)");
    return std::make_pair(file, args.value());
}

// bake --shard I/N: bakes the shard's lights (maybe none) into a part file for `manylights merge`.
int bakeShard(const Scene& scene, const SceneSpec& spec, StaticMethod method, uint32_t res,
              const std::vector<uint32_t>& selected, ShardId id, const std::string& out,
              BakeRenderer rendererKind, const DualRenderFn& render, const GpuDualRenderer* gpu, bool quiet) {
    BakePart part;
    part.shard = id;
    part.selected = selected;
    part.own = shardLights(scene, selected, res, id);
    part.fingerprint = sceneFingerprint(scene);
    auto build = executableHash();
    if (!build) return runError("bake", build.error());
    part.build = build.value();
    part.device = "cpu";
    if (gpu) part.device = gpu->deviceDescription();
    part.file.scene = spec, part.file.method = method, part.file.resolution = res;
    std::vector<uint32_t> bakeable;
    for (uint32_t l : part.own)
        if (bakeSkipReason(scene, scene.lights[l]).empty())
            bakeable.push_back(l);
        else
            std::printf("skipped light %u: %s\n", l, bakeSkipReason(scene, scene.lights[l]).c_str());
    std::printf("shard %u/%u: %zu of the %zu selected lights (%zu to bake)\n", id.index, id.count,
                part.own.size(), selected.size(), bakeable.size());
    double renderSeconds = 0, encodeSeconds = 0;
    if (!bakeable.empty()) {
        auto baked = bakeScene(scene, spec, method, res, bakeable, progressPrinter("bake", quiet), render);
        if (!baked) return runError("bake", baked.error());
        part.file = std::move(baked->file);
        renderSeconds = baked->renderSeconds, encodeSeconds = baked->encodeSeconds;
    }
    part.file.renderer = rendererKind;
    if (auto w = writeBakePart(out, part); !w) return runError("bake", w.error());
    std::printf("wrote part %s: shard %u/%u, %zu records; render %.2f s, encode %.2f s\n", out.c_str(),
                id.index, id.count, part.file.records.size(), renderSeconds, encodeSeconds);
    if (validationErrors())
        return runError("bake", std::to_string(validationErrors()) + " Vulkan validation errors");
    return 0;
}

// bake --need: the camera region's samples, each bakeable selected light's need (printed, one line
// each, and counted by reason).
Result<BakeNeed> bakeNeed(const Scene& scene, const std::vector<uint32_t>& lights, const std::string& spec,
                          uint32_t samples, uint32_t seconds, std::pair<uint32_t, uint32_t> size,
                          uint32_t minRes, uint32_t maxRes) {
    auto region = makeNeedRegion(scene, spec, samples, double(seconds), size.first, size.second);
    if (!region) return fail(region.error());
    NeedOptions o;
    o.width = size.first, o.height = size.second, o.minRes = minRes, o.maxRes = maxRes;
    auto needs = estimateNeedWithRays(scene, lights, region.value(), o);
    if (!needs) return fail(needs.error());
    BakeNeed n;
    n.region = region->text, n.width = o.width, n.height = o.height, n.minRes = minRes, n.maxRes = maxRes;
    n.samples = uint32_t(region->cameras.size());
    n.lights = needs.value();
    uint32_t byReason[6] = {};
    uint64_t rays = 0;
    for (const LightNeed& l : n.lights) {
        ++byReason[uint32_t(l.reason)];
        rays += l.rays;
        std::printf("need light %u: %s\n", l.light, needReasonText(l, n.samples).c_str());
    }
    std::printf(
        "need (%s, %ux%u): %zu lights: %u by footprint, %u capped at %u, %u raised to the minimum %u, "
        "%u not seen (minimum), %u with no caster (not baked); %llu occlusion rays\n",
        io::escapeText(n.region).c_str(), n.width, n.height, n.lights.size(),
        byReason[uint32_t(NeedReason::Footprint)], byReason[uint32_t(NeedReason::Capped)], maxRes,
        byReason[uint32_t(NeedReason::Floor)], minRes, byReason[uint32_t(NeedReason::NotSeen)],
        byReason[uint32_t(NeedReason::NoCaster)], (unsigned long long)rays);
    std::fflush(stdout);
    return n;
}

struct BakeOptions {
    StaticMethod method = StaticMethod::None;
    uint32_t res = 0, sceneLights = 256;
    opts::Scene scene;
    std::optional<ShardId> shard;
    bool byNeed = false, quiet = false;
    opts::Need need;
    std::string out;
    BakeRenderer renderer = BakeRenderer::Gpu;
    uint64_t maxMemory = 0; // bytes (--max-memory)
    uint32_t tile = 0;      // --tile (0: tiles only past kBakeWholeMapMax)
};

// --need and its region's options: only together, never with --shard; the minimum a power of two at
// most the cap, and one CPVS takes.
Result<void> parseNeed(const cli::Args& args, BakeOptions& o) {
    o.byNeed = args.has("--need");
    if (!o.byNeed)
        for (const std::string& f : opts::kNeedFlags.valued)
            if (args.has(f)) return fail(f + ": only with --need");
    if (o.byNeed && o.shard) return fail("--need: not with --shard (parts hold one resolution)");
    auto need = opts::need(args, "1280x720");
    if (!need) return fail(need.error());
    o.need = need.value();
    if (!o.byNeed) return {};
    if (auto r = opts::checkNeedMin(o.need.minRes); !r) return r;
    if (o.need.minRes > o.res)
        return fail("--need-min: " + std::to_string(o.need.minRes) + " is above the cap --res " +
                    std::to_string(o.res));
    if (o.method == StaticMethod::CPVS)
        if (auto s = makeCpvsSpace(o.need.minRes, 1.0f, 2.0f); !s) return fail("--need-min: " + s.error());
    return {};
}

Result<BakeOptions> parseBake(const cli::Args& args) {
    for (const char* required : {"--method", "--res", "--lights", "--out"})
        if (!args.has(required)) return fail(std::string(required) + ": required (see --help)");
    BakeOptions o;
    auto method = parseStaticMethod(args.get("--method", ""));
    if (method && method.value() == StaticMethod::None) method = fail("method 'none' cannot be baked");
    auto res = cli::parseUint("--res", args.get("--res", ""), 1, kBakeMaxResolution);
    auto sceneLights = cli::parseUint("--scene-lights", args.get("--scene-lights", "256"), 1, 4096);
    auto scene = opts::scene(args);
    if (!method) return fail("--method: " + method.error());
    for (const std::string* e : {&res.error(), &sceneLights.error(), &scene.error()})
        if (!e->empty()) return fail(*e);
    o.method = method.value(), o.res = res.value(), o.sceneLights = sceneLights.value();
    o.scene = scene.value();
    o.quiet = args.has("--quiet");
    if (o.method == StaticMethod::CPVS)
        if (auto s = makeCpvsSpace(o.res, 1.0f, 2.0f); !s) return fail("--res: " + s.error());
    if (args.has("--shard")) {
        auto s = parseShard(args.get("--shard", ""));
        if (!s) return fail(s.error());
        o.shard = s.value();
    }
    if (auto r = parseNeed(args, o); !r) return fail(r.error());
    o.out = args.get("--out", "");
    if (o.out.empty()) return fail("--out: empty path");
    // Fail before a long bake, not after it.
    const std::filesystem::path outDir = std::filesystem::absolute(o.out).parent_path();
    if (!std::filesystem::is_directory(outDir))
        return fail("--out: " + outDir.string() + " is not a directory");
    if (auto r = io::checkReplaceable(o.out); !r) return fail("--out: " + r.error());
    auto renderer = parseRenderer(args);
    if (!renderer) return fail(renderer.error());
    o.renderer = renderer.value();
    auto limit = opts::maxMemory(args);
    if (!limit) return fail(limit.error());
    o.maxMemory = limit.value();
    if (args.has("--tile")) {
        auto tile = cli::parseUint("--tile", args.get("--tile", ""), 64, 16384);
        if (!tile) return fail(tile.error());
        if (tile.value() & (tile.value() - 1))
            return fail("--tile: " + args.get("--tile", "") + " is not a power of two");
        o.tile = tile.value();
    }
    if (o.res > kBakeWholeMapMax && o.method == StaticMethod::SM)
        return fail("--res: " + smPastLimitReason(o.res));
    if (o.tile && !bakeTiled(o.method, o.res, o.tile))
        return fail("--tile: " + std::string(staticMethodName(o.method)) +
                    " bakes whole maps (sm, mh, mmh, dagmh and cpvs bake in tiles)");
    return o;
}

// The scene with its --bounds and --light-dir modifiers, and the selected lights (the --light-dir
// ones always among them).
struct Selection {
    SceneSpec spec;
    Scene scene;
    std::vector<uint32_t> lights;
};

Result<Selection> selectLights(const cli::Args& args, const BakeOptions& o, bool& sceneFailed) {
    Selection sel;
    sel.spec = SceneSpec{o.scene.name, o.sceneLights, o.scene.seed};
    SceneSpec& spec = sel.spec;
    SceneModifiers mods;
    mods.base = spec.scene;
    if (spec.scene.find('|') != std::string::npos) return fail("--scene: '|' is not allowed");
    if (args.has("--bounds") || args.has("--light-dir")) {
        std::string text;
        if (args.has("--bounds")) text += "|bounds=" + args.get("--bounds", "");
        if (args.has("--light-dir")) text += "|light-dir=" + args.get("--light-dir", "");
        auto m = parseSceneModifiers(spec.scene + text);
        if (!m) return fail(m.error());
        mods = m.value();
        spec.scene = sceneModifierString(mods);
        spec.lights += uint32_t(mods.lightDirs.size());
    }
    auto scene = loadBakeScene(spec, {o.scene.allowOutside});
    if (!scene) {
        sceneFailed = true;
        return fail(scene.error());
    }
    for (const auto& w : scene->warnings)
        std::fprintf(stderr, "manylights bake: warning: %s\n", io::escapeText(w).c_str());
    auto lights = parseLightSelection(args.get("--lights", ""), uint32_t(scene->lights.size()));
    if (!lights) return fail(lights.error());
    for (size_t i = 0; i < mods.lightDirs.size(); ++i) // the --light-dir lights are always baked
        if (uint32_t li = uint32_t(scene->lights.size() - mods.lightDirs.size() + i);
            std::find(lights->begin(), lights->end(), li) == lights->end())
            lights->push_back(li);
    sel.scene = std::move(scene.value());
    sel.lights = std::move(lights.value());
    return sel;
}

// --tile and the memory limit as the bake's tiling: the tree's nodes are bounded by what --max-memory
// leaves after the tiles' working memory (a node is held twice while tiles are spliced).
BakeTiles bakeTilesOf(const BakeOptions& o) {
    BakeTiles t;
    t.tile = o.tile;
    const uint64_t working = tiledWorkingBytes(o.tile ? o.tile : kBakeDefaultTile);
    t.maxNodes = o.maxMemory > working ? (o.maxMemory - working) / (2 * sizeof(MhTree::Node)) : 1;
    return t;
}

Result<void> checkBakeMemory(const BakeOptions& o, const Selection& sel,
                             const std::optional<BakeNeed>& need) {
    std::vector<uint32_t> faces;
    uint32_t lights = 0;
    for (uint32_t l : sel.lights) {
        if (l >= sel.scene.lights.size() || !bakeSkipReason(sel.scene, sel.scene.lights[l]).empty()) continue;
        uint32_t res = o.byNeed && !need ? o.need.minRes : o.res; // --need: its minimum until it has chosen
        if (need) {
            res = 0;
            for (const LightNeed& n : need->lights)
                if (n.light == l) res = n.resolution;
        }
        if (!res) continue;
        ++lights;
        for (size_t f = 0; f < bakeFrustums(sel.scene, sel.scene.lights[l]).size(); ++f) faces.push_back(res);
    }
    const std::string what = std::to_string(lights) + " lights, " + std::to_string(faces.size()) + " maps " +
                             (need ? std::string("at the need's resolutions")
                                   : "at " + std::to_string(o.byNeed ? o.need.minRes : o.res) + "^2" +
                                         (o.byNeed ? " (--need-min, before the need chooses)" : ""));
    const uint32_t shards = o.shard && bakeTiled(o.method, o.res, o.tile) ? o.shard->count : 1;
    const uint64_t estimate = bakePeakBytes(faces, o.method, o.tile, shards,
                                            bakeBaseOf(sel.scene, o.renderer == BakeRenderer::Gpu));
    // The estimate's node counts (a node per 64 texels; CPVS: kCpvsNodesPerSide a texel of the side) are
    // no proven bound; a tiled tree or DAG is held to what --max-memory leaves (bakeTilesOf), so a tiled
    // bake goes on and stops if it passes that.
    const auto tiled = [&](uint32_t r) { return bakeTiled(o.method, r, o.tile); };
    // SM's tiles build no tree to hold to the limit: past --max-memory SM is refused as a whole map is.
    if (o.method != StaticMethod::SM && !faces.empty() && std::all_of(faces.begin(), faces.end(), tiled) &&
        estimate > o.maxMemory) {
        const uint64_t nodes = bakeTilesOf(o).maxNodes;
        const std::string held =
            o.method == StaticMethod::CPVS
                ? std::to_string(kCpvsNodesPerSide) + " DAG nodes a texel of the side) is over the limit " +
                      std::to_string(o.maxMemory >> 20) + " MiB: the DAG under construction is held to " +
                      std::to_string((nodes * 2 * sizeof(MhTree::Node)) >> 20) +
                      " MiB, the bake stops past it"
                : "a tree node per 64 texels) is over the limit " + std::to_string(o.maxMemory >> 20) +
                      " MiB: the tree is held to " + std::to_string(nodes) +
                      " nodes, the bake stops past them";
        std::fprintf(stderr, "manylights bake: estimated peak memory %llu MiB (%s, %s\n",
                     (unsigned long long)(estimate >> 20), what.c_str(), held.c_str());
        return {};
    }
    return opts::checkMemory("bake", estimate, o.maxMemory,
                             shards > 1 ? what + ", one tile shard of " + std::to_string(shards) : what);
}

// The whole selection into one bake file (by need or at one resolution), and what was baked.
int bakeWhole(const cli::Args& args, const BakeOptions& o, const Selection& sel, const DualRenderFn& render) {
    Result<BakeResult> baked = fail("");
    if (o.byNeed) {
        auto need = bakeNeed(sel.scene, sel.lights, args.get("--need", ""), o.need.samples, o.need.seconds,
                             {o.need.width, o.need.height}, o.need.minRes, o.res);
        if (!need) return usageError("bake", need.error());
        if (auto r = checkBakeMemory(o, sel, need.value()); !r) return usageError("bake", r.error());
        baked = bakeSceneNeed(sel.scene, sel.spec, o.method, need.value(), sel.lights,
                              progressPrinter("bake", o.quiet), render, bakeTilesOf(o));
    } else {
        baked = bakeScene(sel.scene, sel.spec, o.method, o.res, sel.lights, progressPrinter("bake", o.quiet),
                          render, bakeTilesOf(o));
    }
    if (!baked) return runError("bake", baked.error());
    baked->file.renderer = o.renderer;
    for (const SkippedLight& s : baked->skipped)
        std::printf("skipped light %u: %s\n", s.light, io::escapeText(s.reason).c_str());
    for (const LightBakeStats& l : baked->lights) {
        std::printf("light %u: %u^2, render %.2f s, encode %.2f s, %.1f%% covered, %llu bytes", l.light,
                    l.resolution, l.renderSeconds, l.encodeSeconds,
                    100.0 * double(l.coveredTexels) / (double(l.resolution) * l.resolution),
                    (unsigned long long)l.bytes);
        if (l.tiles && o.method == StaticMethod::SM)
            std::printf(" (%u tiles, %u empty; render includes writing the texels)", l.tiles, l.emptyTiles);
        else if (l.tiles)
            std::printf(" (%u tiles, %u empty; render includes building the %llu-node tree)", l.tiles,
                        l.emptyTiles, (unsigned long long)l.treeNodes);
        if (l.dagLiveBytes)
            std::printf(" (CPVS: %llu steps, largest region %llu nodes + %llu leaves, sub-DAGs alive at most "
                        "%llu bytes)",
                        (unsigned long long)l.cpvsSteps, (unsigned long long)l.regionNodesPeak,
                        (unsigned long long)l.regionLeavesPeak, (unsigned long long)l.dagLiveBytes);
        std::printf("\n");
    }
    if (auto w = writeBakeFile(o.out, baked->file); !w) return runError("bake", w.error());
    BakeBytes b = bakeFileBytes(baked->file);
    size_t noCaster = 0;
    for (const LightNeed& n : baked->file.need.lights) noCaster += n.reason == NeedReason::NoCaster;
    std::printf("wrote %s: %zu lights baked, %zu skipped, %zu not baked (no caster), %llu bytes; render "
                "%.2f s, encode %.2f s\n",
                io::escapeText(o.out).c_str(), baked->file.records.size(), baked->skipped.size(), noCaster,
                (unsigned long long)b.total(), baked->renderSeconds, baked->encodeSeconds);
    std::fprintf(stderr, "manylights bake: measured peak memory %llu MiB\n",
                 (unsigned long long)(peakResidentBytes() >> 20));
    if (validationErrors())
        return runError("bake", std::to_string(validationErrors()) + " Vulkan validation errors");
    return 0;
}

} // namespace

// The flags of `bake` beside its option groups.
const cli::Flags kBakeFlags{{"--scene-lights", "--method", "--res", "--lights", "--out", "--renderer",
                             "--shard", "--light-dir", "--bounds", "--need", "--max-memory", "--tile"},
                            {"--quiet"}};

int runBake(int argc, char** argv) {
    int status = 0;
    const auto args = commandArgs(
        "bake", kBakeHelp,
        cli::parse(argc, argv, 2, {opts::kSceneFlags, opts::kSceneDirFlags, opts::kNeedFlags, kBakeFlags}),
        status);
    if (!args) return status;
    auto options = parseBake(*args);
    if (!options) return usageError("bake", options.error());
    const BakeOptions& o = options.value();
    bool sceneFailed = false;
    auto sel = selectLights(*args, o, sceneFailed);
    if (!sel) return sceneFailed ? inputError("bake", sel.error()) : usageError("bake", sel.error());
    // Memory bounded before any work: the estimate at the selection's resolutions (--need: the cap,
    // refined once the need has chosen them, in bakeWhole).
    if (auto r = checkBakeMemory(o, sel.value(), std::nullopt); !r) return usageError("bake", r.error());
    if (bakeTiled(o.method, o.res, o.tile) && o.renderer == BakeRenderer::Gpu)
        for (uint32_t l : sel->lights)
            if (l < sel->scene.lights.size() && sel->scene.lights[l].type != LightKind::Directional &&
                bakeSkipReason(sel->scene, sel->scene.lights[l]).empty())
                return usageError("bake",
                                  "light " + std::to_string(l) +
                                      ": tiled bakes render on the CPU rasteriser; a spot or point "
                                      "light needs --renderer cpu (directional lights are CPU-rendered "
                                      "with either)");
    auto rendering = makeRendering(o.renderer);
    if (!rendering) return runError("bake", rendering.error());
    std::printf("manylights bake: %s, %s at %s%u^2, %zu of %zu lights selected\n",
                io::escapeText(sel->spec.scene).c_str(), staticMethodName(o.method),
                o.byNeed ? "need-based resolutions up to " : "", o.res, sel->lights.size(),
                sel->scene.lights.size());
    std::fflush(stdout);
    if (o.shard && bakeTiled(o.method, o.res, o.tile)) // one light's tiles
        return bakeTileShard(sel->scene, sel->spec, o.method, o.res, o.tile ? o.tile : kBakeDefaultTile,
                             sel->lights, o.shard.value(), o.renderer, o.out, o.quiet);
    if (o.shard)
        return bakeShard(sel->scene, sel->spec, o.method, o.res, sel->lights, o.shard.value(), o.out,
                         o.renderer, rendering->render, rendering->gpu.get(), o.quiet);
    return bakeWhole(*args, o, sel.value(), rendering->render);
}

namespace {
// A bake file, or a part of a sharded bake: shown as its shard and the bake file it wraps.
struct Inspected {
    std::optional<BakePart> part;
    BakeFile file;
    std::string ownList; // the part's own lights, ", "-separated
};

Result<Inspected> readInspected(const std::string& path) {
    Inspected in;
    uint32_t magic = 0;
    uint64_t fileSize = 0;
    if (auto head = io::readRegularFileHead(path, 4, &fileSize); !head)
        return fail(head.error());
    else if (head->size() == 4)
        std::memcpy(&magic, head->data(), 4);
    if (magic == partfmt::kMagic) {
        auto p = readBakePart(path);
        if (!p) return fail(p.error());
        in.part = std::move(p.value());
        in.file = in.part->file;
        for (uint32_t l : in.part->own) in.ownList += (in.ownList.empty() ? "" : ", ") + std::to_string(l);
        return in;
    }
    auto file = readBakeFile(path);
    if (!file) return fail(file.error());
    in.file = std::move(file.value());
    return in;
}

std::string partsJson(uint64_t headers, uint64_t skipList, uint64_t bounds, uint64_t nodes, uint64_t treelets,
                      uint64_t values, uint64_t factors) {
    return json::Object()
        .integer("headers", headers)
        .integer("skip_list", skipList)
        .integer("bounds", bounds)
        .integer("nodes", nodes)
        .integer("treelets", treelets)
        .integer("values", values)
        .integer("factors", factors)
        .str();
}

// inspect --json's "need" object: the region and every light's need.
std::string needJson(const BakeNeed& n) {
    std::vector<std::string> lights;
    for (const LightNeed& l : n.lights)
        lights.push_back(json::Object()
                             .integer("light", l.light)
                             .integer("resolution", l.resolution)
                             .text("reason", needReasonName(l.reason))
                             .text("why", needReasonText(l, n.samples))
                             .real("depth", l.distance, "%.9g")
                             .integer("sample", l.sample)
                             .real("needed", l.needed, "%.9g")
                             .integer("receivers", l.receivers)
                             .integer("seen", l.seen)
                             .str());
    json::Object o;
    o.text("region", n.region).integer("width", n.width).integer("height", n.height);
    o.integer("min", n.minRes).integer("max", n.maxRes).integer("samples", n.samples);
    o.raw("lights", json::array(lights, ",\n  ", "[\n  ", "]"));
    return o.str();
}

// A fitted directional record's map and box: sizes, extents and the shares in the box.
std::string directionalJson(const DirectionalFit& d) {
    return json::Object()
        .integer("width", d.width)
        .integer("rows", d.rows)
        .real("extent_x", d.extentX, "%.9g")
        .real("extent_y", d.extentY, "%.9g")
        .real("slab_near", d.slabNear, "%.9g")
        .real("slab_far", d.slabFar, "%.9g")
        .real("texels_in_box", d.texelsInBox, "%.6f")
        .real("depth_slices_in_box", d.depthSlicesInBox, "%.6f")
        .real("caster_slices", d.casterSlices, "%.6f")
        .str();
}

// inspect --json: one object, a line per part of it and per record.
std::string inspectJson(const std::string& path, const Inspected& in) {
    const BakeFile& f = in.file;
    std::vector<BakeRecordBytes> per;
    const BakeBytes b = bakeFileBytes(f, &per);
    json::Object o;
    o.text("file", path).integer("version", bakeFileVersion(f));
    o.raw("scene", json::Object()
                       .text("name", f.scene.scene)
                       .integer("lights", f.scene.lights)
                       .integer("seed", f.scene.seed)
                       .str());
    if (in.part) {
        std::vector<std::string> own;
        for (uint32_t l : in.part->own) own.push_back(std::to_string(l));
        o.breakLine().raw("part", json::Object()
                                      .integer("shard", in.part->shard.index)
                                      .integer("shards", in.part->shard.count)
                                      .integer("selected", in.part->selected.size())
                                      .raw("own", json::array(own))
                                      .text("device", in.part->device)
                                      .str());
    }
    o.breakLine().text("method", staticMethodName(f.method)).integer("resolution", f.resolution);
    o.integer("lights", f.records.size()).integer("bytes_total", b.total());
    o.breakLine().raw("bytes",
                      partsJson(b.headers, b.skipList, b.bounds, b.nodes, b.treelets, b.values, b.factors));
    o.breakLine().integer("map_bytes_per_light", uint64_t(f.resolution) * f.resolution * 4);
    std::vector<std::string> records;
    for (size_t i = 0; i < f.records.size(); ++i) {
        const BakeRecord& r = f.records[i];
        const stat::ByteBreakdown& p = per[i].parts;
        json::Object rec;
        rec.integer("light", r.light)
            .integer("resolution", r.resolution)
            .integer("bytes", uint64_t(r.data.size() * 4))
            .real("fov", r.frustum.fov, "%.9g")
            .real("near", r.frustum.nearPlane, "%.9g")
            .real("far", r.frustum.farPlane, "%.9g")
            .raw("parts",
                 partsJson(p.header, p.skipList, p.bounds, p.nodes, p.treelets, p.values, p.factors));
        if (auto fit = directionalFit(r); fit) rec.raw("directional", directionalJson(fit.value()));
        records.push_back(rec.str());
    }
    o.breakLine().raw("per_light", json::array(records, ",\n  ", "[\n  ", "]"));
    if (f.hasNeed) o.breakLine().raw("need", needJson(f.need));
    return o.str();
}

// inspect's need-based resolution summary: lights per resolution and by reason, one line per light.
void printNeed(const BakeNeed& n) {
    uint32_t byReason[6] = {};
    std::map<uint32_t, uint32_t> byRes; // lights per resolution, highest first below
    for (const LightNeed& l : n.lights) ++byReason[uint32_t(l.reason)], ++byRes[l.resolution];
    std::printf("resolution from need: %s, image %ux%u, resolutions %u..%u\n",
                io::escapeText(n.region).c_str(), n.width, n.height, n.minRes, n.maxRes);
    std::string hist;
    for (auto it = byRes.rbegin(); it != byRes.rend(); ++it)
        hist += (hist.empty() ? "" : ", ") + std::to_string(it->second) + " at " +
                (it->first ? std::to_string(it->first) : std::string("none"));
    std::printf("lights per resolution: %s\n", hist.c_str());
    std::printf("%zu lights: %u by footprint, %u capped, %u raised to the minimum, %u not seen, %u with no "
                "caster (not baked)\n",
                n.lights.size(), byReason[uint32_t(NeedReason::Footprint)],
                byReason[uint32_t(NeedReason::Capped)], byReason[uint32_t(NeedReason::Floor)],
                byReason[uint32_t(NeedReason::NotSeen)], byReason[uint32_t(NeedReason::NoCaster)]);
    for (const LightNeed& l : n.lights)
        std::printf("light %u: %s\n", l.light, needReasonText(l, n.samples).c_str());
}

// inspect without --json: the file, its bytes by part and per record.
void printInspected(const std::string& path, const Inspected& in) {
    const BakeFile& f = in.file;
    const std::optional<BakePart>& part = in.part;
    const std::string& ownList = in.ownList;
    const BakeBytes b = bakeFileBytes(f);
    uint64_t allMapBytes = 0; // the 32-bit maps of every record at its own resolution
    for (const BakeRecord& r : f.records) allMapBytes += uint64_t(r.resolution) * r.resolution * 4;
    const uint32_t version = bakeFileVersion(f);
    // The scene string comes from the file: escaped, so it cannot add lines or terminal codes.
    std::printf("%s: bake file version %u, scene %s (%u lights, seed %u)\n", io::escapeText(path).c_str(),
                version, io::escapeText(f.scene.scene).c_str(), f.scene.lights, f.scene.seed);
    if (part)
        std::printf("part of a sharded bake: shard %u/%u, lights %s of %zu selected; device %s\n",
                    part->shard.index, part->shard.count, ownList.empty() ? "(none)" : ownList.c_str(),
                    part->selected.size(), part->device.c_str());
    std::printf("method %s, resolution %s%u^2, %zu lights, %llu bytes (%.2f%% of %zu 32-bit maps)\n",
                staticMethodName(f.method), f.hasNeed ? "from need, at most " : "", f.resolution,
                f.records.size(), (unsigned long long)b.total(),
                f.records.empty() ? 0.0 : 100.0 * double(b.total()) / double(allMapBytes), f.records.size());
    std::printf(
        "bytes: headers %llu, skip list %llu, value bounds %llu, nodes %llu, treelets %llu, values %llu, "
        "factors %llu\n",
        (unsigned long long)b.headers, (unsigned long long)b.skipList, (unsigned long long)b.bounds,
        (unsigned long long)b.nodes, (unsigned long long)b.treelets, (unsigned long long)b.values,
        (unsigned long long)b.factors);
    std::printf("%8s %6s %12s %8s %8s %8s\n", "light", "res", "bytes", "of map", "fov", "far");
    for (const BakeRecord& r : f.records)
        std::printf("%8u %6u %12llu %7.2f%% %8.3f %8.2f\n", r.light, r.resolution,
                    (unsigned long long)(r.data.size() * 4),
                    100.0 * double(r.data.size() * 4) / (double(r.resolution) * r.resolution * 4),
                    r.frustum.fov, r.frustum.farPlane);
    for (const BakeRecord& r : f.records)
        if (auto d = directionalFit(r); d)
            std::printf(
                "directional light %u: map %u x %u texels over %.3f x %.3f m, depth slab %.3f..%.3f m; "
                "%.1f%% of texels and %.1f%% of depth slices in the box, casters span %.1f%% of the "
                "slices\n",
                r.light, d->width, d->rows, d->extentX, d->extentY, d->slabNear, d->slabFar,
                100.0 * d->texelsInBox, 100.0 * d->depthSlicesInBox, 100.0 * d->casterSlices);
    if (f.hasNeed) printNeed(f.need);
}
} // namespace

int runInspect(int argc, char** argv) {
    auto fa = fileAndFlags(argc, argv, {"--json"});
    if (!fa) return usageError("inspect", fa.error());
    auto& [path, args] = fa.value();
    if (args.help) {
        std::fputs(kInspectHelp, stdout);
        return 0;
    }
    if (isTilePartFile(path)) return inspectTilePart(path, args.has("--json"));
    auto in = readInspected(path);
    if (!in) return inputError("inspect", in.error());
    if (args.has("--json"))
        std::printf("%s\n", inspectJson(path, in.value()).c_str());
    else
        printInspected(path, in.value());
    return 0;
}

int runVerify(int argc, char** argv) {
    auto fa = fileAndFlags(argc, argv, {"--quiet", "--allow-outside-scene-dir"}, {"--tile"});
    if (!fa) return usageError("verify", fa.error());
    auto& [path, args] = fa.value();
    if (args.help) {
        std::fputs(kVerifyHelp, stdout);
        return 0;
    }
    uint32_t tile = 0;
    if (args.has("--tile")) {
        auto t = cli::parseUint("--tile", args.get("--tile", ""), 64, 16384);
        if (!t) return usageError("verify", t.error());
        if (t.value() & (t.value() - 1))
            return usageError("verify", "--tile: " + args.get("--tile", "") + " is not a power of two");
        tile = t.value();
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto file = readBakeFile(path);
    if (!file) return inputError("verify", file.error());
    const BakeFile& f = file.value();
    if (f.records.empty())
        return inputError("verify", path + ": the file holds no records: nothing to verify");
    std::printf("manylights verify: %s: %s at %u^2, %zu lights of %s (%u lights, seed %u)\n",
                io::escapeText(path).c_str(), staticMethodName(f.method), f.resolution, f.records.size(),
                io::escapeText(f.scene.scene).c_str(), f.scene.lights, f.scene.seed);
    std::fflush(stdout);
    // Re-render with the renderer that made the bake (the file says which).
    auto rendering = makeRendering(f.renderer);
    if (!rendering) return runError("verify", rendering.error());
    const DualRenderFn& render = rendering->render;
    // verifyBake, with the trust option: the scene named inside the file is loaded like a --scene.
    auto scene = loadBakeScene(f.scene, {args.has("--allow-outside-scene-dir")});
    if (!scene) return inputError("verify", path + ": cannot re-create the baked scene: " + scene.error());
    auto rep =
        verifyBakeScene(f, scene.value(), render, progressPrinter("verify", args.has("--quiet")), tile);
    if (!rep) return inputError("verify", path + ": " + rep.error());
    const char* unit = f.method == StaticMethod::CPVS ? "voxels" : "texels";
    for (const VerifyLight& l : rep->lights) {
        std::printf("light %u: %llu %s checked, %llu mismatches", l.light, (unsigned long long)l.checked,
                    unit, (unsigned long long)l.mismatches);
        if (f.method == StaticMethod::CPVS) std::printf(", %llu undefined", (unsigned long long)l.undefined);
        if (l.casterSlices >= 0.0)
            std::printf(", casters span %.1f%% of the depth slices", 100.0 * l.casterSlices);
        std::printf(" (render %.2f s, check %.2f s)\n", l.renderSeconds, l.checkSeconds);
    }
    for (const std::string& e : rep->examples) std::printf("mismatch: %s\n", io::escapeText(e).c_str());
    std::printf("total %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::fprintf(stderr, "manylights verify: measured peak memory %llu MiB\n",
                 (unsigned long long)(peakResidentBytes() >> 20));
    std::printf("{\"checked\": %llu, \"mismatches\": %llu}\n", (unsigned long long)rep->checked,
                (unsigned long long)rep->mismatches);
    if (validationErrors())
        return runError("verify", std::to_string(validationErrors()) + " Vulkan validation errors");
    return rep->mismatches ? kExitRun : 0;
}

} // namespace ml
