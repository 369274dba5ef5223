#include "shadows/virtual/vsm_meshlets.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <tuple>
#include <unordered_map>

namespace ml {

uint32_t appendMeshlets(MeshletSet& out, const float* positions, size_t stride, size_t vertexCount,
                        std::span<const uint32_t> indices, uint32_t firstVertex, uint32_t maxVertices,
                        uint32_t maxTriangles) {
    if (indices.empty()) return 0;
    const size_t maxV = std::min<uint32_t>(maxVertices, ML_MESHLET_VERTICES);
    const size_t maxT = std::min<uint32_t>(maxTriangles, ML_MESHLET_TRIANGLES) & ~3u;
    std::vector<meshopt_Meshlet> ms(meshopt_buildMeshletsBound(indices.size(), maxV, maxT));
    std::vector<uint32_t> verts(ms.size() * maxV);
    std::vector<unsigned char> tris(ms.size() * maxT * 3);
    // cone_weight 0: meshlets by locality only (the cone test applies to few casters: closed meshes).
    const size_t count =
        meshopt_buildMeshlets(ms.data(), verts.data(), tris.data(), indices.data(), indices.size(), positions,
                              vertexCount, stride, maxV, maxT, 0.0f);
    for (size_t i = 0; i < count; ++i) {
        const meshopt_Meshlet& m = ms[i];
        meshopt_Bounds b = meshopt_computeMeshletBounds(&verts[m.vertex_offset], &tris[m.triangle_offset],
                                                        m.triangle_count, positions, vertexCount, stride);
        gpu::GpuMeshlet g{};
        g.sphere = glm::vec4(b.center[0], b.center[1], b.center[2], b.radius);
        g.cone = glm::vec4(b.cone_axis[0], b.cone_axis[1], b.cone_axis[2], b.cone_cutoff);
        g.apex = glm::vec4(b.cone_apex[0], b.cone_apex[1], b.cone_apex[2], 0.0f);
        g.data = glm::uvec4(uint32_t(out.vertices.size()), uint32_t(out.triangles.size()), m.vertex_count,
                            m.triangle_count);
        for (uint32_t v = 0; v < m.vertex_count; ++v)
            out.vertices.push_back(firstVertex + verts[m.vertex_offset + v]);
        for (uint32_t t = 0; t < m.triangle_count; ++t) {
            const unsigned char* c = &tris[m.triangle_offset + 3 * t];
            out.triangles.push_back(uint32_t(c[0]) | uint32_t(c[1]) << 8 | uint32_t(c[2]) << 16);
        }
        out.meshlets.push_back(g);
    }
    return uint32_t(count);
}

bool meshIsClosed(const float* positions, size_t stride, size_t vertexCount,
                  std::span<const uint32_t> indices) {
    if (indices.empty()) return false;
    auto pos = [&](uint32_t i) {
        const float* p =
            reinterpret_cast<const float*>(reinterpret_cast<const char*>(positions) + i * stride);
        return glm::vec3(p[0], p[1], p[2]);
    };
    // Weld by exact position bits (the rasteriser then sees the same transformed vertex on both sides).
    struct Key {
        uint32_t x, y, z;
        bool operator<(const Key& o) const { return std::tie(x, y, z) < std::tie(o.x, o.y, o.z); }
    };
    std::map<Key, uint32_t> ids;
    std::vector<uint32_t> weld(vertexCount);
    for (uint32_t i = 0; i < vertexCount; ++i) {
        Key k;
        std::memcpy(&k, reinterpret_cast<const char*>(positions) + i * stride, 12);
        weld[i] = ids.emplace(k, uint32_t(ids.size())).first->second;
    }
    std::unordered_map<uint64_t, int> edges; // directed edge -> count
    double volume = 0.0;
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        uint32_t a = weld[indices[t]], b = weld[indices[t + 1]], c = weld[indices[t + 2]];
        if (a == b || b == c || a == c) continue; // degenerate: covers nothing
        for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            if (++edges[uint64_t(u) << 32 | v] > 1) return false;
        glm::dvec3 p0(pos(indices[t])), p1(pos(indices[t + 1])), p2(pos(indices[t + 2]));
        volume += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
    }
    if (edges.empty()) return false;
    for (const auto& [e, n] : edges)
        if (!edges.count(e >> 32 | e << 32)) return false;
    return volume > 0.0;
}

} // namespace ml
