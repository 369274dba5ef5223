// `manylights check vsm`: every virtual-shadow-map lookup of a path's frames against a full reference
// depth map of the same casters at the same mip, rendered by the CPU rasteriser (shadows/static/
// raster_dual.h, exact top-left coverage). The probe pass (vsm_probe.comp) records, per shaded pixel and
// light with maps, the map, mip and texel the evaluation pass read and the depth it found there.
// A record disagrees when the texel is empty in one map and not the other, when the shadow test of the
// receiver's biased depth against the two depths differs, when a "no caster" answer has a caster in the
// reference, or when no page was found at any mip. Depths further apart than the float-versus-double
// interpolation tolerance of the static dual-depth test (2e-5 of the range plus 1/64 of the local depth
// step) are reported as depth_beyond_tolerance: huge triangles clipped far outside the map interpolate
// depth with float error on the GPU (measured: up to 0.05 % of the range at mip 3 on the night city).
// Last stdout line: JSON; exit 0 only when something was checked and
// nothing disagreed.
#include "apps/commands.h"
#include "apps/json.h"
#include "apps/options.h"
#include "apps/vsm_args.h"
#include "engine/manylights_diagnostics.h"
#include "host/vsm_session.h"
#include "shaders/shared/config.h"
#include "shadows/static/raster_dual.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>

namespace ml {

static const char* kCheckHelp = R"(usage: manylights check vsm [options]
Checks every virtual-shadow-map lookup of a camera path against full reference maps (CPU rasteriser).
  --scene S      night-city (default), indoor (rooms: spot, point lights, carts) or a .gltf / .glb file
  --path P       drive (default), orbit or static (indoor: the drive path's first frames can show only
                 the rooms' outer walls, which face away from every light inside, leaving nothing to
                 check; the tests use orbit)
  --frames N     frames of the path (default 10)
  --size WxH     frame size (default 320x180)
  --lights N     lights in the scene (default 256)
  --seed S       scene seed (default 1)
  --bake FILE    static bake of this scene: its lights' maps then hold dynamic casters only
  --vsm-res N    virtual resolution (default 1024)
  --vsm-page N   page size (default 64)
  --vsm-pool N   physical pages (default 4096)
  --vsm-mark M   page marking: pixel (default: per receiver pixel) or cluster (per cluster and light)
  --vsm-texels T shadow texels per pixel footprint: 0.25, 0.5, 1 (default), 2, 4 or 8
  --pcf R        filter radius of the lookups (default 0; the check reads each kernel's centre texel)
  --vsm-raster R how pages are drawn: auto (default: vertex on CPU devices, mesh elsewhere), mesh or vertex
  --max-memory M peak memory allowed, MiB (default: half of this machine's memory); the estimate is
                 printed before the run, and a run past the limit is refused before it starts
Last stdout line: {"checked": N, "mismatches": M, ...}; exit 0 only when N > 0 and M == 0.
Directional lights' clip levels are checked against the orthographic reference rasteriser
(directional_checked counts their lookups). A differing shadow decision is not a mismatch when the
depths agree within the float-vs-double tolerance (the receiver sits on the caster) or the VSM's depth
is a neighbouring reference texel's (a triangle edge through the texel centre): ties_or_edges, printed.
)";

namespace {

// World-space triangles of the instances a map draws, transformed as vsm_draw.vert does (vsmPoint).
CasterTriangles mapCasters(const Scene& scene, bool dynamicOnly) {
    CasterTriangles t;
    for (const Instance& inst : scene.instances) {
        if (dynamicOnly && !inst.dynamic) continue;
        const Mesh& mesh = scene.meshes[inst.mesh];
        for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
            glm::vec3 p[3];
            for (int k = 0; k < 3; ++k)
                p[k] = diag::vsmCasterPoint(inst.transform, mesh.vertices[mesh.indices[i + k]].position);
            t.add(p[0], p[1], p[2], false); // open: only the enter depth is compared
        }
    }
    return t;
}

// What the check counted over the frames: the summary line's fields.
struct CheckCounts {
    uint64_t checked = 0, mismatches = 0, depthBeyondTolerance = 0, directionalChecked = 0, ties = 0,
             fallbacks = 0, noCaster = 0, missing = 0;
    uint32_t probeOverflow = 0;
};

// Whether the reference texel (x, y) or one of its eight neighbours holds `value` within `tol` (or is
// empty too, for an empty value).
bool neighbourHas(const DualDepthMap& ref, uint32_t x, uint32_t y, uint32_t value, uint64_t tol) {
    const uint32_t n = ref.resolution;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int nx = int(x) + dx, ny = int(y) + dy;
            if (nx < 0 || ny < 0 || nx >= int(n) || ny >= int(n)) continue;
            const uint32_t v = ref.enter[size_t(ny) * n + nx];
            if (value == kDepthEmpty
                    ? v == kDepthEmpty
                    : v != kDepthEmpty && uint64_t(std::llabs(int64_t(v) - int64_t(value))) <= tol)
                return true;
        }
    return false;
}

enum class Verdict { Agrees, TieOrEdge, Disagrees };

// The lookup is right when it gives the answer the full map gives: the same coverage and the same
// shadow test of the receiver's biased depth. Depths further apart than the float-vs-double
// interpolation tolerance of tests/gpu/dual_depth_test.cpp are counted apart (they decide nothing
// unless the receiver lies between them).
// Not an error of the page machinery when the two rasterisers may both be right: a tie (the receiver's
// biased depth lies between two depths within the float-vs-double tolerance: it sits on the caster) or
// an edge (the GPU's texel centre took a neighbouring reference texel's surface, or its emptiness,
// within tolerance: a triangle edge through the texel centre that the fixed-point reference puts on the
// other side). Counted apart, printed.
Verdict judgeProbe(const diag::VsmProbe& p, const DualDepthMap& ref, CheckCounts& c, bool& tie) {
    const uint32_t x = p.x, y = p.y, n = ref.resolution;
    const uint32_t want = ref.enter[size_t(y) * n + x], got = p.depth;
    const uint64_t baseTol = uint64_t(4294967294.0 * 2e-5);
    const uint32_t tap = p.receiverDepth;
    bool ok, edge = false;
    tie = false;
    if (p.status == diag::VsmProbeStatus::NoCaster) {
        ++c.noCaster;
        ok = want == kDepthEmpty;
    } else {
        c.fallbacks += p.status == diag::VsmProbeStatus::Fallback;
        if (want == kDepthEmpty || got == kDepthEmpty) {
            ok = want == got;
            edge = !ok && neighbourHas(ref, x, y, got, baseTol);
        } else {
            ok = (tap <= got) == (tap <= want);
            uint64_t step = 0;
            for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
                int nx = int(x) + dx, ny = int(y) + dy;
                if (nx < 0 || ny < 0 || nx >= int(n) || ny >= int(n)) continue;
                uint32_t v = ref.enter[size_t(ny) * n + nx];
                if (v != kDepthEmpty)
                    step = std::max<uint64_t>(step, uint64_t(std::llabs(int64_t(v) - int64_t(want))));
            }
            const uint64_t tol = baseTol + step / 64;
            const uint64_t diff = uint64_t(std::llabs(int64_t(got) - int64_t(want)));
            c.depthBeyondTolerance += diff > tol;
            tie = !ok && diff <= tol;
            edge = !ok && !tie && neighbourHas(ref, x, y, got, tol);
        }
    }
    return ok ? Verdict::Agrees : tie || edge ? Verdict::TieOrEdge : Verdict::Disagrees;
}

