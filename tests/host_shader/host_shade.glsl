// The host's per-pixel lighting of tests/host_shader/host_forward.{comp,frag}: written only against the
// installed include (manylights/manylights.glsl, included by the stage's file before this one). Ambient,
// then every light of the pixel's cluster, shaded with the module's BRDF and multiplied by the module's
// static x dynamic visibility: what the evaluation pass computes, so HostShader.* compare the images.
#ifndef HOST_SHADE_GLSL
#define HOST_SHADE_GLSL

// Radiance at pixel px with reversed-Z depth d, G-buffer normal Nraw (as stored) and albedo. n: lights
// in the cluster list, lights shaded (non-zero BRDF), of those the ones with visibility < 1, and the ones
// with a virtual shadow map (the tests check that shadows were looked up at all).
vec3 hostShade(uvec2 px, float d, vec3 Nraw, vec3 albedo, out uvec4 n) {
    n = uvec4(0u);
    if (!hasSurface(d)) return frame.sky.rgb;
    vec3 P = mlWorldPosition(px, d);
    vec3 N = normalize(Nraw);
    vec3 V = normalize(mlCameraPosition() - P);
    vec3 radiance = albedo * frame.ambient.rgb;
    // (a) for each light of the cluster at this pixel and depth
    uvec2 range = mlClusterRange(px, d);
    n.x = mlRangeCount(range);
    for (uint i = 0; i < mlRangeCount(range); ++i) {
        GpuLight L = mlRangeLight(range, i);
        vec3 c = shadeLight(L, P, N, V, albedo);
        if (c == vec3(0.0)) continue;
        // (b) static x dynamic shadow visibility of light L at P with normal N
        float v = mlLightVisibility(L, P, Nraw);
        radiance += c * v;
        n.y += 1u;
        if (v < 1.0) n.z += 1u;
        if (L.info.y != ML_VSM_NO_MAP) n.w += 1u;
    }
    return radiance;
}

#endif
