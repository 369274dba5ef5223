// `manylights demo`: renders a scene (the night city by default) with the module, headless, and writes
// frame_NNNN.png, profile.json, frames.csv and stats.json into --out. A host of the public API only.
#include "apps/commands.h"
#include "apps/options.h"
#include "apps/report.h"
#include "apps/vsm_args.h"
#include "apps/window.h"
#include "host/scene_host.h"
#include "scenes/camera_path.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "shadows/static/cpvs.h"
#include "shaders/shared/config.h"

#include <GLFW/glfw3.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ml {

namespace {
// The window title: culling mode and the newest frame's GPU milliseconds per pass.
std::string windowTitle(CullingMode mode, const FrameReport& r) {
    std::string t = std::string("manylights | ") + cullingName(mode);
    char buf[64];
    for (const PassTime& p : r.times.passes) {
        std::snprintf(buf, sizeof(buf), " | %.*s %.2f", int(p.name.size()), p.name.data(), p.ms);
        t += buf;
    }
    std::snprintf(buf, sizeof(buf), " | total %.2f ms", r.times.totalMs());
    return t + buf;
}

// One frame of window input: key commands (1/2/3 culling, Esc closes) and the camera.
void steer(Window& win, Module& m, CullingMode& mode, FlyCamera& fly, const CameraDesc& base, float seconds) {
    Window::Input in = win.poll();
    for (int key : in.pressed) {
        const CullingMode modes[] = {CullingMode::Clustered, CullingMode::Tiled, CullingMode::None};
        if (key >= GLFW_KEY_1 && key <= GLFW_KEY_3) {
            mode = modes[key - GLFW_KEY_1];
            m.setCulling(mode);
            std::printf("window: culling %s\n", cullingName(mode));
        }
        if (key == GLFW_KEY_ESCAPE) win.close();
    }
    fly.update(in.fly, seconds);
    if (auto r = m.setCamera(fly.desc(base)); !r)
        std::fprintf(stderr, "manylights demo: %s\n", r.error().c_str());
}

void printCamera(const char* when, const CameraDesc& c) {
    std::printf("window: %s camera %.2f,%.2f,%.2f,%.2f,%.2f,%.2f (for --camera)\n", when, c.position.x,
                c.position.y, c.position.z, c.target.x, c.target.y, c.target.z);
}
} // namespace