// One frame's probes against reference maps, per (map, mip): the probes sorted by map and mip, each
// reference rendered when its first probe comes and dropped after its last, so one reference map is
// held at a time (8 B a texel: 2 GiB at 16384^2; estimatePeak counts it).
Result<void> checkFrame(VsmSession& s, uint32_t f, uint32_t resolution, CheckCounts& c) {
    auto report = s.frame(f);
    if (!report) return fail(report.error());
    uint32_t overflow = 0;
    auto probes = diag::readVsmProbes(*s.module, &overflow);
    const std::vector<diag::VsmMap> maps = diag::vsmMaps(*s.module);
    c.probeOverflow += overflow;
    std::stable_sort(probes.begin(), probes.end(), [](const diag::VsmProbe& a, const diag::VsmProbe& b) {
        return std::make_pair(a.map, a.mip) < std::make_pair(b.map, b.mip);
    });
    std::optional<std::pair<uint32_t, uint32_t>> held; // the (map, mip) of `ref`
    DualDepthMap ref;
    size_t referenceMaps = 0;
    uint64_t frameMismatches = 0, frameTies = 0;
    for (const diag::VsmProbe& p : probes) {
        const uint32_t map = p.map, mip = p.mip;
        const diag::VsmMap& info = maps[map];
        if (p.status == diag::VsmProbeStatus::Missing) {
            ++c.missing;
            ++c.mismatches;
            ++frameMismatches;
            continue;
        }
        c.directionalChecked += info.orthographic;
        const auto key = std::make_pair(map, mip);
        if (held != key) {
            ref = DualDepthMap{}; // the previous reference's memory goes before the next is rendered
            DualRasterizer raster(mapCasters(s.scene, info.dynamicOnly), info.frustum, resolution >> mip);
            ref = raster.render();
            held = key;
            ++referenceMaps;
        }
        const uint32_t want = ref.enter[size_t(p.y) * ref.resolution + p.x];
        bool tie = false;
        const Verdict v = judgeProbe(p, ref, c, tie);
        ++c.checked;
        if (v == Verdict::TieOrEdge) {
            ++c.ties;
            if (++frameTies <= 3)
                std::fprintf(
                    stderr,
                    "  frame %u: map %u mip %u texel (%u, %u): %s: vsm %u, reference %u, receiver %u\n", f,
                    map, mip, p.x, p.y, tie ? "tie" : "edge", p.depth, want, p.receiverDepth);
        } else if (v == Verdict::Disagrees) {
            ++c.mismatches;
            if (++frameMismatches <= 3)
                std::fprintf(stderr,
                             "  frame %u: map %u mip %u texel (%u, %u): vsm %u, reference %u (status %u)\n",
                             f, map, mip, p.x, p.y, p.depth, want, uint32_t(p.status));
        }
    }
    std::fprintf(stderr, "frame %u: %zu lookups, %zu reference maps, %llu mismatches\n", f, probes.size(),
                 referenceMaps, (unsigned long long)frameMismatches);
    return {};
}

