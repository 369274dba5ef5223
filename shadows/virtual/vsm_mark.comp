#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_mark: per shaded receiver pixel, each light of its cluster that has virtual shadow maps and that
// the surface faces (vsmFacesLight: the evaluation looks nothing up for the rest) marks the pages
// its lookup will read (resolution-matched mip, PCF kernel, normal-offset bias) and, near pool pressure,
// reserves two pages of its fallback chain (vsm_common.glsl's vsmMarkReceiver). Marks are bits, one per page-table entry, cleared at the start of the frame; the
// first want of an entry appends it to the request list (vsm_common.glsl's vsmWant).
// Clustered marking: the seed (RMVSM section 6) marks against every light and names this as future work.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_MARK_GROUP, local_size_y = ML_VSM_MARK_GROUP) in;
// Profiling only (ML_VSM_MARK_STAGE, vsm_programs.cpp; tools/vsm_mark_stages.py): 0 marks; 1..5 stop
// early to time the pass's parts, and then mark nothing (the frame's shadows are wrong): 1 returns at
// once (the dispatch), 2 after the depth read, 3 after the G-buffer, world position and cluster lookup,
// 4 after the light loop's reach and facing tests, 5 marks local lights only (directional skipped).
layout(constant_id = 0) const uint kStage = 0;

layout(binding = ML_VSM_MARK_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_VSM_MARK_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = ML_VSM_MARK_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_VSM_MARK_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_VSM_MARK_LIGHT_POOL, std430) readonly buffer Pool { uint pool[]; };
layout(binding = ML_VSM_MARK_DEPTH) uniform texture2D depthImage;
layout(binding = ML_VSM_MARK_NORMAL) uniform texture2D normalImage;
layout(binding = ML_VSM_MARK_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_MARK_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_MARK_COVERAGE, std430) readonly buffer Coverage { uint vsmCoverage[]; };
layout(binding = ML_VSM_MARK_MARKS, std430) coherent buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_MARK_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_MARK_RANK_BASE, std430) readonly buffer Ranks { uint vsmRankBase[]; }; // per (map slot, mip)
layout(binding = ML_VSM_MARK_REQUESTS, std430) writeonly buffer List { uint vsmList[]; };

#define VSM_CONST vsm
#define VSM_MAPS vsmMaps
#define VSM_COVER vsmCoverage
#define VSM_MARKS vsmMarks
#define VSM_COUNTERS vsmCounters
#define VSM_RANKS vsmRankBase
#define VSM_LIST vsmList
#define VSM_MARKING
#include "shaders/shared/cluster_list.glsl"
#include "shadows/virtual/vsm_common.glsl"

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size.x || px.y >= frame.size.y || kStage == 1u) return;
    float d = texelFetch(depthImage, ivec2(px), 0).r;
    // The profiling stages keep their last value alive with a test no real frame passes (an all-ones
    // bit pattern is a NaN, never a stored depth, normal or light count), so the compiler cannot drop it.
    if (kStage == 2u) {
        if (floatBitsToUint(d) == 0xFFFFFFFFu) atomicAdd(vsmCounters.listCount, 1u);
        return;
    }
    if (!hasSurface(d)) return;
    vec4 stored = texelFetch(normalImage, ivec2(px), 0);
    if (stored.w < 0.0) return; // ML_NOT_A_RECEIVER: the evaluation looks no shadow up here
    vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
    vec3 N = vsmNormalize(stored.xyz);
    uvec2 range = clusterLights(px, d);
    if (kStage == 3u) {
        if (floatBitsToUint(P.x + N.x) == 0xFFFFFFFFu || range.y == 0xFFFFFFFFu) atomicAdd(vsmCounters.listCount, 1u);
        return;
    }
    uint facing = 0u;
    for (uint i = 0; i < range.y; ++i) {
        GpuLight L = lights[ML_CLUSTER_LIGHT(range, i)];
        if (L.info.y == ML_VSM_NO_MAP || !lightReachesPoint(L, P) || !vsmFacesLight(L, P, N)) continue;
        if (kStage == 4u || (kStage == 5u && L.info.x == ML_LIGHT_DIRECTIONAL)) {
            facing += 1u;
            continue;
        }
        vsmMarkReceiver(L, L.info.y, P, N);
    }
    if (facing == 0xFFFFFFFFu) atomicAdd(vsmCounters.listCount, 1u);
}
