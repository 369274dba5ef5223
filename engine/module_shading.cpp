// Per-instance shading and shadow-receiving settings and the physical exposure (manylights/module.h):
// setInstanceShadowReceiving, setInstanceMaterial, setExposureEV100. Each reaches the GPU through the next
// frame's instance upload or frame constants (engine/frame_write.cpp): no device wait.
#include "engine/module_impl.h"

#include <cmath>
#include <string>
#include <utility>

namespace ml {

Result<void> Module::setInstanceShadowReceiving(InstanceId id, bool receivesShadows) {
    auto index = impl_->instanceIndex(id, "setInstanceShadowReceiving");
    if (!index) return fail(index.error());
    impl_->instances[index.value()].receivesShadows = receivesShadows;
    impl_->touchInstance(index.value());
    return {};
}

Result<void> Module::setInstanceMaterial(InstanceId id, float roughness, float metalness) {
    auto index = impl_->instanceIndex(id, "setInstanceMaterial");
    if (!index) return fail(index.error());
    for (auto [value, name] : {std::pair{roughness, "roughness"}, std::pair{metalness, "metalness"}})
        if (!(value >= 0.0f && value <= 1.0f)) // NaN fails both
            return fail(std::string("setInstanceMaterial: ") + name + " " + std::to_string(value) +
                        " is not in [0, 1]");
    impl_->instances[index.value()].roughness = roughness;
    impl_->instances[index.value()].metalness = metalness;
    impl_->touchInstance(index.value());
    return {};
}

Result<void> Module::setExposureEV100(float ev100) {
    // EV100 spans about -6 (a starlit night) to 17 (snow in sunlight); beyond +-64 the float exposure
    // overflows or vanishes.
    if (!std::isfinite(ev100) || std::abs(ev100) > 64.0f)
        return fail("setExposureEV100: ev100 " + std::to_string(ev100) + " is not finite within [-64, 64]");
    return setExposure(exposureFromEV100(ev100));
}

} // namespace ml
