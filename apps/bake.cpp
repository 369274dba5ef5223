// `manylights bake`, `inspect` and `verify`: the static shadow bake file from the command line.
//   bake     renders each selected static light's dual depth maps (a spot: one; a point light: six cube
//            faces) and encodes them (one file per scene);
//   inspect  validates a bake file and reports its method, resolution, lights and bytes per part;
//   verify   re-creates the scene, re-renders every light and checks every texel (or voxel).
// Progress goes to stderr, results to stdout; verify's last stdout line is JSON.
#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/gpu_dual_renderer.h"
#include "apps/need_region.h"
#include "gpu/device_types.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "bake/bake.h"
#include "bake/bake_shard.h"
#include "shadows/tools/gpu_dual_renderer.h"

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
  --scene S          night-city (default), or a .gltf / .glb file
  --scene-lights N   lights the scene is created with, 1..4096 (default 256)
  --seed S           scene seed (default 1)
  --method M         sm, mh, mmh, dagmh or cpvs
  --res N            dual depth map resolution per light, 1..16384 (cpvs: a power of two, 64..16384)
  --lights SEL       scene lights to bake: all, N, A-B, or a comma list (e.g. 0-7,12)
  --out FILE         the bake file to write
  --renderer R       gpu (default: Vulkan, tiles of <= 4096^2) or cpu (the reference rasteriser);
                     the file records it and verify re-renders with the same one
  --shard I/N        bake only shard I (0-based) of N of the selected lights into a part file for
                     `manylights merge` (same flags in every shard; each computes the same split:
                     lights dealt costliest first, 6 faces for a point light, to the least loaded shard)
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
  --quiet            no progress lines on stderr
Dynamic lights among the selection are skipped and listed, never silently. Directional lights (the
glTF's, or --light-dir) bake one orthographic map each.
)";

const char* kInspectHelp = R"(usage: manylights inspect FILE [--json]
Validates a bake file (every offset, count and checksum) and reports method, resolution, lights and
bytes per part (headers, skip list, nodes, treelets, values, factors), in total and per light.
A need-based bake (bake --need, version 2) also shows each light's resolution and why (the receiver and
camera sample that decided, the cap or the minimum, no caster: not baked), and lights per resolution.
A part of a sharded bake (bake --shard) is reported as its shard, its lights and its records.
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
Exit status: 0 all agree, 1 mismatches found, 2 bad input (unreadable or invalid file, scene changed,
no records: nothing checked is not a pass).
  --allow-outside-scene-dir  let the named glTF's buffer/image URIs leave its folder (trusted files only)
  --quiet   no progress lines on stderr
)";

std::string jsonString(const std::string& s) {
    std::string o = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\', o += char(c);
        } else if (c < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof(buf), "\\u%04x", c);
            o += buf;
        } else {
            o += char(c);
        }
    }
    return o + "\"";
}

// Progress on stderr, at most one line a second, so short runs stay quiet and long ones show the light,
// the phase, the overall percentage and the elapsed time.
BakeProgressFn progressPrinter(const char* command, bool quiet) {
    if (quiet) return {};
    auto lastPrint = std::make_shared<double>(0.0);
    return [command, lastPrint](const BakeProgress& p) {
        if (p.elapsedSeconds - *lastPrint < 1.0) return;
        *lastPrint = p.elapsedSeconds;
        std::fprintf(stderr, "manylights %s: [%3.0f%%] light %u (%u/%u) %-6s %8.1f s\n", command,
                     100.0 * p.fraction, p.light, p.ordinal + 1, p.count, p.phase, p.elapsedSeconds);
    };
}

// The positional FILE of inspect / verify, and the remaining flags.
Result<std::pair<std::string, cli::Args>> fileAndFlags(int argc, char** argv,
                                                       const std::set<std::string>& switches) {
    std::string file;
    std::vector<char*> rest = {argv[0], argv[1]};
    for (int i = 2; i < argc; ++i) {
        std::string s = argv[i];
        if (!s.empty() && s[0] == '-') {
            rest.push_back(argv[i]);
        } else if (file.empty()) {
            file = s;
        } else {
            return fail("more than one FILE ('" + file + "' and '" + s + "')");
        }
    }
    auto args = cli::parse(int(rest.size()), rest.data(), 2, {}, switches);
    if (!args) return fail(args.error());
    if (file.empty() && !args->help) return fail("missing FILE (see --help)");
    return std::make_pair(file, args.value());
}

