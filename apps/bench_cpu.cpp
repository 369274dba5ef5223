// `manylights bench cpu`: the module's own CPU time per frame, the share an engine's frame budget pays
// (a millisecond or two). The night city with N lights plus small boxes up to M instances in all, a
// fraction F of them dynamic and moved every frame. Timed per frame on the host clock:
//   update  the host's calls for the frame (setInstanceTransform of the moving boxes, setCamera);
//   record  Module::record into a command buffer (uploads, VSM preparation, the passes' commands);
//   vsm     the part of record spent in VirtualShadowMaps::prepare (diag::vsmPrepareMs).
// The GPU never runs while the clock does: each frame is submitted after its record() is timed and
// waited for before the next one starts (on lavapipe the "GPU" is this machine's CPU, so overlap would
// bill its work to the host). --no-submit records every frame without submitting it (the state then
// stops evolving after the warm-up: a floor of the record cost). Table on stdout, then one JSON line:
// {"record_ms_median": ..., "record_ms_max": ..., "update_ms_median": ..., ...}.
#include "apps/commands.h"
#include "apps/options.h"
#include "engine/manylights_diagnostics.h"
#include "host/scene_host.h"
#include "scenes/mesh_utils.h"
#include "scenes/scenes.h"
#include "shaders/shared/config.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace ml {

static const char* kBenchCpuHelp = R"(usage: manylights bench cpu [options]
The module's CPU time per frame (host clock, the GPU idle while it runs): the host's per-frame calls
and Module::record. Every flag may be given once; a flag's value cannot be another flag.
  --lights N       lights in the night city (default 4096)
  --instances M    instances in all: the city's plus small boxes (default 10000)
  --moving F       fraction of the instances that are dynamic boxes moved every frame (default 0.01)
  --frames K       timed frames (default 30; two warm-up frames before them)
  --size WxH       frame size (default 320x180)
  --seed S         scene seed (default 1)
  --vsm on|off     virtual shadow maps (default on)
  --no-submit      record without submitting (after the warm-up): the record cost with no GPU work
The row "vsm" is the part of record spent preparing the virtual shadow maps (0 with --vsm off).
Last stdout line: {"record_ms_median": ..., "record_ms_max": ..., "update_ms_median": ...,
"vsm_prepare_ms_median": ..., "lights": ..., "instances": ..., "moving": ...}
)";

