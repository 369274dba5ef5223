#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_view (demo --view vsm): colours each shaded pixel by the virtual shadow map page its first
// shadowed light reads: the hue is the mip (or clip level) the lookup wanted, 0 red, 1 orange, 2 yellow,
// 3 green, 4 cyan, 5 blue, 6+ magenta; bright where the page was drawn this frame, dim where it came
// from the cache; grey where no dynamic caster covers the point (no page needed), white where the
// lookup fell back to a coarser page. Blended over the shaded frame so the scene stays readable.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_MARK_GROUP, local_size_y = ML_VSM_MARK_GROUP) in;

layout(binding = ML_VSM_VIEW_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_VSM_VIEW_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = ML_VSM_VIEW_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_VSM_VIEW_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_VSM_VIEW_LIGHT_POOL, std430) readonly buffer Pool { uint pool[]; };
layout(binding = ML_VSM_VIEW_DEPTH) uniform texture2D depthImage;
layout(binding = ML_VSM_VIEW_NORMAL) uniform texture2D normalImage;
layout(binding = ML_VSM_VIEW_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_VIEW_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_VIEW_COVERAGE, std430) readonly buffer Coverage { uint vsmCoverage[]; };
layout(binding = ML_VSM_VIEW_TABLE, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_VIEW_PAGE_POOL, std430) readonly buffer PagePool { uint vsmPool[]; };
layout(binding = ML_VSM_VIEW_OUTPUT, rgba8) uniform image2D outputImage;

#define VSM_CONST vsm
#define VSM_MAPS vsmMaps
#define VSM_COVER vsmCoverage
#define VSM_TABLE vsmTable
#define VSM_POOL vsmPool
#include "shaders/shared/cluster_list.glsl"
#include "shadows/virtual/vsm_common.glsl"

const vec3 kMipColours[7] = vec3[7](vec3(1.0, 0.15, 0.1), vec3(1.0, 0.55, 0.1), vec3(0.95, 0.9, 0.1),
                                    vec3(0.2, 0.9, 0.2), vec3(0.1, 0.85, 0.9), vec3(0.2, 0.35, 1.0),
                                    vec3(0.85, 0.2, 0.9));

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
        VsmChoice want = vsmChoose(L, L.info.y, P, Nunit);
        if (want.tap.ok == 0u) continue;
        VsmChoice c;
        uint status, depth;
        vsmVisibility(L, L.info.y, P, N, c, status, depth);
        uint level = L.info.x == ML_LIGHT_DIRECTIONAL ? want.map - L.info.y : want.mip;
        vec3 colour = kMipColours[min(level, 6u)];
        if (status == ML_VSM_PROBE_NO_CASTER) {
            colour = vec3(0.35);
        } else if (status == ML_VSM_PROBE_FALLBACK || status == ML_VSM_PROBE_MISSING) {
            colour = vec3(1.0);
        } else {
            uint pt = vsmTable[vsmEntryOf(c.map, c.mip, c.tap.texel)];
            if ((pt & ML_VSM_DIRTY) == 0u) colour *= 0.45; // cached: dim
        }
        vec3 shaded = imageLoad(outputImage, ivec2(px)).rgb;
        imageStore(outputImage, ivec2(px), vec4(mix(shaded, colour, 0.65), 1.0));
        return;
    }
}