// The build id of a part: a hash of this executable's bytes (another build's encoders may differ).
Result<uint64_t> executableHash() {
    std::ifstream is("/proc/self/exe", std::ios::binary);
    if (!is) return fail("cannot read /proc/self/exe to identify this build");
    uint64_t h = fnv1a64(nullptr, 0);
    std::vector<char> buf(1 << 20);
    while (is.read(buf.data(), std::streamsize(buf.size())) || is.gcount() > 0)
        h = fnv1a64(buf.data(), size_t(is.gcount()), h);
    return h;
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

} // namespace

int runBake(int argc, char** argv) {
    auto args = cli::parse(argc, argv, 2,
                           {"--scene", "--scene-lights", "--seed", "--method", "--res", "--lights", "--out",
                            "--renderer", "--shard", "--light-dir", "--bounds", "--need", "--need-size",
                            "--need-min", "--need-samples", "--need-seconds"},
                           {"--quiet", "--allow-outside-scene-dir"});
    if (!args) return usageError("bake", args.error());
    if (args->help) {
        std::fputs(kBakeHelp, stdout);
        return 0;
    }
    for (const char* required : {"--method", "--res", "--lights", "--out"})
        if (!args->has(required))
            return usageError("bake", std::string(required) + ": required (see --help)");
    auto method = parseStaticMethod(args->get("--method", ""));
    if (method && method.value() == StaticMethod::None) method = fail("method 'none' cannot be baked");
    auto res = cli::parseUint("--res", args->get("--res", ""), 1, kBakeMaxResolution);
    auto sceneLights = cli::parseUint("--scene-lights", args->get("--scene-lights", "256"), 1, 4096);
    auto seed = cli::parseUint("--seed", args->get("--seed", "1"), 0, 0xFFFFFFFFu);
    if (!method) return usageError("bake", "--method: " + method.error());
    for (const std::string* e : {&res.error(), &sceneLights.error(), &seed.error()})
        if (!e->empty()) return usageError("bake", *e);
    if (method.value() == StaticMethod::CPVS)
        if (auto s = makeCpvsSpace(res.value(), 1.0f, 2.0f); !s)
            return usageError("bake", "--res: " + s.error());
    std::optional<ShardId> shard;
    if (args->has("--shard")) {
        auto s = parseShard(args->get("--shard", ""));
        if (!s) return usageError("bake", s.error());
        shard = s.value();
    }
    const bool byNeed = args->has("--need");
    if (!byNeed)
        for (const char* f : {"--need-size", "--need-min", "--need-samples", "--need-seconds"})
            if (args->has(f)) return usageError("bake", std::string(f) + ": only with --need");
    if (byNeed && shard) return usageError("bake", "--need: not with --shard (parts hold one resolution)");
    auto needSize = cli::parseSize("--need-size", args->get("--need-size", "1280x720"));
    auto needMin = cli::parseUint("--need-min", args->get("--need-min", "64"), 1, kBakeMaxResolution);
    auto needSamples = cli::parseUint("--need-samples", args->get("--need-samples", "120"), 1, 100000);
    auto needSeconds = cli::parseUint("--need-seconds", args->get("--need-seconds", "60"), 1, 86400);
    for (const std::string* e :
         {&needSize.error(), &needMin.error(), &needSamples.error(), &needSeconds.error()})
        if (!e->empty()) return usageError("bake", *e);
    if (byNeed && (needMin.value() & (needMin.value() - 1)) != 0)
        return usageError("bake",
                          "--need-min: " + std::to_string(needMin.value()) + " is not a power of two");
    if (byNeed && needMin.value() > res.value())
        return usageError("bake", "--need-min: " + std::to_string(needMin.value()) +
                                      " is above the cap --res " + std::to_string(res.value()));
    if (byNeed && method.value() == StaticMethod::CPVS)
        if (auto s = makeCpvsSpace(needMin.value(), 1.0f, 2.0f); !s)
            return usageError("bake", "--need-min: " + s.error());
    const std::string out = args->get("--out", "");
    if (out.empty()) return usageError("bake", "--out: empty path");
    // Fail before a long bake, not after it.
    const std::filesystem::path outDir = std::filesystem::absolute(out).parent_path();
    if (!std::filesystem::is_directory(outDir))
        return usageError("bake", "--out: " + outDir.string() + " is not a directory");
    if (auto r = io::checkReplaceable(out); !r) return usageError("bake", "--out: " + r.error());

    const std::string rendererName = args->get("--renderer", "gpu");
    if (rendererName != "gpu" && rendererName != "cpu")
        return usageError("bake", "--renderer: '" + rendererName + "' is not gpu or cpu");
    const BakeRenderer rendererKind = rendererName == "gpu" ? BakeRenderer::Gpu : BakeRenderer::Cpu;
    GpuRendererFn gpu;
    DualRenderFn render = cpuDualRenderer();
    if (rendererKind == BakeRenderer::Gpu) {
        auto fn = gpu.make();
        if (!fn) return runError("bake", fn.error());
        render = fn.value();
    }
    SceneSpec spec{args->get("--scene", "night-city"), sceneLights.value(), seed.value()};
    SceneModifiers mods;
    mods.base = spec.scene;
    if (spec.scene.find('|') != std::string::npos) return usageError("bake", "--scene: '|' is not allowed");
    if (args->has("--bounds") || args->has("--light-dir")) {
        std::string text;
        if (args->has("--bounds")) text += "|bounds=" + args->get("--bounds", "");
        if (args->has("--light-dir")) text += "|light-dir=" + args->get("--light-dir", "");
        auto m = parseSceneModifiers(spec.scene + text);
        if (!m) return usageError("bake", m.error());
        mods = m.value();
        spec.scene = sceneModifierString(mods);
        spec.lights += uint32_t(mods.lightDirs.size());
    }
    auto scene = loadBakeScene(spec, {args->has("--allow-outside-scene-dir")});
    if (!scene) return usageError("bake", scene.error());
    for (const auto& w : scene->warnings)
        std::fprintf(stderr, "manylights bake: warning: %s\n", io::escapeText(w).c_str());
    auto lights = parseLightSelection(args->get("--lights", ""), uint32_t(scene->lights.size()));
    if (!lights) return usageError("bake", lights.error());
    for (size_t i = 0; i < mods.lightDirs.size(); ++i) // the --light-dir lights are always baked
        if (uint32_t li = uint32_t(scene->lights.size() - mods.lightDirs.size() + i);
            std::find(lights->begin(), lights->end(), li) == lights->end())
            lights->push_back(li);

    std::printf("manylights bake: %s, %s at %s%u^2, %zu of %zu lights selected\n",
                io::escapeText(spec.scene).c_str(), staticMethodName(method.value()),
                byNeed ? "need-based resolutions up to " : "", res.value(), lights->size(),
                scene->lights.size());
    std::fflush(stdout);
    if (shard)
        return bakeShard(scene.value(), spec, method.value(), res.value(), lights.value(), shard.value(), out,
                         rendererKind, render, gpu.renderer.get(), args->has("--quiet"));
    Result<BakeResult> baked = fail("");
    if (byNeed) {
        auto need = bakeNeed(scene.value(), lights.value(), args->get("--need", ""), needSamples.value(),
                             needSeconds.value(), needSize.value(), needMin.value(), res.value());
        if (!need) return usageError("bake", need.error());
        baked = bakeSceneNeed(scene.value(), spec, method.value(), need.value(), lights.value(),
                              progressPrinter("bake", args->has("--quiet")), render);
    } else {
        baked = bakeScene(scene.value(), spec, method.value(), res.value(), lights.value(),
                          progressPrinter("bake", args->has("--quiet")), render);
    }
    if (!baked) return runError("bake", baked.error());
    baked->file.renderer = rendererKind;
    for (const SkippedLight& s : baked->skipped)
        std::printf("skipped light %u: %s\n", s.light, io::escapeText(s.reason).c_str());
    for (const LightBakeStats& l : baked->lights)
        std::printf("light %u: %u^2, render %.2f s, encode %.2f s, %.1f%% covered, %llu bytes\n", l.light,
                    l.resolution, l.renderSeconds, l.encodeSeconds,
                    100.0 * double(l.coveredTexels) / (double(l.resolution) * l.resolution),
                    (unsigned long long)l.bytes);
    if (auto w = writeBakeFile(out, baked->file); !w) return runError("bake", w.error());
    BakeBytes b = bakeFileBytes(baked->file);
    size_t noCaster = 0;
    for (const LightNeed& n : baked->file.need.lights) noCaster += n.reason == NeedReason::NoCaster;
    std::printf("wrote %s: %zu lights baked, %zu skipped, %zu not baked (no caster), %llu bytes; render "
                "%.2f s, encode %.2f s\n",
                io::escapeText(out).c_str(), baked->file.records.size(), baked->skipped.size(), noCaster,
                (unsigned long long)b.total(), baked->renderSeconds, baked->encodeSeconds);
    if (validationErrors())
        return runError("bake", std::to_string(validationErrors()) + " Vulkan validation errors");
    return 0;
}