namespace {

double msBetween(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

// Boxes on a grid over the city's ground, 0.5 m, above the ground so they cast on it.
glm::mat4 boxAt(const Scene& s, uint32_t i, uint32_t count, float phase) {
    const uint32_t side = uint32_t(std::ceil(std::sqrt(double(count))));
    const glm::vec3 lo = s.boundsMin, hi = s.boundsMax;
    const float fx = (float(i % side) + 0.5f) / float(side), fz = (float(i / side) + 0.5f) / float(side);
    glm::vec3 p(lo.x + fx * (hi.x - lo.x), lo.y + 1.0f + 0.25f * std::sin(phase + float(i)),
                lo.z + fz * (hi.z - lo.z));
    glm::mat4 m(0.5f);
    m[3] = glm::vec4(p, 1.0f);
    return m;
}

} // namespace

int runBenchCpu(int argc, char** argv) {
    int status = 0;
    const cli::Flags own{{"--lights", "--instances", "--moving", "--vsm"}, {"--no-submit"}};
    const auto args = commandArgs(
        "bench", kBenchCpuHelp, cli::parse(argc, argv, 3, {opts::kSeedFlags, opts::kViewFlags, own}), status);
    if (!args) return status;
    auto view = opts::view(*args, {30, 1, 100000, "320x180"});
    auto lights = cli::parseUint("--lights", args->get("--lights", "4096"), 1, ML_MAX_LIGHTS);
    auto instances = cli::parseUint("--instances", args->get("--instances", "10000"), 1, 1000000);
    auto moving = opts::number("--moving", args->get("--moving", "0.01"), 0.0f, 1.0f);
    auto seed = opts::seed(*args);
    const std::string vsm = args->get("--vsm", "on");
    for (const std::string* e :
         {&view.error(), &lights.error(), &instances.error(), &moving.error(), &seed.error()})
        if (!e->empty()) return usageError("bench", *e);
    if (vsm != "on" && vsm != "off") return usageError("bench", "--vsm must be on or off, got '" + vsm + "'");
    const bool submit = !args->switches.count("--no-submit");

    auto loaded = loadScene("night-city", lights.value(), seed.value());
    if (!loaded) return runError("bench", loaded.error());
    Scene scene = std::move(loaded.value());
    const uint32_t cityInstances = uint32_t(scene.instances.size());
    if (instances.value() < cityInstances)
        return usageError("bench", "--instances " + std::to_string(instances.value()) +
                                       " is below the night city's own " + std::to_string(cityInstances));
    const uint32_t boxes = instances.value() - cityInstances;
    const uint32_t movers = std::min(boxes, uint32_t(std::lround(moving.value() * instances.value())));
    const uint32_t boxMesh = uint32_t(scene.meshes.size());
    scene.meshes.push_back(detail::makeUnitBox());
    for (uint32_t i = 0; i < boxes; ++i) {
        Instance inst;
        inst.mesh = boxMesh;
        inst.transform = boxAt(scene, i, boxes, 0.0f);
        inst.dynamic = i < movers;
        scene.instances.push_back(inst);
    }

    ModuleOptions options;
    options.vsm.enabled = vsm == "on";
    options.timing = TimingChoice::Timestamps; // the frame in one command buffer, as a host records it
    auto module = Module::create(options);
    if (!module) return runError("bench", module.error());
    Module& m = *module.value();
    auto binding = bindScene(m, scene);
    if (!binding) return runError("bench", binding.error());
    if (auto r = m.createTargets(view->width, view->height); !r) return usageError("bench", r.error());

    const DeviceInfo info = m.deviceInfo();
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.queueFamilyIndex = info.queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    if (vkCreateCommandPool(info.device, &pci, nullptr, &pool) != VK_SUCCESS)
        return runError("bench", "vkCreateCommandPool failed");
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vkAllocateCommandBuffers(info.device, &ai, &cmd);

    std::vector<double> recordMs, updateMs, vsmMs;
    const uint32_t warmup = 2;
    int rc = 0;
    for (uint32_t f = 0; f < warmup + view->frames && rc == 0; ++f) {
        const auto t0 = std::chrono::steady_clock::now();
        for (uint32_t i = 0; i < movers; ++i) {
            auto r = m.setInstanceTransform(binding->instances[cityInstances + i],
                                            boxAt(scene, i, boxes, 0.1f * float(f)));
            if (!r) rc = runError("bench", r.error());
        }
        CameraDesc cam = toCameraDesc(scene.camera);
        cam.position =
            toGlm(cam.position) + glm::vec3(0.05f * float(f), 0.0f, 0.0f); // a moving camera: marks change
        cam.target = toGlm(cam.target) + glm::vec3(0.05f * float(f), 0.0f, 0.0f);
        if (auto r = m.setCamera(cam); !r) rc = runError("bench", r.error());
        const auto t1 = std::chrono::steady_clock::now();
        vkResetCommandPool(info.device, pool, 0);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkBeginCommandBuffer(cmd, &bi);
        const auto t2 = std::chrono::steady_clock::now();
        auto r = m.record(cmd);
        const auto t3 = std::chrono::steady_clock::now();
        vkEndCommandBuffer(cmd);
        if (!r) rc = runError("bench", r.error());
        if (f >= warmup) {
            updateMs.push_back(msBetween(t0, t1));
            recordMs.push_back(msBetween(t2, t3));
            vsmMs.push_back(diag::vsmPrepareMs(m));
        }
        if (submit || f < warmup) {
            VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
            si.commandBufferCount = 1;
            si.pCommandBuffers = &cmd;
            vkQueueSubmit(info.queue, 1, &si, VK_NULL_HANDLE);
            vkQueueWaitIdle(info.queue); // outside the timed spans
            m.collect();
            m.takeReports();
        }
    }
    vkQueueWaitIdle(info.queue);
    vkDestroyCommandPool(info.device, pool, nullptr);
    if (rc) return rc;

    const double recMed = percentile(recordMs, 0.5), recMax = percentile(recordMs, 1.0);
    const double updMed = percentile(updateMs, 0.5), updMax = percentile(updateMs, 1.0);
    const double vsmMed = percentile(vsmMs, 0.5), vsmMax = percentile(vsmMs, 1.0);
    std::printf(
        "bench cpu: night-city, %u lights, %u instances (%u moving), %ux%u, vsm %s, %u frames, %s, %s\n",
        lights.value(), instances.value(), movers, view->width, view->height, vsm.c_str(), view->frames,
        submit ? "each submitted and waited for" : "recorded only", info.name.c_str());
    std::printf("| span   | median ms | max ms |\n|--------|----------:|-------:|\n");
    std::printf("| update | %9.3f | %6.3f |\n| record | %9.3f | %6.3f |\n", updMed, updMax, recMed, recMax);
    std::printf("| vsm    | %9.3f | %6.3f |\n", vsmMed, vsmMax);
    std::printf("{\"record_ms_median\": %.4f, \"record_ms_max\": %.4f, \"update_ms_median\": %.4f, "
                "\"update_ms_max\": %.4f, \"vsm_prepare_ms_median\": %.4f, \"vsm_prepare_ms_max\": %.4f, "
                "\"lights\": %u, \"instances\": %u, \"moving\": %u, \"vsm\": %s, "
                "\"submitted\": %s, \"frames\": %u}\n",
                recMed, recMax, updMed, updMax, vsmMed, vsmMax, lights.value(), instances.value(), movers,
                vsm == "on" ? "true" : "false", submit ? "true" : "false", view->frames);
    return 0;
}

} // namespace ml
