// The module's lights and shadows for a host's own shaders (forward, transparent, decal passes), and
// for the module's evaluation pass (lights/evaluate.comp), which includes this file: one lookup, so the
// host's result and the module's cannot drift (HostShader.ForwardPassMatchesEvaluation compares them).
//
// Host use (installed: include/manylights/manylights.glsl is this file with its includes inlined,
// cmake/install.cmake; compile with -I<prefix>/include):
//   #version 460
//   #extension GL_GOOGLE_include_directive : require
//   #define ML_LIGHTS_SET 1        // optional: descriptor set of the module's buffers (default 0)
//   #define ML_LIGHTS_BINDING 0    // optional: their first binding (default 0)
//   #include "manylights/manylights.glsl"
//   ...
//   uvec2 range = mlClusterRange(pixel, depth);            // the cluster list at this pixel and depth
//   for (uint i = 0; i < mlRangeCount(range); ++i) {
//       GpuLight L = mlRangeLight(range, i);
//       vec3 c = shadeLight(L, P, N, V, albedo);           // the module's BRDF (shaders/shared/shading.h)
//       if (c != vec3(0.0)) color += c * mlLightVisibility(L, P, Nraw);
//   }
// The buffers: manylights/host_bindings.h lists them (offset, type); Module::hostShaderBindings()
// gives the handles for the frame record() just recorded (manylights/module.h has the contract).
//
// `pixel` and `depth` are in the module's frame: the pixel of the targets' size and the reversed-Z
// depth of Module::viewProjection() (a host pass drawn with it has them as gl_FragCoord.xy, .z).
// Cluster lists are built for the G-buffer's surfaces: a cluster holds the lights reaching the
// G-buffer pixels in it, so a fragment at another depth (a transparent surface in front of the opaque
// one) may find an incomplete or empty list there; such passes use mlVisibleLights() (every light in
// the view: correct, slower). Names this file declares (reserved for the includer): the blocks Ml*,
// their members frame, sliceFar, lights, ranges, pool, staticWords, shadowRecords, vsm, vsmMaps,
// vsmCoverage, vsmTable, vsmPool, and the functions of the files it includes.
#ifndef ML_MANYLIGHTS_LIGHTS_GLSL
#define ML_MANYLIGHTS_LIGHTS_GLSL

#include "shaders/shared/glsl_common.glsl"
#include "manylights/host_bindings.h"
#include "shadows/virtual/vsm_types.h"
#include "shaders/shared/shading.h"

#ifndef ML_LIGHTS_SET
#define ML_LIGHTS_SET 0
#endif
#ifndef ML_LIGHTS_BINDING
#define ML_LIGHTS_BINDING 0
#endif
#define ML_LIGHTS_UBO(offset) layout(set = ML_LIGHTS_SET, binding = ML_LIGHTS_BINDING + offset)
#define ML_LIGHTS_SSBO(offset) layout(set = ML_LIGHTS_SET, binding = ML_LIGHTS_BINDING + offset, std430)

ML_LIGHTS_UBO(ML_HOST_FRAME) uniform MlFrame { FrameConstants frame; };
ML_LIGHTS_SSBO(ML_HOST_SLICES) readonly buffer MlSlices { float sliceFar[]; };
ML_LIGHTS_SSBO(ML_HOST_LIGHTS) readonly buffer MlLights { GpuLight lights[]; };
ML_LIGHTS_SSBO(ML_HOST_RANGES) readonly buffer MlRanges { uvec2 ranges[]; };
ML_LIGHTS_SSBO(ML_HOST_POOL) readonly buffer MlPool { uint pool[]; };
ML_LIGHTS_SSBO(ML_HOST_STATIC_WORDS) readonly buffer MlStaticWords { uint staticWords[]; };
ML_LIGHTS_SSBO(ML_HOST_SHADOW_RECORDS) readonly buffer MlShadowRecords { GpuShadowRecord shadowRecords[]; };
ML_LIGHTS_UBO(ML_HOST_VSM_CONST) uniform MlVsmConst { VsmConstants vsm; };
ML_LIGHTS_SSBO(ML_HOST_VSM_MAPS) readonly buffer MlVsmMaps { GpuVsmMap vsmMaps[]; };
ML_LIGHTS_SSBO(ML_HOST_VSM_COVERAGE) readonly buffer MlVsmCoverage { uint vsmCoverage[]; };
ML_LIGHTS_SSBO(ML_HOST_VSM_TABLE) readonly buffer MlVsmTable { uint vsmTable[]; };
ML_LIGHTS_SSBO(ML_HOST_VSM_POOL) readonly buffer MlVsmPool { uint vsmPool[]; };

