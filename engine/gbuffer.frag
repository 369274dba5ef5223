#version 460
// G-buffer: world normal (RGBA16F) and albedo (RGBA8). Depth comes from the depth attachment; world
// positions are reconstructed from it by later passes (light_math.h worldFromPixel).
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inAlbedo;
layout(location = 0) out vec4 outNormal;
layout(location = 1) out vec4 outAlbedo;

void main() {
    vec3 n = normalize(inNormal);
    // Open geometry (cards, awnings) is drawn two-sided: face the normal towards the viewer.
    if (!gl_FrontFacing) n = -n;
    outNormal = vec4(n, 1.0);
    outAlbedo = vec4(inAlbedo, 1.0);
}