int runInspect(int argc, char** argv) {
    auto fa = fileAndFlags(argc, argv, {"--json"});
    if (!fa) return usageError("inspect", fa.error());
    auto& [path, args] = fa.value();
    if (args.help) {
        std::fputs(kInspectHelp, stdout);
        return 0;
    }
    // A part of a sharded bake is shown as its shard and the bake file it wraps.
    std::optional<BakePart> part;
    uint32_t magic = 0;
    uint64_t fileSize = 0;
    if (auto head = io::readRegularFileHead(path, 4, &fileSize); !head)
        return usageError("inspect", head.error());
    else if (head->size() == 4)
        std::memcpy(&magic, head->data(), 4);
    Result<BakeFile> file = fail("");
    if (magic == partfmt::kMagic) {
        auto p = readBakePart(path);
        if (!p) return usageError("inspect", p.error());
        part = std::move(p.value());
        file = part->file;
    } else {
        file = readBakeFile(path);
    }
    if (!file) return usageError("inspect", file.error());
    const BakeFile& f = file.value();
    std::string ownList;
    if (part)
        for (uint32_t l : part->own) ownList += (ownList.empty() ? "" : ", ") + std::to_string(l);
    std::vector<BakeRecordBytes> per;
    BakeBytes b = bakeFileBytes(f, &per);
    const uint64_t mapBytes = uint64_t(f.resolution) * f.resolution * 4; // at the file's resolution
    uint64_t allMapBytes = 0; // the 32-bit maps of every record at its own resolution
    for (const BakeRecord& r : f.records) allMapBytes += uint64_t(r.resolution) * r.resolution * 4;
    const uint32_t version = bakeFileVersion(f);
    if (args.has("--json")) {
        std::printf(
            "{\"file\": %s, \"version\": %u, \"scene\": {\"name\": %s, \"lights\": %u, \"seed\": %u},\n",
            jsonString(path).c_str(), version, jsonString(f.scene.scene).c_str(), f.scene.lights,
            f.scene.seed);
        if (part)
            std::printf(" \"part\": {\"shard\": %u, \"shards\": %u, \"selected\": %zu, \"own\": [%s], "
                        "\"device\": %s},\n",
                        part->shard.index, part->shard.count, part->selected.size(), ownList.c_str(),
                        jsonString(part->device).c_str());
        std::printf(" \"method\": \"%s\", \"resolution\": %u, \"lights\": %zu, \"bytes_total\": %llu,\n",
                    staticMethodName(f.method), f.resolution, f.records.size(),
                    (unsigned long long)b.total());
        std::printf(
            " \"bytes\": {\"headers\": %llu, \"skip_list\": %llu, \"nodes\": %llu, \"treelets\": %llu, "
            "\"values\": %llu, \"factors\": %llu},\n",
            (unsigned long long)b.headers, (unsigned long long)b.skipList, (unsigned long long)b.nodes,
            (unsigned long long)b.treelets, (unsigned long long)b.values, (unsigned long long)b.factors);
        std::printf(" \"map_bytes_per_light\": %llu,\n \"per_light\": [", (unsigned long long)mapBytes);
        for (size_t i = 0; i < f.records.size(); ++i) {
            const BakeRecord& r = f.records[i];
            const stat::ByteBreakdown& p = per[i].parts;
            std::printf(
                "%s\n  {\"light\": %u, \"resolution\": %u, \"bytes\": %llu, \"fov\": %.9g, \"near\": %.9g, "
                "\"far\": %.9g, "
                "\"parts\": {\"headers\": %llu, \"skip_list\": %llu, \"nodes\": %llu, \"treelets\": %llu, "
                "\"values\": %llu, \"factors\": %llu}}",
                i ? "," : "", r.light, r.resolution, (unsigned long long)(r.data.size() * 4), r.frustum.fov,
                r.frustum.nearPlane, r.frustum.farPlane, (unsigned long long)p.header,
                (unsigned long long)p.skipList, (unsigned long long)p.nodes, (unsigned long long)p.treelets,
                (unsigned long long)p.values, (unsigned long long)p.factors);
        }
        std::printf("]");
        if (f.hasNeed) {
            const BakeNeed& n = f.need;
            std::printf(",\n \"need\": {\"region\": %s, \"width\": %u, \"height\": %u, \"min\": %u, "
                        "\"max\": %u, \"samples\": %u, \"lights\": [",
                        jsonString(n.region).c_str(), n.width, n.height, n.minRes, n.maxRes, n.samples);
            for (size_t i = 0; i < n.lights.size(); ++i) {
                const LightNeed& l = n.lights[i];
                std::printf(
                    "%s\n  {\"light\": %u, \"resolution\": %u, \"reason\": \"%s\", \"why\": %s, "
                    "\"depth\": %.9g, \"sample\": %u, \"needed\": %.9g, \"receivers\": %u, \"seen\": %u}",
                    i ? "," : "", l.light, l.resolution, needReasonName(l.reason),
                    jsonString(needReasonText(l, n.samples)).c_str(), l.distance, l.sample, l.needed,
                    l.receivers, l.seen);
            }
            std::printf("]}");
        }
        std::printf("}\n");
        return 0;
    }
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
    std::printf("bytes: headers %llu, skip list %llu, nodes %llu, treelets %llu, values %llu, factors %llu\n",
                (unsigned long long)b.headers, (unsigned long long)b.skipList, (unsigned long long)b.nodes,
                (unsigned long long)b.treelets, (unsigned long long)b.values, (unsigned long long)b.factors);
    std::printf("%8s %6s %12s %8s %8s %8s\n", "light", "res", "bytes", "of map", "fov", "far");
    for (const BakeRecord& r : f.records)
        std::printf("%8u %6u %12llu %7.2f%% %8.3f %8.2f\n", r.light, r.resolution,
                    (unsigned long long)(r.data.size() * 4),
                    100.0 * double(r.data.size() * 4) / (double(r.resolution) * r.resolution * 4),
                    r.frustum.fov, r.frustum.farPlane);
    if (f.hasNeed) {
        const BakeNeed& n = f.need;
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
        std::printf(
            "%zu lights: %u by footprint, %u capped, %u raised to the minimum, %u not seen, %u with no "
            "caster (not baked)\n",
            n.lights.size(), byReason[uint32_t(NeedReason::Footprint)],
            byReason[uint32_t(NeedReason::Capped)], byReason[uint32_t(NeedReason::Floor)],
            byReason[uint32_t(NeedReason::NotSeen)], byReason[uint32_t(NeedReason::NoCaster)]);
        for (const LightNeed& l : n.lights)
            std::printf("light %u: %s\n", l.light, needReasonText(l, n.samples).c_str());
    }
    return 0;
}

