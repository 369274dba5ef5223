// Receiver bounds per cluster (tile x slice), for page marking per cluster (shadows/virtual/
// vsm_mark_cluster.comp): written by culling/cluster_bounds.comp's receiver variant, reduced again by
// the CPU references (cullReceiversReference in culling/culling.cpp, vsmClusterReceiversReference in
// shadows/virtual/vsm_reference.cpp). One source for GLSL and C++; layout rules as in gpu_types.h.
//
// Only receivers count (surface pixels whose G-buffer normal has w >= 0: the evaluation looks their
// shadows up), so sky, and instances that receive no shadow, widen no box. Beside the world box, the
// cluster keeps a box over the receivers' unit normals (per axis the smallest and largest component),
// which vsmBoxFacesAway (shadows/virtual/vsm_bounds.h) tests against a light: a min / max reduction is
// order-independent, so the GPU's reductions (either build) equal the reference bit for bit in one pass (an
// axis-and-cosine cone would need a second pass over the pixels for the cosine).
#ifndef ML_CLUSTER_RECEIVERS_H
#define ML_CLUSTER_RECEIVERS_H

#include "shaders/shared/light_math.h"

#ifdef __cplusplus
namespace ml::gpu {
#endif

// 32 bytes per cluster, written for the occupied clusters only (the tile masks' bits: the clusters the
// mark pass reads; the others keep an older frame's values, and the references give them zeros).
// lo, hi: the world AABB of the cluster's receivers (0 when it has none). normalLo, normalHi: per axis a
// 10-bit code (x bits 0-9, y 10-19, z 20-29) of a lower and an upper bound of the receivers' unit
// normals (clusterNormalBound); bit 31 of normalHi: the cluster holds a receiver (every other field is
// 0 when it does not).
ML_STRUCT(ClusterReceivers) {
    vec3 lo;
    uint normalLo;
    vec3 hi;
    uint normalHi;
};

#define ML_CLUSTER_HAS_RECEIVER 0x80000000u

// The receiver's unit normal as the marking passes compute it (vsmNormalize in shadows/virtual/
// vsm_math.h: the same operations; 0 for a degenerate or non-finite stored normal).
ML_FN vec3 clusterUnitNormal(vec3 n) {
    ML_PRECISE float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(len > 0.0f)) return vec3(0.0f, 0.0f, 0.0f);
    ML_PRECISE float x = n.x / len, y = n.y / len, z = n.z / len;
    return vec3(x, y, z);
}

// Code of a normal component c in [-1, 1] (a correctly rounded division keeps |n.x / len| <= 1): t =
// (c + 1) * 511.5 in [0, 1023], off the exact value by at most 1.3e-4 after its two roundings; the lower
// code floor(t) - 1 and the upper floor(t) + 2 are therefore at least 0.99 code below and above the
// exact t, and decode (code / 511.5 - 1, rounded by at most 1.2e-7) to at least 1.9e-3 below and above
// c: no receiver's component lies outside its cluster's bounds. A non-finite component (never produced:
// clusterUnitNormal returns 0 then) takes code 0 / 1023.
ML_FN uint clusterNormalCode(float c, bool upper) {
    ML_PRECISE float t = (c + 1.0f) * 511.5f;
    if (!(t >= 0.0f)) t = 0.0f;
    if (!(t <= 1023.0f)) t = 1023.0f;
    int q = int(floor(t)) + (upper ? 2 : -1);
    q = q < 0 ? 0 : (q > 1023 ? 1023 : q);
    return uint(q);
}
ML_FN float clusterNormalBound(uint packed, uint axis) {
    uint code = (packed >> (10u * axis)) & 1023u;
    ML_PRECISE float c = float(code) / 511.5f - 1.0f;
    return c;
}

#ifdef __cplusplus
static_assert(sizeof(ClusterReceivers) == 32);
static_assert(offsetof(ClusterReceivers, normalLo) == 12);
static_assert(offsetof(ClusterReceivers, hi) == 16);
static_assert(offsetof(ClusterReceivers, normalHi) == 28);
} // namespace ml::gpu
#endif

#endif
