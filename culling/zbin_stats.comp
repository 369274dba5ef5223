#version 460
#extension GL_GOOGLE_include_directive : require
// Z-binning statistics (culling/zbin.h), a thread per pixel with geometry: the lights it would evaluate
// (the bits of its tile's mask between its bin's min and max, plus the wide lights, evaluated
// everywhere) and, of those, the ones that really reach its point (lightReachesPoint). The second sum
// equals statistics.comp's brute-force reaching sum exactly when the Z-bins miss no light (tests check
// it), so this pass costs what the candidates cost, not every light per pixel.
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/light_math.h"
#include "culling/zbin_types.h"
#include "culling/zbin_bindings.h"

layout(local_size_x = ML_ZBIN_GROUP / 8, local_size_y = 8) in;
layout(push_constant) uniform Push { ZBinPush push; };

layout(binding = ML_ZBIN_STATS_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_ZBIN_STATS_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_ZBIN_STATS_SORTED, std430) readonly buffer Sorted { ZBinLight sorted[]; };
layout(binding = ML_ZBIN_STATS_MASKS, std430) readonly buffer Masks { uint masks[]; };
layout(binding = ML_ZBIN_STATS_BINS, std430) readonly buffer Bins { uint bins[]; };
layout(binding = ML_ZBIN_STATS_DEPTH) uniform texture2D depthImage;
// Sums over the pixels with geometry (ZBinStats): [0] evaluated, [1] reaching (among the evaluated),
// [2] pixels, [3] the tile's bits at any depth (what the tile alone would give), [4] evaluated lights
// whose own bin range holds the pixel's bin (exact per-light depth ranges; the rest of [0] are the
// (min, max) range's false positives). Wide lights count in all but [2].
layout(binding = ML_ZBIN_STATS_OUT, std430) buffer Stats { uint64_t stats[5]; };
layout(binding = ML_ZBIN_STATS_WIDE, std430) readonly buffer Wide { uint wide[]; }; // visible indices of the wide lights

shared uint sEvaluated, sReaching, sSurface, sTile, sExact;

void main() {
    if (gl_LocalInvocationIndex == 0) { sEvaluated = 0; sReaching = 0; sSurface = 0; sTile = 0; sExact = 0; }
    barrier();
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x < frame.size.x && px.y < frame.size.y) {
        float d = texelFetch(depthImage, ivec2(px), 0).r;
        if (hasSurface(d)) {
            vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
            uint bin = zbinOf(linearDepth(d, frame.depth), push.binNear, push.binScale, push.bins);
            uint range = bins[bin], lo = range & 0xFFFFu, hi = range >> 16u;
            uint tile = (px.y / frame.cluster.y) * frame.size.z + px.x / frame.cluster.y;
            uint evaluated = push.wide, reaching = 0u, tileBits = push.wide, exact = push.wide;
            for (uint word = 0u; word < push.words; ++word)
                tileBits += uint(bitCount(masks[tile * push.words + word]));
            for (uint k = 0u; k < push.wide; ++k) reaching += lightReachesPoint(lights[wide[k]], P) ? 1u : 0u;
            for (uint word = lo >> 5u; lo <= hi && word <= (hi >> 5u); ++word) {
                uint bits = masks[tile * push.words + word];
                // Only the bits of [lo, hi] within this word.
                uint first = word == (lo >> 5u) ? (lo & 31u) : 0u;
                uint last = word == (hi >> 5u) ? (hi & 31u) : 31u;
                bits &= (last == 31u ? 0xFFFFFFFFu : ((1u << (last + 1u)) - 1u)) & ~((1u << first) - 1u);
                evaluated += uint(bitCount(bits));
                while (bits != 0u) {
                    uint i = word * 32u + uint(findLSB(bits));
                    bits &= bits - 1u;
                    ZBinLight L = sorted[i];
                    exact += (L.bins & 0xFFFFu) <= bin && bin <= (L.bins >> 16u) ? 1u : 0u;
                    reaching += lightReachesPoint(lights[L.light], P) ? 1u : 0u;
                }
            }
            atomicAdd(sEvaluated, evaluated);
            atomicAdd(sReaching, reaching);
            atomicAdd(sSurface, 1u);
            atomicAdd(sTile, tileBits);
            atomicAdd(sExact, exact);
        }
    }
    barrier();
    if (gl_LocalInvocationIndex == 0 && sSurface > 0) {
        atomicAdd(stats[0], uint64_t(sEvaluated));
        atomicAdd(stats[1], uint64_t(sReaching));
        atomicAdd(stats[2], uint64_t(sSurface));
        atomicAdd(stats[3], uint64_t(sTile));
        atomicAdd(stats[4], uint64_t(sExact));
    }
}
