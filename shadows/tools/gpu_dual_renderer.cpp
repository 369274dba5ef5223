#include "shadows/tools/gpu_dual_renderer.h"

#include "shadows/gpu/dual_depth_gpu.h"

namespace ml {

struct GpuDualRenderer::State {
    std::unique_ptr<Device> device; // declared first: destroyed after the renderer made on it
    std::unique_ptr<DualDepthRenderer> renderer;
};

GpuDualRenderer::GpuDualRenderer(std::unique_ptr<State> s) : s_(std::move(s)) {}
GpuDualRenderer::~GpuDualRenderer() = default;

Result<std::unique_ptr<GpuDualRenderer>> GpuDualRenderer::create() {
    auto s = std::make_unique<State>();
    auto d = Device::create({});
    if (!d) return fail(d.error());
    s->device = std::move(d.value());
    auto r = DualDepthRenderer::create(*s->device);
    if (!r) return fail(r.error());
    s->renderer = std::move(r.value());
    return std::unique_ptr<GpuDualRenderer>(new GpuDualRenderer(std::move(s)));
}

Result<DualDepthMap> GpuDualRenderer::render(const CasterTriangles& casters, const LightFrustum& frustum,
                                             uint32_t resolution, uint32_t maxTile,
                                             const std::function<void(float)>& progress) {
    return s_->renderer->render(casters, frustum, resolution, maxTile, progress);
}

std::string GpuDualRenderer::deviceDescription() const {
    const Device& d = *s_->device;
    return "gpu: " + d.name + ", driver " + std::to_string(d.properties.driverVersion) + ", vendor " +
           std::to_string(d.properties.vendorID) + ", device " + std::to_string(d.properties.deviceID);
}

} // namespace ml
