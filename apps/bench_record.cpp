// `manylights bench record`: Module::record's CPU time on the frames that do more than the steady ones,
// frame 0 (every buffer's first fill, recorded into the frame's command buffer) and the first frame after
// an LDR <-> HDR switch (whose evaluation pipelines createTargets builds ahead), beside the steady frames.
// Each run makes a module on its own device (no validation layer unless ML_VALIDATION asks for it: the
// JSON says which), binds the night city, creates the targets and times record() on the host clock, the
// GPU idle meanwhile (each frame is submitted and waited for after its record() was timed: on lavapipe the
// GPU is this machine's CPU). Fails (exit 3) when record() submits, waits or builds a pipeline (the module's
// counters), or with --limit-ms when frame 0 or a switch frame's median passes the limit.
#include "apps/commands.h"
#include "apps/options.h"
#include "engine/manylights_diagnostics.h"
#include "host/scene_host.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "shaders/shared/config.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sstream>

namespace ml {

static const char* kBenchRecordHelp = R"(usage: manylights bench record [options]
Module::record's CPU time (host clock, the GPU idle while it runs, no validation layer unless
ML_VALIDATION is set) for frame 0, the steady frames, and the first frame after LDR -> HDR and after
HDR -> LDR (setHdrOutput), over --runs fresh modules on the night city. Every flag may be given once;
a flag's value cannot be another flag.
  --lights N       lights in the night city (default 256)
  --size WxH       targets (default 1280x720)
  --frames K       steady frames timed per run (default 20)
  --runs R         fresh modules, each timing frame 0 and both switches (default 3)
  --seed S         scene seed (default 1)
  --vsm on|off     virtual shadow maps (default on)
  --limit-ms X     fail (exit 3) when the CPU median of frame 0 or of a switch frame exceeds X ms (default:
                   no limit)
  --csv FILE       one row per run (default out/bench_record.csv)
Fails (exit 3) whenever record() submits, waits or builds a pipeline (diag::queueAccessCounts).
Each time is the calling thread's CPU time and the wall time (on a loaded machine a preemption adds a
scheduler tick to the wall time). --limit-ms applies to the CPU medians.
Last stdout line: {"frame0_cpu_ms_median": ..., "frame0_wall_ms_median": ..., "steady_cpu_ms_median":
..., "to_hdr_cpu_ms_median": ..., "to_ldr_cpu_ms_median": ..., ..., "validation": false}
)";

