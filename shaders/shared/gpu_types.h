// GPU structs, defined once for C++ and GLSL. Members are vec4/uvec4/mat4, or 4-byte scalars in runs
// that keep every vec4 at a 16-byte offset (GpuVertex's floats, FrameCounters' uints) and 64-bit
// counters at 8-byte offsets, so std430 (and std140 for the uniform ones) and C++ agree without padding
// rules; C++ static_asserts sizes and offsets below. Push blocks follow the same rules (feature headers:
// culling/culling_push.h, shadows/virtual/vsm_types.h, ...).
#ifndef ML_GPU_TYPES_H
#define ML_GPU_TYPES_H

#include "shaders/shared/config.h"

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
namespace ml::gpu {
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using uvec2 = glm::uvec2;
using mat4 = glm::mat4;
using uint = uint32_t;
using uint64_t = ::uint64_t;
#define ML_STRUCT(name) struct name
#else
#define ML_STRUCT(name) struct name
#endif

// One light, 80 bytes. Spot: cone around `direction` with half angle outer (cos/sin kept for the
// cone-sphere test) and a smooth edge starting at inner. Point: cosOuter = -1. Directional: position
// unused, range = +inf in effect (info.x says so).
ML_STRUCT(GpuLight) {
    vec4 positionRange;     // xyz world position, w range (metres)
    vec4 directionCosOuter; // xyz unit direction, w cos(outer half angle)
    vec4 colorSinOuter;     // rgb colour * intensity, w sin(outer half angle)
    vec4 params;            // x cos(inner half angle), y 1/range^2, z unused, w 1 for a wide light
                            // (its clusters come from the wide pass, culling/culling.h), else 0
    uvec4 info;             // x type (ML_LIGHT_*), y first virtual shadow map (ML_VSM_NO_MAP: none),
                            // z static shadow record (ML_NO_SHADOW: none), w light id
};

// A mesh vertex as the module stores it (MeshVertex in manylights/module.h): pulled from a storage
// buffer by the G-buffer and shadow-page vertex shaders. 24 bytes, no padding (std430 float members).
ML_STRUCT(GpuVertex) {
    float px, py, pz;
    float nx, ny, nz;
};

// Per-instance data, one per module instance and frame in flight. 160 bytes.
ML_STRUCT(GpuInstance) {
    mat4 model;
    mat4 normalMatrix;
    vec4 albedo;   // rgb linear albedo, w 1
    vec4 material; // x perceptual roughness, y metalness (glTF metallicRoughness factors), z the G-buffer
                   // normal's w: 1 a shadow receiver, ML_NOT_A_RECEIVER not (shadows/unshadowed light), w 0
};

// A light's baked static shadow (shadows/static/static_method.h): where its words start in the one
// static-shadow buffer, the light frustum they were rendered with, and its bias. 80 bytes.
// The evaluation reads a record per lit pixel-light pair, and on a CPU device (lavapipe) every word of
// it is a gather across the lanes, so the record holds what the lookup reads in few words: the view as
// a unit quaternion and a translation (7 words, not a 3x4 matrix's 12; a light view is rigid), and
// method, PCF radius and resolution in one word (shadowRecordMethod and the other accessors below).
// A DAG-MH one-tap lookup reads 14 words of it (21 with the matrix and four info words).
ML_STRUCT(GpuShadowRecord) {
    vec4 rotation; // world -> light view rotation, a unit quaternion (x, y, z, w) (the light looks down -Z)
    vec4 translation; // xyz: view(P) = rotate(rotation, P) + translation (shadowViewPoint), w 0
    vec4 frustum;     // x tan(fov / 2), y near, z far, w log(far / near)
    uvec4 info;       // x method (StaticMethod, bits 0-3, 0 = none) | PCF radius << 4 (0 = one tap) |
                      // resolution << 8; y base word; z bit 0 filter by level (shadowRecordByLevel); w 0
    vec4 bias;        // the light's shadow bias (LightDesc): x depth bias in texels (default 0.5), y scale on
                      // the normal offset of (1 + PCF radius) texels (default 1); CPVS ignores both; zw 0
};

// Per-frame constants (uniform buffer), 240 bytes.
ML_STRUCT(FrameConstants) {
    mat4 viewProj;
    mat4 invViewProj;
    vec4 cameraPosition; // xyz, w (2 tan(fovY / 2) / height)^2: a pixel's squared size at unit distance
    uvec4 size;          // x width, y height, z tiles x, w tiles y
    uvec4 cluster;       // x slices, y tile size, z visible light count, w culling mode
    vec4 depth;          // x near, y far, z near*far, w far-near
    vec4 ambient;        // rgb ambient (moonlight), w exposure
    vec4 sky;            // rgb background, w unused
    uvec4 limits;        // x light-list pool capacity (entries), y cluster count, zw unused
};

// World-space bounds of the pixels that fall into one cluster (tile x slice). lo.w = 1 when at
// least one pixel is in the cluster, else 0 (the cluster is skipped).
ML_STRUCT(ClusterBounds) {
    vec4 lo;
    vec4 hi;
};

// Frame statistics written by the passes with atomics, read back one frame later.
ML_STRUCT(FrameCounters) {
    uint poolCursor;           // light-list entries allocated
    uint overflowClusters;     // clusters whose list did not fit in the pool
    uint occupiedClusters;     // clusters holding at least one pixel
    uint maxClusterLights;     // longest list (including overflowed ones' true length)
    uint64_t clusterLightsSum; // sum of list lengths over occupied clusters
    uint64_t surfacePixels;    // pixels with geometry
    uint64_t evaluatedSum;     // sum over surface pixels of lights evaluated
    uint64_t reachingSum;      // sum over surface pixels of lights whose cone and range hold the point
};

#ifdef __cplusplus
static_assert(sizeof(GpuLight) == 80);
static_assert(sizeof(GpuVertex) == 24);
static_assert(sizeof(GpuInstance) == 160);
static_assert(offsetof(GpuInstance, material) == 144);
static_assert(offsetof(GpuLight, info) == 64);
static_assert(sizeof(FrameConstants) == 240);
static_assert(offsetof(FrameConstants, size) == 144);
static_assert(offsetof(FrameConstants, limits) == 224);
static_assert(sizeof(ClusterBounds) == 32);
static_assert(sizeof(GpuShadowRecord) == 80);
static_assert(offsetof(GpuShadowRecord, translation) == 16);
static_assert(offsetof(GpuShadowRecord, info) == 48);
static_assert(offsetof(GpuShadowRecord, bias) == 64);
static_assert(sizeof(FrameCounters) == 48);
static_assert(offsetof(FrameCounters, clusterLightsSum) == 16);
} // namespace ml::gpu
#endif

#endif
