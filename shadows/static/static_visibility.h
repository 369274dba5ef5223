// The CPU twin of the shader's static shadow visibility of one receiver for one light's baked record:
// the same text, shaders/static/static_pcf.h, compiled as C++ (see there for the bias and the filter). Used
// by the evaluation pass's CPU reference and by accuracy measurements that run without a GPU.
#pragma once
#include "shaders/shared/gpu_types.h"
#include "shaders/shared/shadow_record.h"
#include "shadows/static/static_method.h"

namespace ml {

// The default per-light bias (LightDesc::shadowDepthBias, shadowNormalBias; GpuShadowRecord.bias): half a
// texel of depth, and the normal offset of (1 + PCF radius) texels unscaled.
constexpr float kDefaultShadowDepthBias = 0.5f;
constexpr float kDefaultShadowNormalBias = 1.0f;

// The record of a light frustum and a bake: method, base word in `data`, resolution, PCF radius, and the
// default bias (the module writes the light's own). The frustum's view must be rigid (rigidView).
gpu::GpuShadowRecord makeShadowRecord(StaticMethod method, const LightFrustum& frustum, uint32_t base,
                                      uint32_t resolution, uint32_t pcfRadius);

// True when `view` is a rigid motion: finite, bottom row 0 0 0 1, and a rotation R (det > 0) with every
// entry of R^T R within `tolerance` of the identity's. The default, 1e-5, bounds what GpuShadowRecord's
// quaternion drops: a uniform scale within 5e-6 of 1 (0.04 texel at the edge of a 16384^2 map); lookAt
// views are orthonormal to ~1e-7. A bake file's frustum may be anything. The camera's check
// (cameraFromMatrices) takes 1e-3.
bool rigidView(const glm::mat4& view, float tolerance = 1e-5f);

// Receiver depth in the light's integer depth space, as the shader quantises it (float arithmetic).
uint32_t staticQuantizeFloat(float z, float farPlane);

// Visibility in [0, 1] (fraction of lit PCF taps). `data` holds the validated words of the record.
// footprint2: the squared world size of the receiver's pixel (gpu::shadowFootprint2), read only by a
// record that filters by level (gpu::shadowRecordByLevel); 0 takes the finest level.
float staticVisibility(const gpu::GpuShadowRecord& record, const uint32_t* data, glm::vec3 P, glm::vec3 N,
                       float footprint2 = 0.0f);

// How a DAG-MH record's lookup at (P, N) is answered (the shader's dagmhBoundsClass over the kernel's
// in-map taps): 1 lit or 2 shadowed by the value bounds alone (one word), 0 undecided (descent and value
// decode), 3 before the map or off it, or not DAG-MH. Counts for bench static; staticVisibility's own path.
uint32_t dagmhBoundsDecision(const gpu::GpuShadowRecord& record, const uint32_t* data, glm::vec3 P,
                             glm::vec3 N);

// The evaluation pass's static term for a light: its record (a point light's by cube face), or 1.
float lightStaticVisibility(const gpu::GpuLight& light, const gpu::GpuShadowRecord* records,
                            const uint32_t* data, glm::vec3 P, glm::vec3 N, float footprint2 = 0.0f);

} // namespace ml