static const char* kDemoHelp = R"(usage: manylights demo [options]
Renders a scene lit by many spotlights and writes images and a GPU profile.
  --scene S        night-city (default), night-city-large (40x40 blocks, 520K triangles), either
                   with -closed (awnings, fences, foliage as thin closed boxes), indoor (rooms and
                   corridors) or a .gltf / .glb file
  --frames N       frames to render (default 3)
  --size WxH       image size (default 1280x720)
  --lights N       lights in the scene, 1..4096 (default 256)
  --seed S         scene seed (default 1)
  --culling M      clustered (default; footprint assignment), clustered-brute, tiled or none
  --out DIR        output folder (default out/demo)
  --window         also show the frames in a window (needs a display): drag with a mouse button to
                   look, W/A/S/D move, Q/E down/up, shift faster, 1/2/3 clustered/tiled/no culling,
                   Esc closes; per-pass GPU ms in the title. With --frames 0 it runs until closed
                   (no PNGs then)
  --no-stats       skip the per-pixel light counts (a brute-force loop in a statistics pass of its own)
  --bake FILE[,FILE...]  static shadows from bake files (manylights bake) of this scene, lights and
                   seed; a light in several files takes the last one's record (each replacement is
                   printed), e.g. the spot lights at 1024^2 and the moon from a 16384^2 bake
  --static M       bake static shadows in-process (Module::bakeStaticShadows) for every static spot and
                   point light: sm, mh, mmh, dagmh, cpvs
  --static-res N   resolution of those bakes (default 512; only with --static)
  --camera X,Y,Z,TX,TY,TZ  camera position and target (default: the scene's own)
  --allow-outside-scene-dir  let the glTF's buffer/image URIs leave its folder (trusted scenes only)
  --pcf R          shadow filter radius (static and dynamic): 0 one tap (default), 1 = 3x3 ... 4 = 9x9
  --by-level       MH, MMH, DAG-MH and CPVS static shadows filtered on the coarsest hierarchy level
                   whose texel is at most a quarter of the pixel (setShadowFilter's byLevel); SM stays
                   at its finest level
  --path P         camera path: static (default: the scene's camera or --camera), drive, orbit
  --dynamic M      dynamic shadows: vsm (virtual shadow maps, default) or off
  --vsm-res N      virtual resolution of each shadow map (power of two, 256..16384; default 4096)
  --vsm-page N     page size in texels: 32, 64 (default) or 128
  --vsm-pool N     physical pages in the shared pool (default 4096)
  --vsm-mark M     page marking: pixel (default: per receiver pixel) or cluster (per cluster and light)
  --vsm-raster R   how shadow pages are drawn: auto (default: vertex on CPU devices such as lavapipe,
                   mesh elsewhere), mesh (meshlets, task and mesh shaders) or vertex
  --timing T       fenced (default: each pass submitted and timed on its own, honest on lavapipe) or
                   timestamps (one command buffer, GPU timestamps)
  --view V         shaded (default); lights: heat map of lights evaluated per pixel; lights-reaching:
                   of lights whose cone and range hold the pixel's point. Colours: 0 black, 1 dark blue,
                   4 blue, 8 cyan, 16 green, 32 yellow, 64 red, 128+ white (linear between);
                   vsm: the virtual shadow map page each pixel's first shadowed light reads: hue =
                   mip (0 red .. 6 magenta), bright = drawn this frame, dim = cached, grey = no
                   dynamic caster there, white = fell back to a coarser page
Writes DIR/frame_NNNN.png, DIR/profile.json (Chrome trace), DIR/frames.csv, DIR/stats.json.
)";

namespace {
struct DemoOptions {
    opts::View view;
    opts::Scene scene;
    uint32_t lights = 256;
    CullingMode culling = CullingMode::Clustered;
    std::string out;
    StaticMethod staticMethod = StaticMethod::None;
    uint32_t staticRes = 512, pcf = 0;
    bool byLevel = false;
    std::optional<std::array<float, 6>> camera;
    CameraPath path = CameraPath::Static;
    DebugView debugView = DebugView::Shaded;
    ModuleOptions module;
    std::optional<std::string> bake; // --bake FILE
};

Result<DebugView> parseView(const std::string& name) {
    const std::pair<const char*, DebugView> views[] = {{"shaded", DebugView::Shaded},
                                                       {"lights", DebugView::LightsEvaluated},
                                                       {"lights-reaching", DebugView::LightsReaching},
                                                       {"vsm", DebugView::Vsm}};
    for (const auto& [word, view] : views)
        if (name == word) return view;
    return fail("--view: unknown view '" + name + "' (shaded, lights, lights-reaching or vsm)");
}

// The module's options: culling, statistics, window, timing and the virtual shadow maps.
Result<void> parseModule(const cli::Args& args, DemoOptions& d) {
    ModuleOptions& mo = d.module;
    const bool window = args.has("--window");
    const std::string dynamic = args.get("--dynamic", "vsm"), timing = args.get("--timing", "fenced");
    if (dynamic != "vsm" && dynamic != "off")
        return fail("--dynamic takes vsm or off, not '" + dynamic + "'");
    if (timing != "fenced" && timing != "timestamps")
        return fail("--timing takes fenced or timestamps, not '" + timing + "'");
    auto raster = vsmRaster(args);
    if (!raster) return fail(raster.error());
    if (dynamic == "off")
        for (const char* f : {"--vsm-res", "--vsm-page", "--vsm-pool", "--vsm-raster"})
            if (args.has(f)) return fail(std::string(f) + ": does nothing with --dynamic off");
    mo.culling = d.culling;
    mo.statistics = !args.has("--no-stats");
    mo.device.window = window;
    if (window)
        if (auto r = Window::prepareDevice(mo.device); !r) return r;
    mo.timing = timing == "fenced" && !window ? TimingChoice::Fenced : TimingChoice::Timestamps;
    mo.vsm.enabled = dynamic == "vsm";
    mo.vsm.raster = raster.value();
    return {};
}

Result<DemoOptions> parseDemo(const cli::Args& args) {
    DemoOptions d;
    auto view = opts::view(args, {3, args.has("--window") ? 0u : 1u, 100000, "1280x720"});
    auto lights = cli::parseUint("--lights", args.get("--lights", "256"), 1, ML_MAX_LIGHTS);
    auto scene = opts::scene(args);
    auto culling = parseCulling(args.get("--culling", "clustered"));
    auto staticMethod = parseStaticMethod(args.get("--static", "none"));
    auto staticRes = cli::parseUint("--static-res", args.get("--static-res", "512"), 8, 16384);
    auto pcf = cli::parseUint("--pcf", args.get("--pcf", "0"), 0, ML_MAX_PCF_RADIUS);
    for (const std::string* e : {&view.error(), &lights.error(), &scene.error(), &culling.error(),
                                 &staticMethod.error(), &staticRes.error(), &pcf.error()})
        if (!e->empty()) return fail(*e);
    // An option that does nothing without another is a mistake worth a word, not a silent default.
    if (args.has("--static-res") && staticMethod.value() == StaticMethod::None)
        return fail("--static-res: does nothing without --static METHOD");
    // What the bake would refuse after the device and scene are built, refused now.
    if (staticMethod.value() == StaticMethod::CPVS)
        if (auto s = makeCpvsSpace(staticRes.value(), 1.0f, 2.0f); !s)
            return fail("--static-res: " + s.error());
    if (args.has("--pcf") && staticMethod.value() == StaticMethod::None && !args.has("--bake") &&
        args.get("--dynamic", "vsm") == "off")
        return fail("--pcf: does nothing without static shadows (--static, --bake) or --dynamic vsm");
    if (args.has("--by-level") && staticMethod.value() == StaticMethod::None && !args.has("--bake"))
        return fail("--by-level: does nothing without static shadows (--static, --bake)");
    // Checked before any device work: a bad camera is a usage error, not a blank frame.
    if (args.has("--camera")) {
        auto v = cli::parseCamera("--camera", args.get("--camera", ""));
        if (!v) return fail(v.error());
        d.camera = v.value();
    }
    auto path = parseCameraPath(args.get("--path", "static"));
    auto maps = vsmMapOptions(args, 4096, d.module.vsm);
    auto debugView = parseView(args.get("--view", "shaded"));
    for (const std::string* e : {&path.error(), &maps.error(), &debugView.error()})
        if (!e->empty()) return fail(*e);
    d.view = view.value(), d.scene = scene.value(), d.lights = lights.value(), d.culling = culling.value();
    d.staticMethod = staticMethod.value(), d.staticRes = staticRes.value(), d.pcf = pcf.value();
    d.byLevel = args.has("--by-level");
    d.path = path.value(), d.debugView = debugView.value();
    d.out = args.get("--out", "out/demo");
    if (auto r = cli::checkOutputDirectory("--out", d.out); !r) return fail(r.error());
    if (args.has("--bake")) d.bake = args.get("--bake", "");
    if (d.bake && d.staticMethod != StaticMethod::None) return fail("--bake and --static exclude each other");
    if (auto r = parseModule(args, d); !r) return fail(r.error());
    return d;
}

// --bake's comma-separated files (a path holding a comma cannot be given).
std::vector<std::string> bakePaths(const std::string& list) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start <= list.size()) {
        const size_t comma = list.find(',', start);
        out.push_back(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

// Static shadows (a bake file or baked now), the shadow filter and the camera: 0, or the exit status
// (a filter or camera the module refuses is a usage error, a bake that fails is not).
int setupShadows(const DemoOptions& d, Module& m, Scene& scene, const SceneBinding& binding) {
    if (d.bake) {
        std::map<uint64_t, std::string> attached;
        for (const std::string& path : bakePaths(*d.bake)) {
            std::vector<std::string> replaced;
            auto n =
                attachBakeFile(m, binding, path, d.scene.name, d.lights, d.scene.seed, &attached, &replaced);
            if (!n)
                return inputError("demo", n.error()); // a damaged or hostile bake file, or another scene's
            std::printf("static shadows of %u lights from %s\n", n.value(), path.c_str());
            for (const std::string& line : replaced) std::printf("  %s\n", line.c_str());
        }
    }
    // The filter applies to static and dynamic (VSM) lookups alike: --pcf alone filters the VSM's.
    if (d.bake || d.staticMethod != StaticMethod::None || d.pcf)
        if (auto r = m.setShadowFilter(d.pcf, d.byLevel); !r) return usageError("demo", r.error());
    if (d.staticMethod != StaticMethod::None) {
        auto baked = bakeStaticShadows(m, scene, binding, d.staticMethod, d.staticRes);
        if (!baked) return runError("demo", baked.error());
        if (auto r = m.setShadowFilter(d.pcf, d.byLevel); !r) return usageError("demo", r.error());
    }
    if (d.camera) {
        const std::array<float, 6>& c = *d.camera;
        scene.camera.position = {c[0], c[1], c[2]};
        scene.camera.target = {c[3], c[4], c[5]};
        if (auto r = m.setCamera(toCameraDesc(scene.camera)); !r) return usageError("demo", r.error());
    }
    return 0;
}

// The frames: the scene animated, the camera on its path or steered in the window, each frame's PNG
// (not in an endless window run) and its report.
Result<std::vector<FrameReport>> renderFrames(DemoOptions& d, Module& m, Scene& scene,
                                              const SceneBinding& binding, Window* win) {
    std::vector<FrameReport> reports;
    std::vector<uint8_t> rgba;
    const uint32_t frames = d.view.frames;
    const CameraDesc baseCamera = toCameraDesc(scene.camera);
    FlyCamera fly = FlyCamera::lookingAt(toGlm(baseCamera.position), toGlm(baseCamera.target));
    if (win) printCamera("start", fly.desc(baseCamera));
    auto last = std::chrono::steady_clock::now();
    for (uint32_t f = 0; frames == 0 || f < frames; ++f) {
        animateScene(scene, f / 30.0);
        if (auto r = updateScene(m, scene, binding); !r) return fail(r.error());
        if (d.path != CameraPath::Static) {
            auto cam = cameraOnPath(scene, d.path, f / 30.0);
            if (!cam) return fail(cam.error());
            if (auto r = m.setCamera(toCameraDesc(cam.value())); !r) return fail(r.error());
        }
        if (win) {
            auto now = std::chrono::steady_clock::now();
            // Slow frames on CPU devices: cap a step so one long frame does not throw the camera away.
            float seconds = std::min(0.25f, std::chrono::duration<float>(now - last).count());
            last = now;
            steer(*win, m, d.culling, fly, baseCamera, seconds);
            if (win->shouldClose()) break;
            if (auto r = win->frame(m); !r) return fail(r.error());
        } else if (auto r = m.submitFrame(); !r) {
            return fail(r.error());
        }
        if (frames != 0) {
            if (auto r = m.readOutput(rgba); !r) return fail(r.error());
            char name[64];
            std::snprintf(name, sizeof(name), "/frame_%04u.png", f);
            if (auto r = writePng(d.out + name, d.view.width, d.view.height, rgba); !r)
                return fail(r.error());
        }
        m.collect();
        for (auto& r : m.takeReports()) reports.push_back(r);
        if (!reports.empty()) {
            std::printf("  frame %u: %.2f ms GPU\n", f, reports.back().times.totalMs());
            if (win) win->setTitle(windowTitle(d.culling, reports.back()));
        }
    }
    if (win) printCamera("end", fly.desc(baseCamera));
    return reports;
}

// The last frame's counts on stdout, and a warning when the VSM ran out of room.
void printSummary(const ModuleOptions& mo, const FrameStats& s) {
    if (mo.statistics)
        std::printf(
            "lights %u (visible %u), clusters %u, lights/pixel evaluated %.2f, reaching %.2f, overflow %u\n",
            s.lightsTotal, s.lightsVisible, s.clusters, s.lightsPerPixelEvaluatedMean,
            s.lightsPerPixelReachingMean, s.clusterOverflowCount);
    else
        std::printf("lights %u (visible %u), clusters %u, overflow %u (per-pixel counts off: --no-stats)\n",
                    s.lightsTotal, s.lightsVisible, s.clusters, s.clusterOverflowCount);
    if (!mo.vsm.enabled) return;
    const VsmStats& v = s.vsm;
    std::printf("vsm: %u lights with pages, pages marked %u, allocated %u (%.1f MiB of a %.1f MiB pool), "
                "rendered %u, cached %u, fallbacks %u, draws %u (HPB culled %u)\n",
                v.lightsWithPages, v.pagesMarked, v.pagesAllocated, double(v.usedBytes) / 1048576.0,
                double(v.poolBytes) / 1048576.0, v.pagesRendered, v.pagesCached, v.fallbacks,
                v.instancesDrawn, v.instancesCulledHpb);
    if (v.fallbacks || v.drawOverflow || v.lightsWithoutSlot || v.pairOverflow)
        std::fprintf(stderr,
                     "manylights demo: warning: vsm pool full for %u pages (coarser shadows), %u draws "
                     "over the draw buffer, %u lights without a map slot, %u culling pairs over the "
                     "pair list\n",
                     v.fallbacks, v.drawOverflow, v.lightsWithoutSlot, v.pairOverflow);
}

// The module on the scene: created, its targets (a size past the device's limits is a usage error,
// refused before the scene is bound), bound, its view. `status` is the exit status on failure.
Result<std::unique_ptr<Module>> createModule(const DemoOptions& d, Scene& scene, SceneBinding& binding,
                                             int& status) {
    status = kExitRun;
    auto module = Module::create(d.module);
    if (!module) return fail(module.error());
    Module& m = *module.value();
    m.setView(d.debugView);
    if (auto r = m.createTargets(d.view.width, d.view.height); !r) {
        status = kExitUsage;
        return fail("--" + r.error());
    }
    auto b = bindScene(m, scene);
    if (!b) return fail(b.error());
    binding = std::move(b.value());
    return std::move(module.value());
}
} // namespace

// The flags of `demo` beside its option groups.
const cli::Flags kDemoFlags{{"--lights", "--culling", "--out", "--static", "--static-res", "--pcf",
                             "--camera", "--bake", "--path", "--dynamic", "--timing", "--view",
                             "--vsm-raster"},
                            {"--window", "--no-stats", "--by-level"}};

int runDemo(int argc, char** argv) {
    int status = 0;
    const auto args = commandArgs(
        "demo", kDemoHelp,
        cli::parse(argc, argv, 2,
                   {opts::kSceneFlags, opts::kSceneDirFlags, opts::kViewFlags, kVsmMapFlags, kDemoFlags}),
        status);
    if (!args) return status;
    auto parsed = parseDemo(*args);
    if (!parsed) return usageError("demo", parsed.error());
    DemoOptions& d = parsed.value();
    // The bake file is read after the device and scene are built: one that is missing, a folder or a
    // FIFO is refused now.
    uint64_t bakeBytes = 0;
    if (d.bake)
        for (const std::string& path : bakePaths(*d.bake)) {
            uint64_t bytes = 0;
            if (auto head = io::readRegularFileHead(path, 4, &bytes); !head)
                return inputError("demo", head.error());
            bakeBytes += bytes;
        }
    auto scene = loadScene(d.scene.name, d.lights, d.scene.seed, {d.scene.allowOutside});
    if (!scene) return inputError("demo", scene.error()); // a missing, malformed or hostile scene file
    for (const auto& w : scene->warnings)
        std::fprintf(stderr, "manylights demo: warning: %s\n", io::escapeText(w).c_str());
    SceneBinding binding;
    int moduleStatus = 0;
    auto module = createModule(d, scene.value(), binding, moduleStatus);
    if (!module)
        return moduleStatus == kExitUsage ? usageError("demo", module.error())
                                          : runError("demo", module.error());
    Module& m = *module.value();
    if (int status = setupShadows(d, m, scene.value(), binding)) return status;
    std::unique_ptr<Window> win;
    if (d.module.device.window) {
        auto w = Window::open(m, d.view.width, d.view.height);
        if (!w) return runError("demo", w.error());
        win = std::move(w.value());
    }
    std::printf("manylights demo: %s, %u lights, %ux%u, %s culling, %u frames on %s\n", scene->name.c_str(),
                uint32_t(scene->lights.size()), d.view.width, d.view.height, cullingName(d.module.culling),
                d.view.frames, m.deviceInfo().name.c_str());
    auto reports = renderFrames(d, m, scene.value(), binding, win.get());
    if (!reports) return runError("demo", reports.error());
    const DeviceInfo dev = m.deviceInfo();
    vkDeviceWaitIdle(dev.device);
    m.collect();
    for (auto& r : m.takeReports()) reports->push_back(r);
    if (reports->empty()) return runError("demo", "the window was closed before a frame completed");
    RunInfo info{
        scene->name, cullingName(d.module.culling), dev.name, d.view.width, d.view.height, d.view.frames,
        d.scene.seed};
    info.memoryPlacement = dev.memoryPlacement;
    std::printf("memory: %s\n", dev.memoryPlacement.c_str()); // where each buffer role lives, once
    const std::string& out = d.out;
    for (auto r :
         {writeProfile(out + "/profile.json", *reports), writeFramesCsv(out + "/frames.csv", *reports),
          writeStats(out + "/stats.json", info, *reports)})
        if (!r) return runError("demo", r.error());
    printSummary(d.module, reports->back().stats);
    std::printf("wrote %s/frame_*.png, profile.json, frames.csv, stats.json\n", out.c_str());
    if (dev.validation && validationErrors()) {
        std::fprintf(stderr, "manylights demo: %u validation errors\n", validationErrors());
        return kExitRun;
    }
    return 0;
}

} // namespace ml
