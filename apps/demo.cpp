// `manylights demo`: renders a scene (the night city by default) with the module, headless, and writes
// frame_NNNN.png, profile.json, frames.csv and stats.json into --out. A host of the public API only.
#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/report.h"
#include "apps/window.h"
#include "host/scene_host.h"
#include "scenes/camera_path.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "shaders/shared/config.h"

#include <GLFW/glfw3.h>

#include <chrono>
#include <cstdio>

namespace ml {

namespace {
// The window title: culling mode and the newest frame's GPU milliseconds per pass.
std::string windowTitle(CullingMode mode, const FrameReport& r) {
    std::string t = std::string("manylights | ") + cullingName(mode);
    char buf[64];
    for (uint32_t p = 0; p < kPassCount; ++p)
        if (r.times.ran[p]) {
            std::snprintf(buf, sizeof(buf), " | %s %.2f", passName(Pass(p)), r.times.ms[p]);
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
  --scene S        night-city (default), or a .gltf / .glb file
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
  --bake FILE      static shadows from a bake file (manylights bake) of this scene, lights and seed
  --static M       bake static shadows in-process (Module::bakeStaticShadows) for every static spot and
                   point light: sm, mh, mmh, dagmh, cpvs
  --static-res N   resolution of those bakes (default 512)
  --camera X,Y,Z,TX,TY,TZ  camera position and target (default: the scene's own)
  --allow-outside-scene-dir  let the glTF's buffer/image URIs leave its folder (trusted scenes only)
  --pcf R          shadow filter radius (static and dynamic): 0 one tap (default), 1 = 3x3 ... 4 = 9x9
  --path P         camera path: static (default: the scene's camera or --camera), drive, orbit
  --dynamic M      dynamic shadows: vsm (virtual shadow maps, default) or off
  --vsm-res N      virtual resolution of each shadow map (power of two, 256..16384; default 4096)
  --vsm-page N     page size in texels: 32, 64 (default) or 128
  --vsm-pool N     physical pages in the shared pool (default 4096)
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

int runDemo(int argc, char** argv) {
    auto args =
        cli::parse(argc, argv, 2, {"--scene",    "--frames",   "--size",   "--lights",     "--seed",
                                   "--culling",  "--out",      "--static", "--static-res", "--pcf",
                                   "--camera",   "--bake",     "--path",   "--dynamic",    "--vsm-res",
                                   "--vsm-page", "--vsm-pool", "--timing", "--view",       "--vsm-raster"},
                   {"--window", "--no-stats", "--allow-outside-scene-dir"});
    if (!args) return usageError("demo", args.error());
    if (args->help) {
        std::fputs(kDemoHelp, stdout);
        return 0;
    }
    bool window = args->has("--window");
    auto frames = cli::parseUint("--frames", args->get("--frames", "3"), window ? 0 : 1, 100000);
    auto size = cli::parseSize("--size", args->get("--size", "1280x720"));
    auto lights = cli::parseUint("--lights", args->get("--lights", "256"), 1, ML_MAX_LIGHTS);
    auto seed = cli::parseUint("--seed", args->get("--seed", "1"), 0, 0xFFFFFFFFu);
    auto culling = parseCulling(args->get("--culling", "clustered"));
    for (const std::string* e :
         {&frames.error(), &size.error(), &lights.error(), &seed.error(), &culling.error()})
        if (!e->empty()) return usageError("demo", *e);
    std::string out = args->get("--out", "out/demo");
    auto staticMethod = parseStaticMethod(args->get("--static", "none"));
    auto staticRes = cli::parseUint("--static-res", args->get("--static-res", "512"), 8, 16384);
    auto pcf = cli::parseUint("--pcf", args->get("--pcf", "0"), 0, ML_MAX_PCF_RADIUS);
    for (const std::string* e : {&staticMethod.error(), &staticRes.error(), &pcf.error()})
        if (!e->empty()) return usageError("demo", *e);
    // Checked before any device work: a bad camera is a usage error, not a blank frame.
    std::array<float, 6> camera{};
    if (args->has("--camera")) {
        auto v = cli::parseCamera("--camera", args->get("--camera", ""));
        if (!v) return usageError("demo", v.error());
        camera = v.value();
    }
    auto path = parseCameraPath(args->get("--path", "static"));
    auto vsmRes = cli::parseUint("--vsm-res", args->get("--vsm-res", "4096"), 256, 16384);
    auto vsmPage = cli::parseUint("--vsm-page", args->get("--vsm-page", "64"), 32, 128);
    auto vsmPool = cli::parseUint("--vsm-pool", args->get("--vsm-pool", "4096"), 1, 1u << 20);
    for (const std::string* e : {&path.error(), &vsmRes.error(), &vsmPage.error(), &vsmPool.error()})
        if (!e->empty()) return usageError("demo", *e);
    const std::string viewName = args->get("--view", "shaded");
    DebugView view = DebugView::Shaded;
    if (viewName == "lights")
        view = DebugView::LightsEvaluated;
    else if (viewName == "lights-reaching")
        view = DebugView::LightsReaching;
    else if (viewName == "vsm")
        view = DebugView::Vsm;
    else if (viewName != "shaded")
        return usageError("demo",
                          "--view: unknown view '" + viewName + "' (shaded, lights, lights-reaching or vsm)");
    const std::string dynamic = args->get("--dynamic", "vsm"), timing = args->get("--timing", "fenced");
    if (dynamic != "vsm" && dynamic != "off")
        return usageError("demo", "--dynamic takes vsm or off, not '" + dynamic + "'");
    if (timing != "fenced" && timing != "timestamps")
        return usageError("demo", "--timing takes fenced or timestamps, not '" + timing + "'");

    auto scene = loadScene(args->get("--scene", "night-city"), lights.value(), seed.value(),
                           {args->has("--allow-outside-scene-dir")});
    if (!scene) return runError("demo", scene.error());
    for (const auto& w : scene->warnings)
        std::fprintf(stderr, "manylights demo: warning: %s\n", io::escapeText(w).c_str());
    if (auto r = cli::makeDirectory(out); !r) return runError("demo", r.error());

    ModuleOptions mo;
    mo.culling = culling.value();
    mo.statistics = !args->has("--no-stats");
    mo.device.window = window;
    mo.timing = timing == "fenced" && !window ? TimingChoice::Fenced : TimingChoice::Timestamps;
    mo.vsm.enabled = dynamic == "vsm";
    mo.vsm.resolution = vsmRes.value();
    mo.vsm.pageSize = vsmPage.value();
    mo.vsm.poolPages = vsmPool.value();
    if (!parseVsmRaster(args->get("--vsm-raster", "auto"), mo.vsm.raster))
        return usageError("demo", "--vsm-raster takes auto, mesh or vertex, not '" +
                                      args->get("--vsm-raster", "") + "'");
    auto module = Module::create(mo);
    if (!module) return runError("demo", module.error());
    Module& m = *module.value();
    m.setView(view);
    auto [width, height] = size.value();
    auto binding = bindScene(m, scene.value());
    if (!binding) return runError("demo", binding.error());
    if (auto r = m.createTargets(width, height); !r) return runError("demo", r.error());
    if (args->has("--bake")) {
        if (staticMethod.value() != StaticMethod::None)
            return usageError("demo", "--bake and --static exclude each other");
        auto n = attachBakeFile(m, binding.value(), args->get("--bake", ""),
                                args->get("--scene", "night-city"), lights.value(), seed.value());
        if (!n) return runError("demo", n.error());
        std::printf("static shadows of %u lights from %s\n", n.value(), args->get("--bake", "").c_str());
    }
    if (args->has("--bake") || staticMethod.value() != StaticMethod::None) {
        if (auto r = m.setShadowFilter(pcf.value()); !r) return usageError("demo", r.error());
    }
    if (staticMethod.value() != StaticMethod::None) {
        auto baked =
            bakeStaticShadows(m, scene.value(), binding.value(), staticMethod.value(), staticRes.value());
        if (!baked) return runError("demo", baked.error());
        if (auto r = m.setShadowFilter(pcf.value()); !r) return usageError("demo", r.error());
    }
    if (args->has("--camera")) {
        scene->camera.position = {camera[0], camera[1], camera[2]};
        scene->camera.target = {camera[3], camera[4], camera[5]};
        if (auto r = m.setCamera(toCameraDesc(scene->camera)); !r) return usageError("demo", r.error());
    }
    std::unique_ptr<Window> win;
    if (window) {
        auto w = Window::open(m, width, height);
        if (!w) return runError("demo", w.error());
        win = std::move(w.value());
    }
    std::printf("manylights demo: %s, %u lights, %ux%u, %s culling, %u frames on %s\n", scene->name.c_str(),
                uint32_t(scene->lights.size()), width, height, cullingName(mo.culling), frames.value(),
                m.deviceInfo().name.c_str());

    const DeviceInfo d = m.deviceInfo();
    std::vector<FrameReport> reports;
    std::vector<uint8_t> rgba;
    const CameraDesc baseCamera = toCameraDesc(scene->camera);
    FlyCamera fly = FlyCamera::lookingAt(baseCamera.position, baseCamera.target);
    if (win) printCamera("start", fly.desc(baseCamera));
    auto last = std::chrono::steady_clock::now();
    for (uint32_t f = 0; frames.value() == 0 || f < frames.value(); ++f) {
        animateScene(scene.value(), f / 30.0);
        if (auto r = updateScene(m, scene.value(), binding.value()); !r) return runError("demo", r.error());
        if (path.value() != CameraPath::Static) {
            auto cam = cameraOnPath(scene.value(), path.value(), f / 30.0);
            if (!cam) return runError("demo", cam.error());
            if (auto r = m.setCamera(toCameraDesc(cam.value())); !r) return runError("demo", r.error());
        }
        if (win) {
            auto now = std::chrono::steady_clock::now();
            // Slow frames on CPU devices: cap a step so one long frame does not throw the camera away.
            float seconds = std::min(0.25f, std::chrono::duration<float>(now - last).count());
            last = now;
            steer(*win, m, culling.value(), fly, baseCamera, seconds);
            if (win->shouldClose()) break;
            if (auto r = win->frame(m); !r) return runError("demo", r.error());
        } else {
            if (auto r = m.submitFrame(); !r) return runError("demo", r.error());
        }
        if (frames.value() != 0) {
            if (auto r = m.readOutput(rgba); !r) return runError("demo", r.error());
            char name[64];
            std::snprintf(name, sizeof(name), "/frame_%04u.png", f);
            if (auto r = writePng(out + name, width, height, rgba); !r) return runError("demo", r.error());
        }
        m.collect();
        for (auto& r : m.takeReports()) reports.push_back(r);
        if (!reports.empty()) {
            std::printf("  frame %u: %.2f ms GPU\n", f, reports.back().times.totalMs());
            if (win) win->setTitle(windowTitle(culling.value(), reports.back()));
        }
    }
    if (win) printCamera("end", fly.desc(baseCamera));
    vkDeviceWaitIdle(d.device);
    m.collect();
    for (auto& r : m.takeReports()) reports.push_back(r);
    if (reports.empty()) return runError("demo", "the window was closed before a frame completed");

    RunInfo info{scene->name, cullingName(mo.culling), d.name, width, height, frames.value(), seed.value()};
    for (auto r : {writeProfile(out + "/profile.json", reports), writeFramesCsv(out + "/frames.csv", reports),
                   writeStats(out + "/stats.json", info, reports)})
        if (!r) return runError("demo", r.error());
    const FrameStats& s = reports.back().stats;
    if (mo.statistics)
        std::printf(
            "lights %u (visible %u), clusters %u, lights/pixel evaluated %.2f, reaching %.2f, overflow %u\n",
            s.lightsTotal, s.lightsVisible, s.clusters, s.lightsPerPixelEvaluatedMean,
            s.lightsPerPixelReachingMean, s.clusterOverflowCount);
    else
        std::printf("lights %u (visible %u), clusters %u, overflow %u (per-pixel counts off: --no-stats)\n",
                    s.lightsTotal, s.lightsVisible, s.clusters, s.clusterOverflowCount);
    if (mo.vsm.enabled) {
        const VsmStats& v = s.vsm;
        std::printf("vsm: %u lights with pages, pages marked %u, allocated %u (%.1f MiB of a %.1f MiB pool), "
                    "rendered %u, cached %u, fallbacks %u, draws %u (HPB culled %u)\n",
                    v.lightsWithPages, v.pagesMarked, v.pagesAllocated, double(v.usedBytes) / 1048576.0,
                    double(v.poolBytes) / 1048576.0, v.pagesRendered, v.pagesCached, v.fallbacks,
                    v.instancesDrawn, v.instancesCulledHpb);
        if (v.fallbacks || v.drawOverflow || v.lightsWithoutSlot)
            std::fprintf(stderr,
                         "manylights demo: warning: vsm pool full for %u pages (coarser shadows), %u draws "
                         "over the draw buffer, %u lights without a map slot\n",
                         v.fallbacks, v.drawOverflow, v.lightsWithoutSlot);
    }
    std::printf("wrote %s/frame_*.png, profile.json, frames.csv, stats.json\n", out.c_str());
    if (d.validation && validationErrors()) {
        std::fprintf(stderr, "manylights demo: %u validation errors\n", validationErrors());
        return 1;
    }
    return 0;
}

} // namespace ml
