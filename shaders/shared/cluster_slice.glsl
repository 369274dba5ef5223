// The depth slice of a linear view depth z: the number of slice ends sliceFar[0 .. slices-2] at or below
// z, so z < sliceFar[s] (the last slice takes everything beyond). CPU twin: culling/culling.cpp's sliceOf.
// The includer declares `frame` (FrameConstants: cluster.x slices, depth.xy near and far) and `sliceFar[]`.
//
// Every per-pixel pass that walks a cluster list (evaluate, vsm_mark, vsm_probe, statistics, the views,
// a host's shaders) and the cluster bounds pass find a slice per pixel; a walk from slice 0 read up to 63
// dependent bounds. The slices are exponential between near and far (culling/culling.cpp's
// sliceBoundaries), so the estimate from a logarithm is the answer or a neighbour; the two walks then step
// to the exact slice whatever the logarithm's rounding (and for any increasing table), reading two bounds
// in the common case. Measured in docs/culling.md (the grid and the lists).
#ifndef ML_CLUSTER_SLICE_GLSL
#define ML_CLUSTER_SLICE_GLSL

uint clusterSlice(float z) {
    uint slices = frame.cluster.x;
    float lg = log(max(z, frame.depth.x) / frame.depth.x) / log(frame.depth.y / frame.depth.x);
    uint s = uint(clamp(lg * float(slices), 0.0, float(slices - 1u)));
    while (s > 0u && z < sliceFar[s - 1u]) --s;
    while (s + 1u < slices && z >= sliceFar[s]) ++s;
    return s;
}

#endif
