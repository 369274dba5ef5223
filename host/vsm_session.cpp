#include "host/vsm_session.h"

#include "scenes/scenes.h"

namespace ml {

Result<std::unique_ptr<VsmSession>> VsmSession::create(const VsmSessionOptions& o) {
    auto s = std::make_unique<VsmSession>();
    s->options = o;
    auto scene = loadScene(o.scene, o.lights, o.seed);
    if (!scene) return fail(scene.error());
    s->scene = std::move(scene.value());
    auto module = Module::create(o.module);
    if (!module) return fail(module.error());
    s->module = std::move(module.value());
    auto binding = bindScene(*s->module, s->scene);
    if (!binding) return fail(binding.error());
    s->binding = binding.value();
    if (auto r = s->module->createTargets(o.width, o.height); !r) return fail(r.error());
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