#define ML_STATIC_DATA staticWords
#define CPVS_DATA staticWords
#include "shaders/static/static_visibility.glsl"
#define VSM_CONST vsm
#define VSM_MAPS vsmMaps
#define VSM_COVER vsmCoverage
#define VSM_TABLE vsmTable
#define VSM_POOL vsmPool
#include "shaders/shared/cluster_list.glsl"
#include "shadows/virtual/vsm_common.glsl"

// Static (baked SM / MH / MMH / DAG-MH / CPVS) times dynamic (virtual shadow map) visibility of light
// L at P. Nraw is the G-buffer normal as stored (the VSM lookup normalises it like its CPU twin).
float lightVisibility(GpuLight L, vec3 P, vec3 N, vec3 Nraw) {
    float v = 1.0;
    if (L.info.z != ML_NO_SHADOW) {
        // Point lights have six consecutive records, one per cube face (method 0 = face not baked).
        uint r = L.info.z;
        if (L.info.x == ML_LIGHT_POINT) r += pointLightFace(P - L.positionRange.xyz);
        GpuShadowRecord rec = shadowRecords[r];
        if (shadowRecordMethod(rec) != 0u)
            v *= staticVisibility(rec, P, N, shadowFootprint2(frame.cameraPosition.xyz, P, frame.cameraPosition.w));
    }
    if (L.info.y != ML_VSM_NO_MAP && v > 0.0) {
        VsmChoice c;
        uint status, depth;
        v *= vsmVisibility(L, L.info.y, P, Nraw, c, status, depth);
    }
    return v;
}

// --- the host's names for the lookups above ---

// (a) The lights of the cluster at pixel `px` and reversed-Z depth `depth` (> 0: geometry; 0 is the
// sky, which no light reaches). Iterate i < mlRangeCount(range).
uvec2 mlClusterRange(uvec2 px, float depth) { return clusterLights(px, depth); }
// Every light visible in the frame (the brute-force list the module falls back to on overflow).
uvec2 mlVisibleLights() { return uvec2(ML_CLUSTER_OVERFLOW, frame.cluster.z); }
uint mlRangeCount(uvec2 range) { return range.y; }
GpuLight mlRangeLight(uvec2 range, uint i) { return lights[ML_CLUSTER_LIGHT(range, i)]; }

// (b) Static x dynamic shadow visibility (0 shadowed .. 1 lit) of light L at world position P with
// normal N (any length: the static lookup uses it normalised, the VSM lookup normalises it itself).
// The virtual shadow maps hold pages only where the module's evaluation looks them up: G-buffer
// receivers that face the light (n.l > -1e-3 with the G-buffer normal, vsmFacesLight). A host BRDF that
// lights back faces (foliage, wrap lighting) gets no dynamic shadow there (the lookup counts it missing,
// visibility 1).
float mlLightVisibility(GpuLight L, vec3 P, vec3 N) { return lightVisibility(L, P, normalize(N), N); }

// World position of pixel `px` at reversed-Z depth `depth` in the module's frame (the evaluation pass's
// reconstruction, jitter included).
vec3 mlWorldPosition(uvec2 px, float depth) { return worldFromPixel(px.x, px.y, depth, frame.invViewProj, frame.size); }
// Camera position, ambient and sky radiance, exposure, targets' size: the frame constants.
vec3 mlCameraPosition() { return frame.cameraPosition.xyz; }

#endif
