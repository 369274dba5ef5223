#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_probe: the evaluation pass's virtual-shadow-map lookup, written out per (shaded pixel, light with
// maps): the map, mip and texel it read, the depth there and how it got it (page, fallback, no caster,
// missing). `manylights check vsm` and the tests compare each record with a full reference map of the
// same casters at the same mip (CPU rasteriser); nothing else reads it.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_MARK_GROUP, local_size_y = ML_VSM_MARK_GROUP) in;

layout(binding = ML_VSM_PROBE_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_VSM_PROBE_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = ML_VSM_PROBE_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_VSM_PROBE_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_VSM_PROBE_LIGHT_POOL, std430) readonly buffer Pool { uint pool[]; };
layout(binding = ML_VSM_PROBE_DEPTH) uniform texture2D depthImage;
layout(binding = ML_VSM_PROBE_NORMAL) uniform texture2D normalImage;
layout(binding = ML_VSM_PROBE_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_PROBE_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_PROBE_COVERAGE, std430) readonly buffer Coverage { uint vsmCoverage[]; };
layout(binding = ML_VSM_PROBE_TABLE, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_PROBE_PAGE_POOL, std430) readonly buffer PagePool { uint vsmPool[]; };
layout(binding = ML_VSM_PROBE_PROBES, std430) buffer Probes { uint probeCount; uint probeCapacity; uint probeOverflow; uint pad; GpuVsmProbe probes[]; };

#define VSM_CONST vsm
#define VSM_MAPS vsmMaps
#define VSM_COVER vsmCoverage
#define VSM_TABLE vsmTable
#define VSM_POOL vsmPool
#include "shaders/shared/cluster_list.glsl"
#include "shadows/virtual/vsm_common.glsl"

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size.x || px.y >= frame.size.y) return;
    float d = texelFetch(depthImage, ivec2(px), 0).r;
    if (!hasSurface(d)) return;
    vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
    vec4 stored = texelFetch(normalImage, ivec2(px), 0);
    if (stored.w < 0.0) return; // not a receiver: no lookup (evaluate.comp), no marks (vsm_mark)
    vec3 N = stored.xyz;
    vec3 Nunit = vsmNormalize(N);
    uvec2 range = clusterLights(px, d);
    for (uint i = 0; i < range.y; ++i) {
        GpuLight L = lights[ML_CLUSTER_LIGHT(range, i)];
        if (L.info.y == ML_VSM_NO_MAP || !lightReachesPoint(L, P) || !vsmFacesLight(L, P, Nunit)) continue;
        VsmChoice c;
        uint status, depth;
        vsmVisibility(L, L.info.y, P, N, c, status, depth);
        if (c.tap.ok == 0u) continue;
        uint slot = atomicAdd(probeCount, 1u);
        if (slot >= probeCapacity) { atomicAdd(probeOverflow, 1u); continue; }
        probes[slot].texel = uvec4(c.map, c.mip, uint(c.tap.texel.x), uint(c.tap.texel.y));
        probes[slot].info = uvec4(px.y * frame.size.x + px.x, L.info.w, depth, status);
        probes[slot].tap = uvec4(c.tap.depth, 0u, 0u, 0u);
    }
}
