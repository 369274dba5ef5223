// Shading of one light at one surface point, one source for GLSL and the C++ reference (the reference
// compares with a tolerance: pow and normalize are not correctly rounded on every side).
#ifndef ML_SHADING_H
#define ML_SHADING_H

#include "shaders/shared/light_math.h"

#ifdef __cplusplus
namespace ml::gpu {
using glm::clamp;
using glm::dot;
using glm::normalize;
using glm::smoothstep;
using std::pow;
#define ML_OUT(T) T&
#else
#define ML_OUT(T) out T
#endif

// Radiance reflected towards the viewer by one light, before visibility. Lambert diffuse plus a
// normalised Blinn-Phong lobe (shininess 32, specular albedo 0.04); range falloff is the windowed
// inverse square ((1 - (d/r)^4)^2 / d^2), zero at the range; the cone has a smooth edge from the
// inner to the outer half angle.
// The light's direction from P (unit) and its irradiance scale before n.l: the range window times the
// inverse square, times the cone's smooth edge for a spot; 1 for a directional light.
ML_FN float lightIncidence(GpuLight L, vec3 P, ML_OUT(vec3) toLight) {
    float falloff = 1.0f;
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        toLight = -vec3(L.directionCosOuter.x, L.directionCosOuter.y, L.directionCosOuter.z);
    } else {
        vec3 d = vec3(L.positionRange.x, L.positionRange.y, L.positionRange.z) - P;
        float dist2 = max(dot(d, d), 1e-4f);
        toLight = d / sqrt(dist2);
        float ratio2 = dist2 * L.params.y;
        float window = clamp(1.0f - ratio2 * ratio2, 0.0f, 1.0f);
        falloff = window * window / dist2;
        if (L.info.x == ML_LIGHT_SPOT) {
            float cosAngle =
                -dot(toLight, vec3(L.directionCosOuter.x, L.directionCosOuter.y, L.directionCosOuter.z));
            falloff *= smoothstep(L.directionCosOuter.w, L.params.x, cosAngle);
        }
    }
    return falloff;
}

ML_FN vec3 shadeLight(GpuLight L, vec3 P, vec3 N, vec3 V, vec3 albedo) {
    vec3 toLight;
    float falloff = lightIncidence(L, P, toLight);
    float nDotL = dot(N, toLight);
    if (nDotL <= 0.0f || falloff <= 0.0f) return vec3(0.0f);
    vec3 H = normalize(toLight + V);
    float spec = (32.0f + 8.0f) / (8.0f * 3.14159265f) * pow(max(dot(N, H), 0.0f), 32.0f) * 0.04f;
    vec3 color = vec3(L.colorSinOuter.x, L.colorSinOuter.y, L.colorSinOuter.z);
    return color * (falloff * nDotL) * (albedo * (1.0f / 3.14159265f) + vec3(spec));
}

// Filmic curve (Narkowicz's ACES fit) then the sRGB transfer function; input is exposed HDR.
ML_FN vec3 toneMap(vec3 hdr) {
    vec3 x = hdr;
    vec3 y = clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), vec3(0.0f), vec3(1.0f));
    vec3 s;
    for (int i = 0; i < 3; ++i)
        s[i] = y[i] <= 0.0031308f ? y[i] * 12.92f : 1.055f * pow(y[i], 1.0f / 2.4f) - 0.055f;
    return s;
}

#ifdef __cplusplus
} // namespace ml::gpu
#endif
#endif