namespace {

// The module's own device turns the layer on from the environment alone here (gpu/device.cpp reads the
// same variables): a timing taken with it on is not the figure the help promises, so the output says so.
bool validationFromEnvironment() {
    for (const char* name : {"ML_VALIDATION", "ML_VALIDATION_SYNC"}) {
        const char* v = std::getenv(name);
        if (v && *v && std::string(v) != "0") return true;
    }
    return false;
}

// record()'s time: CPU time of the calling thread (what --limit-ms bounds: on a loaded machine a
// preemption adds a scheduler tick, 4 ms at 250 Hz, to the wall time of a 1 ms call) and wall time.
struct Ms {
    double cpu = 0, wall = 0;
};
struct RunTimes {
    Ms frame0, steady, toHdr, toLdr;
    double createTargets = 0;
};

double threadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
double maxOf(const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}
double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// One fresh module: frame 0, `frames` steady frames, the first HDR frame, the first LDR frame again.
Result<RunTimes> oneRun(const Scene& scene, uint32_t width, uint32_t height, uint32_t frames, bool vsm,
                        std::string& deviceName, bool& validation) {
    ModuleOptions options;
    options.vsm.enabled = vsm;
    options.timing = TimingChoice::Timestamps; // the frame in the host's command buffer, as a host records it
    auto module = Module::create(options);
    if (!module) return fail(module.error());
    Module& m = *module.value();
    deviceName = m.deviceInfo().name;
    validation = validationFromEnvironment();
    auto binding = bindScene(m, scene);
    if (!binding) return fail(binding.error());
    RunTimes t;
    const auto targetsStart = std::chrono::steady_clock::now();
    if (auto r = m.createTargets(width, height); !r) return fail(r.error());
    t.createTargets = msSince(targetsStart);
    if (auto r = m.setCamera(toCameraDesc(scene.camera)); !r) return fail(r.error());

    const DeviceInfo info = m.deviceInfo();
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.queueFamilyIndex = info.queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    if (vkCreateCommandPool(info.device, &pci, nullptr, &pool) != VK_SUCCESS)
        return fail("vkCreateCommandPool failed");
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vkAllocateCommandBuffers(info.device, &ai, &cmd);
    std::string error;
    // One frame: record() timed alone, then submitted and waited for (outside the timed span).
    auto frame = [&]() -> Ms {
        vkResetCommandPool(info.device, pool, 0);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkBeginCommandBuffer(cmd, &bi);
        const auto start = std::chrono::steady_clock::now();
        const double cpuStart = threadCpuMs();
        auto r = m.record(cmd);
        const Ms ms{threadCpuMs() - cpuStart, msSince(start)};
        vkEndCommandBuffer(cmd);
        if (!r && error.empty()) error = r.error();
        if (r) {
            VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
            si.commandBufferCount = 1;
            si.pCommandBuffers = &cmd;
            vkQueueSubmit(info.queue, 1, &si, VK_NULL_HANDLE);
            vkQueueWaitIdle(info.queue);
            m.collect();
            m.takeReports();
        }
        return ms;
    };
    t.frame0 = frame();
    std::vector<double> steadyCpu, steadyWall;
    for (uint32_t i = 0; i < frames; ++i) {
        const Ms ms = frame();
        steadyCpu.push_back(ms.cpu), steadyWall.push_back(ms.wall);
    }
    t.steady = {median(steadyCpu), median(steadyWall)};
    Result<void> switched = m.setHdrOutput(true);
    if (switched) t.toHdr = frame();
    for (int i = 0; i < 2 && switched; ++i) frame();
    if (switched) switched = m.setHdrOutput(false);
    if (switched) t.toLdr = frame();
    vkQueueWaitIdle(info.queue);
    vkDestroyCommandPool(info.device, pool, nullptr);
    if (!switched) return fail("setHdrOutput: " + switched.error());
    if (!error.empty()) return fail(error);
    const auto q = diag::queueAccessCounts(m);
    if (q.recordSubmits || q.recordWaits || q.recordPipelines)
        return fail("record() made " + std::to_string(q.recordSubmits) + " submits, " +
                    std::to_string(q.recordWaits) + " waits and " + std::to_string(q.recordPipelines) +
                    " pipeline builds (must be 0)");
    return t;
}

} // namespace

