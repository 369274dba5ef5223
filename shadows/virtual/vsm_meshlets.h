// Meshlets of the VSM mesh path (vsm_expand.comp, vsm_draw.task, vsm_draw.mesh): built once per mesh at
// Module::addMesh with meshoptimizer and stored with the geometry (three GPU buffers: descriptors with
// bounds, vertex lists, packed triangles).
#pragma once
#include "shadows/virtual/vsm_types.h"

#include <cstdint>
#include <span>
#include <vector>

namespace ml {

struct MeshletSet {
    std::vector<gpu::GpuMeshlet> meshlets;
    std::vector<uint32_t> vertices;  // global vertex indices (the mesh's first vertex added)
    std::vector<uint32_t> triangles; // one word per triangle: local indices a | b << 8 | c << 16
};

// Appends the meshlets of one mesh (indices local to its vertices; positions are the first three floats
// of each `stride`-byte vertex) to `out`, at most maxVertices / maxTriangles each (at most
// ML_MESHLET_VERTICES / ML_MESHLET_TRIANGLES, the mesh shader's capacity; triangles a multiple of 4).
// Triangles keep their corner order (the rasteriser then interpolates exactly as the vertex path does).
// Returns the number of meshlets appended.
uint32_t appendMeshlets(MeshletSet& out, const float* positions, size_t stride, size_t vertexCount,
                        std::span<const uint32_t> indices, uint32_t firstVertex,
                        uint32_t maxVertices = ML_MESHLET_VERTICES,
                        uint32_t maxTriangles = ML_MESHLET_TRIANGLES);

// True when the mesh is a closed, consistently wound surface with outward (counter-clockwise) faces:
// after welding vertices with bit-equal positions, every non-degenerate triangle edge a->b meets exactly
// one b->a, and the signed volume is positive. Only then may a meshlet whose triangles all face away
// from a light outside the mesh be skipped (a front face nearer on the same ray covers the same samples).
bool meshIsClosed(const float* positions, size_t stride, size_t vertexCount,
                  std::span<const uint32_t> indices);

} // namespace ml
