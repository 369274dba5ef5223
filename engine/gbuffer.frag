#version 460
// G-buffer: world normal (RGBA16F; w 1 on a shadow receiver, ML_NOT_A_RECEIVER on an instance that
// receives none), albedo (RGBA8) and material (RG8: perceptual roughness, metalness). Depth comes from the
// depth attachment; world positions are reconstructed from it by later passes (light_math.h
// worldFromPixel).
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inAlbedo;
layout(location = 2) flat in vec3 inMaterial;
layout(location = 0) out vec4 outNormal;
layout(location = 1) out vec4 outAlbedo;
layout(location = 2) out vec4 outMaterial;

void main() {
    vec3 n = normalize(inNormal);
    // Open geometry (cards, awnings) is drawn two-sided: face the normal towards the viewer.
    if (!gl_FrontFacing) n = -n;
    outNormal = vec4(n, inMaterial.z);
    outAlbedo = vec4(inAlbedo, 1.0);
    outMaterial = vec4(inMaterial.xy, 0.0, 1.0);
}
