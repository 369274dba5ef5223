#include "bake/scene_casters.h"

#include <utility>

namespace ml {

CasterTriangles castersFromScene(const Scene& scene) {
    CasterTriangles out;
    for (const Instance& inst : scene.instances) {
        if (inst.dynamic || inst.mesh >= scene.meshes.size()) continue;
        const Mesh& mesh = scene.meshes[inst.mesh];
        bool mirror = glm::determinant(glm::mat3(inst.transform)) < 0.0f;
        for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
            uint32_t ia = mesh.indices[i], ib = mesh.indices[i + 1], ic = mesh.indices[i + 2];
            if (ia >= mesh.vertices.size() || ib >= mesh.vertices.size() || ic >= mesh.vertices.size())
                continue;
            glm::vec3 a = glm::vec3(inst.transform * glm::vec4(mesh.vertices[ia].position, 1.0f));
            glm::vec3 b = glm::vec3(inst.transform * glm::vec4(mesh.vertices[ib].position, 1.0f));
            glm::vec3 c = glm::vec3(inst.transform * glm::vec4(mesh.vertices[ic].position, 1.0f));
            if (mirror) std::swap(b, c);
            out.add(a, b, c, mesh.closed);
        }
    }
    return out;
}

} // namespace ml