int runBenchRecord(int argc, char** argv) {
    int status = 0;
    const cli::Flags own{{"--lights", "--runs", "--vsm", "--limit-ms", "--csv"}, {}};
    const auto args =
        commandArgs("bench", kBenchRecordHelp,
                    cli::parse(argc, argv, 3, {opts::kSeedFlags, opts::kViewFlags, own}), status);
    if (!args) return status;
    auto view = opts::view(*args, {20, 1, 100000, "1280x720"});
    auto lights = cli::parseUint("--lights", args->get("--lights", "256"), 1, ML_MAX_LIGHTS);
    auto runs = cli::parseUint("--runs", args->get("--runs", "3"), 1, 1000);
    auto limit = opts::number("--limit-ms", args->get("--limit-ms", "0"), 0.0f, 1.0e6f);
    auto seed = opts::seed(*args);
    for (const std::string* e :
         {&view.error(), &lights.error(), &runs.error(), &limit.error(), &seed.error()})
        if (!e->empty()) return usageError("bench", *e);
    const std::string vsm = args->get("--vsm", "on");
    if (vsm != "on" && vsm != "off") return usageError("bench", "--vsm must be on or off, got '" + vsm + "'");
    const std::string csvPath = args->get("--csv", "out/bench_record.csv");
    if (auto r = cli::checkOutputFile("--csv", csvPath); !r) return usageError("bench", r.error());

    auto scene = loadScene("night-city", lights.value(), seed.value());
    if (!scene) return runError("bench", scene.error());
    std::vector<RunTimes> times;
    std::string deviceName;
    bool validation = false;
    for (uint32_t i = 0; i < runs.value(); ++i) {
        auto t = oneRun(scene.value(), view->width, view->height, view->frames, vsm == "on", deviceName,
                        validation);
        if (!t) return runError("bench", "run " + std::to_string(i) + ": " + t.error());
        times.push_back(t.value());
    }
    // Per quantity: the runs' CPU and wall times.
    struct Column {
        std::vector<double> cpu, wall;
        void add(const Ms& m) { cpu.push_back(m.cpu), wall.push_back(m.wall); }
    } f0, st, hdr, ldr;
    std::vector<double> ct;
    std::ostringstream csv;
    csv << "run,create_targets_ms,frame0_cpu_ms,frame0_wall_ms,steady_cpu_ms,steady_wall_ms,to_hdr_cpu_ms,"
           "to_hdr_wall_ms,to_ldr_cpu_ms,to_ldr_wall_ms\n";
    for (size_t i = 0; i < times.size(); ++i) {
        const RunTimes& t = times[i];
        f0.add(t.frame0), st.add(t.steady), hdr.add(t.toHdr), ldr.add(t.toLdr);
        ct.push_back(t.createTargets);
        csv << i << "," << t.createTargets;
        for (const Ms& m : {t.frame0, t.steady, t.toHdr, t.toLdr}) csv << "," << m.cpu << "," << m.wall;
        csv << "\n";
    }
    std::printf("bench record: night-city, %u lights, %ux%u, vsm %s, %u runs of %u steady frames, validation "
                "%s, %s\n",
                lights.value(), view->width, view->height, vsm.c_str(), runs.value(), view->frames,
                validation ? "on" : "off", deviceName.c_str());
    std::printf("| record() ms over the runs     | CPU median | CPU max | wall median | wall max |\n"
                "|-------------------------------|-----------:|--------:|------------:|---------:|\n");
    for (auto [name, c] : {std::pair<const char*, const Column*>{"frame 0", &f0},
                           {"steady (median of each run)", &st},
                           {"first frame LDR -> HDR", &hdr},
                           {"first frame HDR -> LDR", &ldr}})
        std::printf("| %-29s | %10.3f | %7.3f | %11.3f | %8.3f |\n", name, median(c->cpu), maxOf(c->cpu),
                    median(c->wall), maxOf(c->wall));
    std::printf("createTargets (builds the pipelines; not a frame): median %.1f ms\n", median(ct));
    if (auto w = io::writeFileAtomically(csvPath, csv.str()); !w) return runError("bench", w.error());
    std::printf("wrote %s\n", csvPath.c_str());
    std::printf(
        "{\"frame0_cpu_ms_median\": %.4f, \"frame0_cpu_ms_max\": %.4f, \"frame0_wall_ms_median\": %.4f, "
        "\"frame0_wall_ms_max\": %.4f, \"steady_cpu_ms_median\": %.4f, \"to_hdr_cpu_ms_median\": %.4f, "
        "\"to_hdr_cpu_ms_max\": %.4f, \"to_hdr_wall_ms_median\": %.4f, \"to_ldr_cpu_ms_median\": %.4f, "
        "\"to_ldr_cpu_ms_max\": %.4f, \"to_ldr_wall_ms_median\": %.4f, \"create_targets_ms_median\": %.1f, "
        "\"lights\": %u, \"width\": %u, \"height\": %u, \"runs\": %u, \"validation\": %s}\n",
        median(f0.cpu), maxOf(f0.cpu), median(f0.wall), maxOf(f0.wall), median(st.cpu), median(hdr.cpu),
        maxOf(hdr.cpu), median(hdr.wall), median(ldr.cpu), maxOf(ldr.cpu), median(ldr.wall), median(ct),
        lights.value(), view->width, view->height, runs.value(), validation ? "true" : "false");
    const double limitMs = limit.value();
    if (limitMs > 0)
        for (auto [name, v] : {std::pair{"frame 0", median(f0.cpu)},
                               {"LDR -> HDR", median(hdr.cpu)},
                               {"HDR -> LDR", median(ldr.cpu)}})
            if (v > limitMs)
                return runError("bench", std::string("record() ") + name + " CPU median " +
                                             std::to_string(v) + " ms exceeds --limit-ms " +
                                             std::to_string(limitMs));
    return 0;
}

} // namespace ml
