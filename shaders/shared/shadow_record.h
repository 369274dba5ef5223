// GpuShadowRecord's accessors and its view transform, one source for GLSL and the C++ twins
// (shadows/static/static_visibility.cpp, bake/reference/error_classes.cpp).
//
// The record keeps the world -> light view transform as a unit quaternion and a translation (a light
// view is a rigid motion: makeShadowRecord builds it from the frustum's lookAt matrix, setStaticShadow
// refuses any other). Every intermediate is `precise` and the C++ build uses -ffp-contract=off, so the
// shader and the CPU twin map a receiver to the same view position bit for bit.
#ifndef ML_SHADOW_RECORD_H
#define ML_SHADOW_RECORD_H

#include "shaders/shared/light_math.h"

#ifdef __cplusplus
namespace ml::gpu {
#endif

// info.x: method (bits 0-3: StaticMethod has six values), PCF radius (bits 4-7: at most
// ML_MAX_PCF_RADIUS, 4), resolution (bits 8-31: up to 2^24 - 1 texels a side; bake files stop at 65536).
ML_FN uint shadowRecordMethod(GpuShadowRecord r) {
    return r.info.x & 15u;
}
ML_FN uint shadowRecordRadius(GpuShadowRecord r) {
    return (r.info.x >> 4u) & 15u;
}
ML_FN uint shadowRecordResolution(GpuShadowRecord r) {
    return r.info.x >> 8u;
}
ML_FN uint shadowRecordInfo(uint method, uint radius, uint resolution) {
    return (method & 15u) | ((radius & 15u) << 4u) | (resolution << 8u);
}
// The same info word with another PCF radius (the lookup timer and the error classes vary it).
ML_FN uint shadowRecordWithRadius(uint info, uint radius) {
    return (info & ~0xF0u) | ((radius & 15u) << 4u);
}

// info.z bit 0: filter by level (Module::setShadowFilter): the MH, MMH, DAG-MH and CPVS lookups take the
// coarsest hierarchy level whose texel is at most a quarter of the receiver's pixel (shadowLevelStep); SM
// ignores it.
ML_FN bool shadowRecordByLevel(GpuShadowRecord r) {
    return (r.info.z & 1u) != 0u;
}

// The squared world size of the pixel that sees P: pixelAngle2 (FrameConstants.cameraPosition.w) is the
// square of a pixel's size at unit distance, (2 tan(fovY / 2) / height)^2. Distance, not view depth: a
// little larger off the view axis, and the same for every light.
ML_FN float shadowFootprint2(vec3 cameraPosition, vec3 P, float pixelAngle2) {
    ML_PRECISE float dx = P.x - cameraPosition.x;
    ML_PRECISE float dy = P.y - cameraPosition.y;
    ML_PRECISE float dz = P.z - cameraPosition.z;
    ML_PRECISE float d2 = dx * dx + dy * dy + dz * dz;
    ML_PRECISE float f2 = d2 * pixelAngle2;
    return f2;
}

// Levels above the finest whose texel first covers 1/ML_LEVEL_TEXELS_PER_PIXEL of the footprint: the
// smallest k <= maxStep with (ML_LEVEL_TEXELS_PER_PIXEL texelWorld 2^k)^2 >= footprint2. Scaling by a
// power of two and doubling are exact and the square is `precise`, so the shader and the CPU twin pick
// the same level (no log2, whose rounding differs between implementations).
ML_FN uint shadowLevelStep(float texelWorld, float footprint2, uint maxStep) {
    uint k = 0u;
    ML_PRECISE float w = texelWorld * float(ML_LEVEL_TEXELS_PER_PIXEL);
    ML_PRECISE float w2 = w * w;
    while (k < maxStep && w2 < footprint2) {
        w = w * 2.0f;
        w2 = w * w;
        k = k + 1u;
    }
    return k;
}

// v rotated by the unit quaternion q: v + w t + q.xyz x t with t = 2 q.xyz x v (two cross products).
ML_FN vec3 quatRotate(vec4 q, vec3 v) {
    ML_PRECISE float tx = 2.0f * (q.y * v.z - q.z * v.y);
    ML_PRECISE float ty = 2.0f * (q.z * v.x - q.x * v.z);
    ML_PRECISE float tz = 2.0f * (q.x * v.y - q.y * v.x);
    ML_PRECISE float rx = v.x + q.w * tx + (q.y * tz - q.z * ty);
    ML_PRECISE float ry = v.y + q.w * ty + (q.z * tx - q.x * tz);
    ML_PRECISE float rz = v.z + q.w * tz + (q.x * ty - q.y * tx);
    return vec3(rx, ry, rz);
}

// World point P in the light's view (the light looks down -Z).
ML_FN vec3 shadowViewPoint(GpuShadowRecord r, vec3 P) {
    vec3 v = quatRotate(r.rotation, P);
    ML_PRECISE float x = v.x + r.translation.x;
    ML_PRECISE float y = v.y + r.translation.y;
    ML_PRECISE float z = v.z + r.translation.z;
    return vec3(x, y, z);
}

// World direction N in the light's view.
ML_FN vec3 shadowViewVector(GpuShadowRecord r, vec3 N) {
    return quatRotate(r.rotation, N);
}

#ifdef __cplusplus
} // namespace ml::gpu
#endif
#endif
