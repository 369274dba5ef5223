#version 460
#extension GL_GOOGLE_include_directive : require
// The host's own lighting pass, written against the module's GLSL include and its binding contract
// only (manylights/module.h, HostShaderBindings): per pixel of the host's G-buffer, ambient plus every
// light of the pixel's cluster, shaded with the module's BRDF and multiplied by the module's static x
// dynamic shadow visibility. Recorded after module.record(cmd) in the same command buffer, into a
// buffer of the frame's slot: the radiance and its exposed tone map (the module's, from the include),
// which the example compares with the module's own output (HDR and LDR frames).
// Compiled with glslangValidator -I${MANYLIGHTS_GLSL_INCLUDE_DIR} (examples/host/CMakeLists.txt).
#define ML_LIGHTS_SET 1 // the module's 12 buffers: the host's set 1, bindings 0-11
#include "manylights/manylights.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The host's own resources, set 0: its G-buffer (SHADER_READ_ONLY_OPTIMAL after the hand-over to the
// module) and the slot's result buffer (per pixel, row-major: linear radiance, and its tone map times
// the module's exposure as RGBA8 UNORM bytes).
layout(set = 0, binding = 0) uniform texture2D gbufferDepth;  // reversed Z: 0 = sky
layout(set = 0, binding = 1) uniform texture2D gbufferNormal; // world normal
layout(set = 0, binding = 2) uniform texture2D gbufferAlbedo; // linear
struct HostPixel {
    vec3 radiance;
    uint toneMapped;
};
layout(set = 0, binding = 3, std430) writeonly buffer Result { HostPixel pixels[]; };

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    uvec2 size = frame.size.xy; // the targets' size (frame constants of the module)
    if (px.x >= size.x || px.y >= size.y) return;
    float d = texelFetch(gbufferDepth, ivec2(px), 0).r;
    vec3 color = frame.sky.rgb;
    if (hasSurface(d)) {
        vec3 P = mlWorldPosition(px, d);
        vec3 Nraw = texelFetch(gbufferNormal, ivec2(px), 0).xyz;
        vec3 N = normalize(Nraw);
        vec3 albedo = texelFetch(gbufferAlbedo, ivec2(px), 0).rgb;
        vec3 V = normalize(mlCameraPosition() - P);
        color = albedo * frame.ambient.rgb;
        // For each light of the cluster at this pixel and depth: shading x static x dynamic visibility.
        uvec2 range = mlClusterRange(px, d);
        for (uint i = 0; i < mlRangeCount(range); ++i) {
            GpuLight L = mlRangeLight(range, i);
            vec3 c = shadeLight(L, P, N, V, albedo);
            if (c != vec3(0.0)) color += c * mlLightVisibility(L, P, Nraw);
        }
    }
    uint ldr = packUnorm4x8(vec4(toneMap(color * frame.ambient.w), 1.0)); // ambient.w: the exposure
    pixels[px.y * size.x + px.x] = HostPixel(color, ldr);
}
