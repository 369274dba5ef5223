// `manylights bench soak`: a long run of a host's frame loop whose memory must stay flat. A small scene
// (a ground, static boxes, one box moved every frame), lights switched off (removeLight) and back on
// (addLight, so light slots and their shadow maps are freed and reused), their shadow casting toggled,
// the output switched LDR <-> HDR, two frames in flight with the host's fences. The scene's changes repeat
// with a period of kPeriod frames, and both samples are taken at the same phase, so a flat module holds the
// same lights and buffers at both. Samples: VmRSS of this process (/proc/self/status; on a CPU device such
// as lavapipe it includes the "GPU" memory) and the module's live buffer and image bytes (FrameStats::
// memory), once after the warm-up and at the end. Fails (exit 3) when either grows by --limit-pct or more.
#include "apps/commands.h"
#include "apps/options.h"
#include "host/scene_host.h"
#include "io/safe_io.h"
#include "scenes/mesh_utils.h"

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

namespace ml {

static const char* kBenchSoakHelp = R"(usage: manylights bench soak [options]
A host's frame loop for --frames frames (two in flight, host fences): lights switched off and on, their
shadow casting toggled, a moving caster, LDR <-> HDR every 50 frames, virtual shadow maps on. Resident
memory (VmRSS) and the module's live GPU bytes are sampled after --warmup frames and at the end; fails
(exit 3) when either grew by --limit-pct % or more. Every flag may be given once; a flag's value cannot
be another flag.
  --frames N       frames in all (default 10000; a multiple of 200)
  --warmup W       frames before the first sample (default 1000; a multiple of 200, below --frames)
  --size WxH       targets (default 64x64)
  --lights L       lights in the scene at most (default 16)
  --limit-pct P    growth that fails the run, in % (default 1)
  --csv FILE       VmRSS and GPU bytes every 200 frames (default out/bench_soak.csv)
  --plant-leak K   keep K KiB of host memory more every 200 frames (a leak the run must catch: the
                   check that the soak can fail)
Last stdout line: {"frames": ..., "rss_kib_warm": ..., "rss_kib_end": ..., "rss_growth_pct": ...,
"gpu_bytes_warm": ..., "gpu_bytes_end": ..., "gpu_growth_pct": ..., ...}
)";

namespace {

constexpr uint32_t kPeriod = 200; // frames after which the scene's changes repeat

uint64_t residentKiB() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::stoull(line.substr(6));
    return 0;
}

MeshDesc meshOf(const std::vector<MeshVertex>& v, const std::vector<uint32_t>& i, bool closed,
                const char* name) {
    return {v, i, closed, name};
}

// Light i of the ring, its kind and motion fixed by i (the same light each time it is switched back on).
LightDesc ringLight(uint32_t i, uint32_t count, bool casts) {
    LightDesc l;
    const float a = 6.2831853f * float(i) / float(count);
    l.kind = i % 3 == 2 ? LightKind::Point : LightKind::Spot;
    l.position = {4.0f * std::cos(a), 4.0f, 4.0f * std::sin(a)};
    l.direction = {-0.3f * std::cos(a), -1.0f, -0.3f * std::sin(a)};
    l.range = 9.0f;
    l.intensity = 4.0f;
    l.color = {0.5f + 0.5f * std::cos(a), 0.8f, 0.5f + 0.5f * std::sin(a)};
    l.dynamic = i % 2 == 1;
    l.castsShadows = casts;
    return l;
}

} // namespace

