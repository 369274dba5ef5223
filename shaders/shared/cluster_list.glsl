// The light list of a pixel's cluster, shared by every per-pixel pass that walks lights (evaluate,
// statistics, vsm_mark, vsm_probe). The includer declares `frame` (FrameConstants), `sliceFar[]`
// and `ranges[]` (uvec2 offset, count per cluster; culling/culling.h).
#ifndef ML_CLUSTER_LIST_GLSL
#define ML_CLUSTER_LIST_GLSL

#include "shaders/shared/light_math.h"
#include "shaders/shared/cluster_slice.glsl"

// (offset, count) into the light-index pool, or (ML_CLUSTER_OVERFLOW, visible lights) when the pixel
// must test every visible light: culling off, or its cluster overflowed the pool.
uvec2 clusterLights(uvec2 px, float d) {
    if (frame.cluster.w == ML_CULL_NONE) return uvec2(ML_CLUSTER_OVERFLOW, frame.cluster.z);
    uint slices = frame.cluster.x;
    uint s = clusterSlice(linearDepth(d, frame.depth));
    uvec2 tile = px / frame.cluster.y;
    uvec2 range = ranges[(tile.y * frame.size.z + tile.x) * slices + s];
    if (range.x == ML_CLUSTER_OVERFLOW) return uvec2(ML_CLUSTER_OVERFLOW, frame.cluster.z);
    return range;
}

// The i-th light of a range from clusterLights (an index into the visible-light buffer).
#define ML_CLUSTER_LIGHT(range, i) ((range).x == ML_CLUSTER_OVERFLOW ? (i) : pool[(range).x + (i)])

#endif
