// GGX shading of one light at one surface point (the evaluation pass with a material target,
// kSpecPbr), one source for GLSL and the C++ reference, like shading.h (the reference compares with a
// tolerance: pow, sqrt and normalize are not correctly rounded on every side).
//
// Filament's and glTF's metallic-roughness model: alpha = perceptualRoughness^2 (the perceptual
// roughness clamped to 0.045 so that a mirror's lobe stays representable in fp32 and its highlight does
// not alias to a point); specular D * V * F with
//   D  GGX (Trowbridge-Reitz) normal distribution, a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2)
//   V  Smith-GGX height-correlated visibility, 0.5 / (n.l sqrt((n.v)^2 (1 - a^2) + a^2)
//                                                   + n.v sqrt((n.l)^2 (1 - a^2) + a^2))
//   F  Schlick, F0 + (1 - F0) (1 - v.h)^5 with F0 = mix(0.04, albedo, metalness)
// and Lambert diffuse albedo (1 - metalness) / pi. The incident light (range window, cone) is shading.h's
// lightIncidence, shared with the Lambert + Blinn-Phong model.
#ifndef ML_BRDF_H
#define ML_BRDF_H

#include "shaders/shared/shading.h"

#ifdef __cplusplus
namespace ml::gpu {
using glm::mix;
#endif

#define ML_PI 3.14159265f
#define ML_MIN_PERCEPTUAL_ROUGHNESS 0.045f

ML_FN float ggxDistribution(float nDotH, float a) {
    float a2 = a * a;
    float f = (nDotH * a2 - nDotH) * nDotH + 1.0f;
    return a2 / (ML_PI * f * f);
}

ML_FN float smithGgxCorrelated(float nDotV, float nDotL, float a) {
    float a2 = a * a;
    float ggxL = nDotV * sqrt((nDotL - nDotL * a2) * nDotL + a2);
    float ggxV = nDotL * sqrt((nDotV - nDotV * a2) * nDotV + a2);
    return 0.5f / (ggxV + ggxL);
}

ML_FN vec3 fresnelSchlick(vec3 f0, float vDotH) {
    float m = clamp(1.0f - vDotH, 0.0f, 1.0f);
    float m5 = (m * m) * (m * m) * m;
    return f0 + (vec3(1.0f) - f0) * m5;
}

// Radiance reflected towards the viewer (unit V) by one light, before visibility.
ML_FN vec3 shadeLightPbr(GpuLight L, vec3 P, vec3 N, vec3 V, vec3 albedo, float perceptualRoughness,
                         float metalness) {
    vec3 toLight;
    float falloff = lightIncidence(L, P, toLight);
    float nDotL = dot(N, toLight);
    if (nDotL <= 0.0f || falloff <= 0.0f) return vec3(0.0f);
    float r = clamp(perceptualRoughness, ML_MIN_PERCEPTUAL_ROUGHNESS, 1.0f);
    float m = clamp(metalness, 0.0f, 1.0f);
    float a = r * r;
    vec3 H = normalize(toLight + V);
    float nDotV = abs(dot(N, V)) + 1e-5f; // Filament: back-facing views (normal maps) stay finite
    float nDotH = clamp(dot(N, H), 0.0f, 1.0f);
    float vDotH = clamp(dot(V, H), 0.0f, 1.0f);
    vec3 f0 = mix(vec3(0.04f), albedo, m);
    vec3 specular =
        fresnelSchlick(f0, vDotH) * (ggxDistribution(nDotH, a) * smithGgxCorrelated(nDotV, nDotL, a));
    vec3 diffuse = albedo * ((1.0f - m) * (1.0f / ML_PI));
    vec3 color = vec3(L.colorSinOuter.x, L.colorSinOuter.y, L.colorSinOuter.z);
    return color * (falloff * nDotL) * (diffuse + specular);
}

#ifdef __cplusplus
} // namespace ml::gpu
#endif
#endif