int runBenchSoak(int argc, char** argv) {
    int status = 0;
    const cli::Flags own{{"--warmup", "--lights", "--limit-pct", "--csv", "--plant-leak"}, {}};
    const auto args =
        commandArgs("bench", kBenchSoakHelp, cli::parse(argc, argv, 3, {opts::kViewFlags, own}), status);
    if (!args) return status;
    auto view = opts::view(*args, {10000, kPeriod, 10000000, "64x64"});
    auto warmup = cli::parseUint("--warmup", args->get("--warmup", "1000"), kPeriod, 10000000);
    auto lights = cli::parseUint("--lights", args->get("--lights", "16"), 2, 256);
    auto limit = opts::number("--limit-pct", args->get("--limit-pct", "1"), 0.0f, 100.0f);
    auto leak = cli::parseUint("--plant-leak", args->get("--plant-leak", "0"), 0, 1u << 20);
    for (const std::string* e :
         {&view.error(), &warmup.error(), &lights.error(), &limit.error(), &leak.error()})
        if (!e->empty()) return usageError("bench", *e);
    const uint32_t frames = view->frames, warm = warmup.value(), count = lights.value();
    if (frames % kPeriod || warm % kPeriod)
        return usageError("bench", "--frames and --warmup must be multiples of " + std::to_string(kPeriod) +
                                       " (the scene's period: both samples at the same phase)");
    if (warm >= frames) return usageError("bench", "--warmup must be below --frames");
    const std::string csvPath = args->get("--csv", "out/bench_soak.csv");
    if (auto r = cli::checkOutputFile("--csv", csvPath); !r) return usageError("bench", r.error());

    ModuleOptions options;
    options.timing = TimingChoice::Timestamps; // recorded into the host's command buffers
    options.framesInFlight = 2;
    options.vsm.enabled = true;
    options.vsm.resolution = 1024;
    options.vsm.poolPages = 256;
    auto module = Module::create(options);
    if (!module) return runError("bench", module.error());
    Module& m = *module.value();
    const DeviceInfo info = m.deviceInfo();

    const std::vector<MeshVertex> ground = {
        {{-8, 0, -8}, {0, 1, 0}}, {{8, 0, -8}, {0, 1, 0}}, {{8, 0, 8}, {0, 1, 0}}, {{-8, 0, 8}, {0, 1, 0}}};
    const std::vector<uint32_t> groundIdx = {0, 2, 1, 0, 3, 2};
    const Mesh unit = detail::makeUnitBox();
    std::vector<MeshVertex> boxV;
    for (const Vertex& v : unit.vertices)
        boxV.push_back({{v.position.x, v.position.y, v.position.z}, {v.normal.x, v.normal.y, v.normal.z}});
    auto groundId = m.addMesh(meshOf(ground, groundIdx, false, "ground"));
    auto boxId = m.addMesh(meshOf(boxV, unit.indices, true, "box"));
    if (!groundId || !boxId) return runError("bench", groundId ? boxId.error() : groundId.error());
    if (auto r = m.addInstance(groundId.value(), glm::mat4(1.0f), Float3(0.6f), false); !r)
        return runError("bench", r.error());
    for (int i = 0; i < 6; ++i) {
        const glm::mat4 t = glm::scale(
            glm::translate(glm::mat4(1.0f), {-3.0f + 1.2f * float(i), 0.5f, -1.0f}), glm::vec3(0.5f));
        if (auto r = m.addInstance(boxId.value(), t, Float3(0.5f), false); !r)
            return runError("bench", r.error());
    }
    auto mover = m.addInstance(boxId.value(), glm::mat4(1.0f), Float3(0.7f), true);
    if (!mover) return runError("bench", mover.error());
    std::vector<std::optional<LightId>> on(count);
    for (uint32_t i = 0; i < count; ++i) {
        auto id = m.addLight(ringLight(i, count, true));
        if (!id) return runError("bench", id.error());
        on[i] = id.value();
    }
    if (auto r = m.createTargets(view->width, view->height); !r) return usageError("bench", r.error());
    if (auto r = m.setCamera({{0, 9, 11}, {0, 0, 0}}); !r) return runError("bench", r.error());

    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = info.queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    if (vkCreateCommandPool(info.device, &pci, nullptr, &pool) != VK_SUCCESS)
        return runError("bench", "vkCreateCommandPool failed");
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 2;
    VkCommandBuffer cmd[2]{};
    VkFence fences[2]{};
    vkAllocateCommandBuffers(info.device, &ai, cmd);
    for (VkFence& f : fences) {
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, nullptr, VK_FENCE_CREATE_SIGNALED_BIT};
        vkCreateFence(info.device, &fci, nullptr, &f);
    }

    std::ostringstream csv;
    csv << "frame,rss_kib,gpu_bytes\n";
    uint64_t rssWarm = 0, rssEnd = 0, gpuWarm = 0, gpuEnd = 0, gpuLast = 0;
    std::string error;
    std::vector<std::vector<uint8_t>> leaked; // --plant-leak
    const auto start = std::chrono::steady_clock::now();
    // Both frames in flight done, the newest report collected: the module's live bytes and VmRSS.
    auto sample = [&](uint64_t& rss, uint64_t& gpu) {
        vkWaitForFences(info.device, 2, fences, VK_TRUE, UINT64_MAX);
        m.collect();
        for (const FrameReport& r : m.takeReports()) {
            gpu = 0;
            for (uint64_t b : r.stats.memory.bytes) gpu += b;
        }
        rss = residentKiB();
    };
    for (uint32_t f = 0; f < frames && error.empty(); ++f) {
        // Samples at phase 0, before the period's first change: the warm one and, after the loop, the end.
        if (f % kPeriod == 0 && f > 0) {
            uint64_t rss = 0;
            sample(rss, gpuLast);
            csv << f << "," << rss << "," << gpuLast << "\n";
            if (f == warm) rssWarm = rss, gpuWarm = gpuLast;
            if (leak.value()) { // touched, so that it is resident
                leaked.emplace_back(size_t(leak.value()) * 1024, uint8_t(f));
            }
            if (f % 1000 == 0)
                std::fprintf(stderr, "  frame %u: VmRSS %llu KiB, module GPU bytes %llu\n", f,
                             (unsigned long long)rss, (unsigned long long)gpuLast);
        }
        const uint32_t phase = f % kPeriod;
        // Light (phase / 2) % count goes off on even phases and back on, casting or not, on odd ones.
        const uint32_t li = (phase / 2) % count;
        if (phase % 2 == 0 && on[li]) {
            if (auto r = m.removeLight(*on[li]); !r) error = r.error();
            on[li].reset();
        } else if (phase % 2 == 1 && !on[li]) {
            auto id = m.addLight(ringLight(li, count, phase % 4 != 1 || li % 5 != 0));
            if (!id)
                error = id.error();
            else
                on[li] = id.value();
        }
        if (phase % 50 == 25) // LDR <-> HDR, back to LDR at the period's end
            if (auto r = m.setHdrOutput(!m.hdrOutput()); !r) error = r.error();
        const float a = 6.2831853f * float(phase) / float(kPeriod);
        const glm::mat4 t = glm::scale(
            glm::translate(glm::mat4(1.0f), {2.5f * std::cos(a), 1.0f, 2.5f * std::sin(a)}), glm::vec3(0.4f));
        if (auto r = m.setInstanceTransform(mover.value(), t); !r) error = r.error();

        const uint32_t slot = f % 2;
        vkWaitForFences(info.device, 1, &fences[slot], VK_TRUE, UINT64_MAX);
        m.collect();
        m.takeReports();
        vkResetCommandBuffer(cmd[slot], 0);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkBeginCommandBuffer(cmd[slot], &bi);
        auto r = m.record(cmd[slot]);
        vkEndCommandBuffer(cmd[slot]);
        if (!r) {
            error = r.error();
            break;
        }
        vkResetFences(info.device, 1, &fences[slot]);
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd[slot];
        vkQueueSubmit(info.queue, 1, &si, fences[slot]);
    }
    sample(rssEnd, gpuEnd);
    csv << frames << "," << rssEnd << "," << gpuEnd << "\n";
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (VkFence fnc : fences) vkDestroyFence(info.device, fnc, nullptr);
    vkDestroyCommandPool(info.device, pool, nullptr);
    if (!error.empty()) return runError("bench", error);

    const double rssPct = rssWarm ? 100.0 * (double(rssEnd) - double(rssWarm)) / double(rssWarm) : 0.0;
    const double gpuPct = gpuWarm ? 100.0 * (double(gpuEnd) - double(gpuWarm)) / double(gpuWarm) : 0.0;
    std::printf("bench soak: %u frames (%u warm-up), %ux%u, %u lights switched off and on, %.1f s, %s\n",
                frames, warm, view->width, view->height, count, seconds, info.name.c_str());
    std::printf("| sample            | after warm-up |        at end | growth %% "
                "|\n|-------------------|--------------:|--------------:|---------:|\n");
    std::printf("| VmRSS KiB         | %13llu | %13llu | %8.3f |\n", (unsigned long long)rssWarm,
                (unsigned long long)rssEnd, rssPct);
    std::printf("| module GPU bytes  | %13llu | %13llu | %8.3f |\n", (unsigned long long)gpuWarm,
                (unsigned long long)gpuEnd, gpuPct);
    if (auto w = io::writeFileAtomically(csvPath, csv.str()); !w) return runError("bench", w.error());
    std::printf("wrote %s\n", csvPath.c_str());
    std::printf(
        "{\"frames\": %u, \"warmup\": %u, \"rss_kib_warm\": %llu, \"rss_kib_end\": %llu, \"rss_growth_pct\": "
        "%.4f, "
        "\"gpu_bytes_warm\": %llu, \"gpu_bytes_end\": %llu, \"gpu_growth_pct\": %.4f, \"limit_pct\": %.2f, "
        "\"seconds\": %.1f}\n",
        frames, warm, (unsigned long long)rssWarm, (unsigned long long)rssEnd, rssPct,
        (unsigned long long)gpuWarm, (unsigned long long)gpuEnd, gpuPct, double(limit.value()), seconds);
    if (gpuWarm == 0) return runError("bench", "no frame report arrived before the warm-up sample");
    if (rssPct >= limit.value() || gpuPct >= limit.value())
        return runError("bench", "memory grew: VmRSS " + std::to_string(rssPct) + " %, module GPU bytes " +
                                     std::to_string(gpuPct) + " % (limit " + std::to_string(limit.value()) +
                                     " %)");
    return 0;
}

} // namespace ml
