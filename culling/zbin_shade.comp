#version 460
#extension GL_GOOGLE_include_directive : require
// Shading-loop probe for the Z-binning comparison (culling/zbin.h; bench culling --compare-zbin): per
// pixel with geometry, shadeLight (shaders/shared/shading.h, the evaluation pass's Blinn-Phong light
// term) summed over the pixel's candidates, without visibility. kSpecSource 0: the footprint
// clusters' list (ranges / pool of the frame, clusterLights); 1: the Z-bin candidates (tile mask bits
// within the bin's [min, max], then the wide lights). The same loop body for both, so the difference
// in time is what the extra candidates cost the evaluation (visibility runs only where a light
// shades, the same lights in both). The sum goes to `shaded` (rgb, 1 for a pixel with geometry, 0
// without): candidates that do not reach the pixel add zero (the range window and the cone edge are 0
// there), so both sources give the same image up to the order of the additions (tests compare).
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/shading.h"
#include "culling/zbin_types.h"
#include "culling/zbin_bindings.h"

layout(local_size_x = ML_ZBIN_GROUP / 8, local_size_y = 8) in;
layout(constant_id = 0) const uint kSpecSource = 0;
layout(push_constant) uniform Push { ZBinPush push; };

layout(binding = ML_ZBIN_SHADE_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_ZBIN_SHADE_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = ML_ZBIN_SHADE_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_ZBIN_SHADE_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_ZBIN_SHADE_POOL, std430) readonly buffer Pool { uint pool[]; };
layout(binding = ML_ZBIN_SHADE_SORTED, std430) readonly buffer Sorted { ZBinLight sorted[]; };
layout(binding = ML_ZBIN_SHADE_MASKS, std430) readonly buffer Masks { uint masks[]; };
layout(binding = ML_ZBIN_SHADE_BINS, std430) readonly buffer Bins { uint bins[]; };
layout(binding = ML_ZBIN_SHADE_WIDE, std430) readonly buffer Wide { uint wide[]; };
layout(binding = ML_ZBIN_SHADE_DEPTH) uniform texture2D depthImage;
layout(binding = ML_ZBIN_SHADE_NORMAL) uniform texture2D normalImage;
layout(binding = ML_ZBIN_SHADE_OUT, std430) writeonly buffer Shaded { vec4 shaded[]; }; // row-major pixels

#include "shaders/shared/cluster_list.glsl"

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size.x || px.y >= frame.size.y) return;
    float d = texelFetch(depthImage, ivec2(px), 0).r;
    if (!hasSurface(d)) {
        shaded[px.y * frame.size.x + px.x] = vec4(0.0);
        return;
    }
    vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
    vec3 N = normalize(texelFetch(normalImage, ivec2(px), 0).xyz);
    vec3 V = normalize(frame.cameraPosition.xyz - P);
    vec3 albedo = vec3(0.5);
    vec3 hdr = vec3(0.0);
    if (kSpecSource == 0u) {
        uvec2 range = clusterLights(px, d);
        for (uint i = 0; i < range.y; ++i) hdr += shadeLight(lights[ML_CLUSTER_LIGHT(range, i)], P, N, V, albedo);
    } else {
        uint bin = zbinOf(linearDepth(d, frame.depth), push.binNear, push.binScale, push.bins);
        uint range = bins[bin], lo = range & 0xFFFFu, hi = range >> 16u;
        uint tile = (px.y / frame.cluster.y) * frame.size.z + px.x / frame.cluster.y;
        for (uint word = lo >> 5u; lo <= hi && word <= (hi >> 5u); ++word) {
            uint bits = masks[tile * push.words + word];
            uint first = word == (lo >> 5u) ? (lo & 31u) : 0u;
            uint last = word == (hi >> 5u) ? (hi & 31u) : 31u;
            bits &= (last == 31u ? 0xFFFFFFFFu : ((1u << (last + 1u)) - 1u)) & ~((1u << first) - 1u);
            while (bits != 0u) {
                uint i = word * 32u + uint(findLSB(bits));
                bits &= bits - 1u;
                hdr += shadeLight(lights[sorted[i].light], P, N, V, albedo);
            }
        }
        for (uint k = 0u; k < push.wide; ++k) hdr += shadeLight(lights[wide[k]], P, N, V, albedo);
    }
    shaded[px.y * frame.size.x + px.x] = vec4(hdr, 1.0);
}