// check vsm's peak memory from its arguments: a measured base (device, lavapipe, the night city and
// its 256 lights' module state: ~0.5 GiB at 320x180), the targets and VSM state the module allocates
// (lavapipe's device memory is this process's), the probe records (on the device and read back), and
// one reference map (8 B a texel) with its rasteriser's row tiles (1 M texels of hit lists).
uint64_t estimatePeak(const VsmSessionOptions& o) {
    const VsmSettings& v = o.module.vsm;
    const uint64_t s0 = v.resolution / v.pageSize;
    const uint64_t entries = uint64_t(v.maxMaps) * (s0 * s0 * 4 / 3 + 1);
    const uint64_t vsm =
        entries * 4 * 2 + uint64_t(v.poolPages) * v.pageSize * v.pageSize * 4 * (v.staticLayer ? 2 : 1);
    const uint64_t probes = uint64_t(v.probeCapacity) * 48 * 2;
    const uint64_t reference = uint64_t(v.resolution) * v.resolution * 8 + (uint64_t(1) << 20) * 64;
    return (uint64_t(512) << 20) + diag::targetBytes(o.width, o.height, true) + vsm + probes + reference;
}

std::string summary(const CheckCounts& c, uint32_t frames, bool meshPath) {
    json::Object o;
    o.integer("checked", c.checked).integer("mismatches", c.mismatches);
    o.integer("depth_beyond_tolerance", c.depthBeyondTolerance).integer("fallbacks", c.fallbacks);
    o.integer("no_caster", c.noCaster).integer("missing", c.missing);
    o.integer("directional_checked", c.directionalChecked).integer("ties_or_edges", c.ties);
    o.integer("probe_overflow", c.probeOverflow).integer("frames", frames);
    return o.text("raster", meshPath ? "mesh" : "vertex").str();
}
} // namespace

// The flags of `check vsm` beside its option groups.
const cli::Flags kCheckFlags{{"--pcf", "--vsm-raster", "--max-memory"}, {}};

int runCheck(int argc, char** argv) {
    if (argc < 3 || std::string(argv[2]) == "--help" || std::string(argv[2]) == "-h") {
        std::fputs(kCheckHelp, argc < 3 ? stderr : stdout);
        return argc < 3 ? kExitUsage : 0;
    }
    if (std::string(argv[2]) != "vsm")
        return usageError("check", std::string("unknown check '") + argv[2] + "' (vsm)");
    int status = 0;
    const auto args =
        commandArgs("check vsm", kCheckHelp, parseVsmCommand(argc, argv, 3, kCheckFlags), status);
    if (!args) return status;
    uint32_t frameCount = 0;
    auto options = vsmSessionOptions(*args, {10, 1, "320x180", 1024}, frameCount);
    if (!options) return usageError("check vsm", options.error());
    auto pcf = cli::parseUint("--pcf", args->get("--pcf", "0"), 0, ML_MAX_PCF_RADIUS);
    if (!pcf) return usageError("check vsm", pcf.error());
    auto raster = vsmRaster(*args);
    if (!raster) return usageError("check vsm", raster.error());
    VsmSessionOptions o = options.value();
    o.module.vsm.probeCapacity = o.width * o.height * 8;
    o.module.vsm.raster = raster.value();
    auto limit = opts::maxMemory(*args);
    if (!limit) return usageError("check vsm", limit.error());
    if (auto r = opts::checkMemory("check vsm", estimatePeak(o), limit.value(),
                                   "one " + std::to_string(o.module.vsm.resolution) +
                                       "^2 reference map at a time, the module's targets and maps");
        !r)
        return usageError("check vsm", r.error());
    bool refused = false; // settings past the device's limits: a usage error (README, exit status)
    auto session = VsmSession::create(o, &refused);
    if (!session)
        return refused ? usageError("check vsm", session.error()) : runError("check vsm", session.error());
    VsmSession& s = *session.value();
    if (auto r = s.module->setShadowFilter(pcf.value()); !r) return usageError("check vsm", r.error());
    CheckCounts c;
    for (uint32_t f = 0; f < frameCount; ++f)
        if (auto r = checkFrame(s, f, o.module.vsm.resolution, c); !r)
            return runError("check vsm", r.error());
    if (s.module->deviceInfo().validation && validationErrors())
        std::fprintf(stderr, "manylights check vsm: %u validation messages\n", validationErrors());
    std::printf("%s\n", summary(c, frameCount, diag::vsmMeshPath(*s.module)).c_str());
    return c.checked > 0 && c.mismatches == 0 && c.probeOverflow == 0 ? 0 : kExitRun;
}

} // namespace ml