int runVerify(int argc, char** argv) {
    auto fa = fileAndFlags(argc, argv, {"--quiet", "--allow-outside-scene-dir"});
    if (!fa) return usageError("verify", fa.error());
    auto& [path, args] = fa.value();
    if (args.help) {
        std::fputs(kVerifyHelp, stdout);
        return 0;
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto file = readBakeFile(path);
    if (!file) return usageError("verify", file.error());
    const BakeFile& f = file.value();
    if (f.records.empty())
        return usageError("verify", path + ": the file holds no records: nothing to verify");
    std::printf("manylights verify: %s: %s at %u^2, %zu lights of %s (%u lights, seed %u)\n",
                io::escapeText(path).c_str(), staticMethodName(f.method), f.resolution, f.records.size(),
                io::escapeText(f.scene.scene).c_str(), f.scene.lights, f.scene.seed);
    std::fflush(stdout);
    // Re-render with the renderer that made the bake (the file says which).
    GpuRendererFn gpu;
    DualRenderFn render = cpuDualRenderer();
    if (f.renderer == BakeRenderer::Gpu) {
        auto fn = gpu.make();
        if (!fn) return runError("verify", fn.error());
        render = fn.value();
    }
    // verifyBake, with the trust option: the scene named inside the file is loaded like a --scene.
    auto scene = loadBakeScene(f.scene, {args.has("--allow-outside-scene-dir")});
    if (!scene) return usageError("verify", path + ": cannot re-create the baked scene: " + scene.error());
    auto rep = verifyBakeScene(f, scene.value(), render, progressPrinter("verify", args.has("--quiet")));
    if (!rep) return usageError("verify", path + ": " + rep.error());
    const char* unit = f.method == StaticMethod::CPVS ? "voxels" : "texels";
    for (const VerifyLight& l : rep->lights) {
        std::printf("light %u: %llu %s checked, %llu mismatches", l.light, (unsigned long long)l.checked,
                    unit, (unsigned long long)l.mismatches);
        if (f.method == StaticMethod::CPVS) std::printf(", %llu undefined", (unsigned long long)l.undefined);
        std::printf(" (render %.2f s, check %.2f s)\n", l.renderSeconds, l.checkSeconds);
    }
    for (const std::string& e : rep->examples) std::printf("mismatch: %s\n", io::escapeText(e).c_str());
    std::printf("total %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::printf("{\"checked\": %llu, \"mismatches\": %llu}\n", (unsigned long long)rep->checked,
                (unsigned long long)rep->mismatches);
    if (validationErrors())
        return runError("verify", std::to_string(validationErrors()) + " Vulkan validation errors");
    return rep->mismatches ? 1 : 0;
}

} // namespace ml
