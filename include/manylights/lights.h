// A light as the host describes it (Module::addLight, setLight), its units, and the validation the module
// runs on it. Plain types only (manylights/types.h): the layout is asserted below.
#pragma once
#include "manylights/enums.h"
#include "manylights/result.h"
#include "manylights/types.h"

#include <cstddef>
#include <cstdint>

namespace ml {

// What LightDesc::intensity measures (Filament's conventions). Candela: luminous intensity in candela for
// spot and point lights, illuminance in lux for directional ones; the shading has always used it so
// (inverse-square falloff of the intensity, no conversion), so it is the default and leaves every image
// as it was. Lumen: luminous power of a spot or point light, converted to candela as Filament does
// (point: lm / 4 pi; spot: lm / pi, independent of the cone so that narrowing it does not brighten it);
// refused for a directional light. Colour multiplies the intensity (keep it of luminance ~1 for
// photometric values). Exposure for physical values: Module::setExposureEV100.
enum class LightUnit : uint32_t { Candela, Lumen };

struct LightDesc {
    LightKind kind = LightKind::Spot;
    Float3 position{0.0f};
    Float3 direction{0.0f, -1.0f, 0.0f}; // spot and directional; normalised by the module, not zero
    Float3 color{1.0f};
    float intensity = 1.0f;
    float range = 10.0f;
    float outerAngle = 0.6f;  // half angle, radians, (0, pi/2) for spots
    float innerAngle = 0.4f;  // [0, outer]
    bool dynamic = false;     // moves: its shadows are never baked (virtual shadow maps draw every caster)
    bool castsShadows = true; // false: no static bake is used and no virtual shadow map is made
    LightUnit unit = LightUnit::Candela;
    // Shadow bias of this light's lookups, static bakes and virtual shadow maps alike (finite, >= 0, at most
    // kMaxShadowBias): the receiver's depth is compared shadowDepthBias texels nearer to the light, after
    // moving it along its normal by shadowNormalBias times the module's offset ((1 + PCF radius) texels for
    // a bake, one texel for a virtual shadow map). CPVS bakes use their own voxel bias and ignore both.
    float shadowDepthBias = 0.5f;
    float shadowNormalBias = 1.0f;
    // Static resolution hint: Module::bakeStaticShadows renders this light's maps at shadowResolution^2
    // (8..16384) instead of the call's resolution; 0: the call's. Virtual shadow maps do not read it.
    uint32_t shadowResolution = 0;
    // Virtual shadow maps: this light's lookups pick texels shadowTexelScale times finer per axis than
    // VsmSettings::texelsPerPixel asks (a power of two, 1/4..8; 2 is one mip finer: up to 4x this light's
    // pages). Finer texels flicker less under a moving camera (docs/accuracy.md section 7); a host spends
    // them on the lights whose shadows are seen most. Page contents do not depend on it, so changing it
    // keeps the cached pages. Static bakes do not read it (shadowResolution is theirs).
    float shadowTexelScale = 1.0f;
};
// 80 bytes whatever the includer's compile definitions (bools padded to 4 before `unit`).
static_assert(sizeof(LightDesc) == 80 && offsetof(LightDesc, position) == 4 &&
              offsetof(LightDesc, color) == 28 && offsetof(LightDesc, dynamic) == 56 &&
              offsetof(LightDesc, unit) == 60 && offsetof(LightDesc, shadowResolution) == 72 &&
              offsetof(LightDesc, shadowTexelScale) == 76);
constexpr float kMaxShadowBias = 64.0f; // texels; past that a light's shadows detach from their casters

// The intensity the shading uses (candela, or lux for a directional light) after LightDesc::unit.
float lightIntensityCandela(const LightDesc& light);
// Filament's photometric exposure: the scale on luminance (cd/m^2) before tone mapping for an exposure
// value at ISO 100, 1 / (1.2 * 2^ev100) (the 1.2 is the saturation-based sensitivity's 78/(100 * 0.65));
// and the EV100 of a camera: log2(aperture^2 / shutterSeconds * 100 / iso).
float exposureFromEV100(float ev100);
float ev100FromCamera(float aperture, float shutterSeconds, float iso);

// A one-line reason when a parameter is NaN, infinite, negative or out of its range (addLight and
// setLight call it; a host or a command line may call it first).
Result<void> validateLight(const LightDesc& light);

} // namespace ml
