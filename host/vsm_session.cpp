#include "host/vsm_session.h"

#include "scenes/scenes.h"

namespace ml {

Result<std::unique_ptr<VsmSession>> VsmSession::create(const VsmSessionOptions& o, bool* settingsRefused) {
    if (settingsRefused) *settingsRefused = false;
    auto s = std::make_unique<VsmSession>();
    s->options = o;
    auto scene = loadScene(o.scene, o.lights, o.seed);
    if (!scene) return fail(scene.error());
    s->scene = std::move(scene.value());
    auto module = Module::create(o.module);
    if (!module) {
        if (settingsRefused) *settingsRefused = module.error().rfind("vsm: ", 0) == 0;
        return fail(module.error());
    }
    s->module = std::move(module.value());
    auto binding = bindScene(*s->module, s->scene);
    if (!binding) return fail(binding.error());
    s->binding = binding.value();
    if (auto r = s->module->createTargets(o.width, o.height); !r) {
        // Out of memory is a run failure; a size past the device's limits is the settings'.
        if (settingsRefused) *settingsRefused = r.error().find("VK_ERROR_OUT_OF") == std::string::npos;
        return fail(r.error());
    }
    if (!o.bake.empty()) {
        auto n = attachBakeFile(*s->module, s->binding, o.bake, o.scene, o.lights, o.seed);
        if (!n) return fail(n.error());
    }
    return s;
}

Result<FrameReport> VsmSession::frame(uint32_t f) {
    const double t = f * options.secondsPerFrame;
    animateScene(scene, t);
    if (auto r = updateScene(*module, scene, binding); !r) return fail(r.error());
    auto cam = cameraOnPath(scene, options.path, t);
    if (!cam) return fail(cam.error());
    if (auto r = module->setCamera(toCameraDesc(cam.value())); !r) return fail(r.error());
    if (auto r = module->submitFrame(); !r) return fail(r.error());
    vkQueueWaitIdle(module->deviceInfo().queue);
    module->collect();
    auto reports = module->takeReports();
    if (reports.empty()) return fail("frame " + std::to_string(f) + ": no report arrived");
    return reports.back();
}

} // namespace ml
