// The light-complexity heat map's colour ramp (demo --view lights / lights-reaching), one source for
// lights/view_lights.comp and the test. Piecewise linear in the count between stops:
//   0 black, 1 dark blue, 4 blue, 8 cyan, 16 green, 32 yellow, 64 red, 128 and more white.
// Only +, -, *, / and comparisons, so both sides agree up to the 8-bit store's rounding.
#ifndef ML_HEAT_H
#define ML_HEAT_H

#include "shaders/shared/light_math.h"

#ifdef __cplusplus
namespace ml::gpu {
#endif

ML_FN vec3 heatColor(uint count) {
    float c = float(count);
    if (c <= 0.0f) return vec3(0.0f, 0.0f, 0.0f);
    if (c >= 128.0f) return vec3(1.0f, 1.0f, 1.0f);
    float lo = 1.0f, hi = 4.0f;
    vec3 a = vec3(0.0f, 0.0f, 0.35f), b = vec3(0.0f, 0.25f, 1.0f);
    if (c >= 64.0f) {
        lo = 64.0f;
        hi = 128.0f;
        a = vec3(1.0f, 0.05f, 0.0f);
        b = vec3(1.0f, 1.0f, 1.0f);
    } else if (c >= 32.0f) {
        lo = 32.0f;
        hi = 64.0f;
        a = vec3(1.0f, 0.9f, 0.0f);
        b = vec3(1.0f, 0.05f, 0.0f);
    } else if (c >= 16.0f) {
        lo = 16.0f;
        hi = 32.0f;
        a = vec3(0.1f, 0.85f, 0.1f);
        b = vec3(1.0f, 0.9f, 0.0f);
    } else if (c >= 8.0f) {
        lo = 8.0f;
        hi = 16.0f;
        a = vec3(0.0f, 0.85f, 0.9f);
        b = vec3(0.1f, 0.85f, 0.1f);
    } else if (c >= 4.0f) {
        lo = 4.0f;
        hi = 8.0f;
        a = vec3(0.0f, 0.25f, 1.0f);
        b = vec3(0.0f, 0.85f, 0.9f);
    }
    float t = (c - lo) / (hi - lo);
    return a + (b - a) * t;
}

#ifdef __cplusplus
} // namespace ml::gpu
#endif
#endif
