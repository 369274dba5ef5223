// Scene-level utilities: the scene dispatcher (loadScene), the closed-mesh test and scene bounds.
#include "scenes/mesh_utils.h"
#include "scenes/scenes.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <unordered_map>

namespace ml {

Result<Scene> loadScene(const std::string& nameOrPath, uint32_t lights, uint32_t seed,
                        const LoadOptions& options) {
    // "night-city-large": the benchmark city at the seeds' scale (their CLOSED CITY has 613K
    // triangles), kLargeCityBlocks^2 blocks instead of 6 x 6, the same generator, lights and seed.
    // "-closed": awnings, fences and foliage as thin closed boxes (NightCityOptions::closedCasters).
    for (const char* name :
         {"night-city", "night-city-large", "night-city-closed", "night-city-large-closed"}) {
        if (nameOrPath != name) continue;
        NightCityOptions options;
        options.seed = seed;
        options.lights = lights;
        if (nameOrPath.find("-large") != std::string::npos)
            options.blocksX = options.blocksZ = kLargeCityBlocks;
        options.closedCasters = nameOrPath.find("-closed") != std::string::npos;
        auto scene = makeNightCity(options);
        if (scene) scene->name = nameOrPath;
        return scene;
    }
    if (nameOrPath == "indoor") {
        IndoorOptions options;
        options.seed = seed;
        options.lights = lights;
        return makeIndoor(options);
    }
    std::string lower = nameOrPath;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    auto endsWith = [&](const char* suffix) {
        size_t n = std::strlen(suffix);
        return lower.size() >= n && lower.compare(lower.size() - n, n, suffix) == 0;
    };
    if (endsWith(".gltf") || endsWith(".glb")) return loadGltf(nameOrPath, lights, seed, options);
    return fail(nameOrPath +
                ": unknown scene (expected \"night-city\", \"night-city-large\", \"night-city-closed\", "
                "\"night-city-large-closed\", \"indoor\" or a path ending in "
                ".gltf or .glb)");
}

bool isClosedMesh(const Mesh& mesh) {
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) return false;
    // Weld by exact position. -0.0 and +0.0 are the same point, so keys use the value + 0.0f, which
    // turns -0.0 into +0.0 while leaving every other value's bits unchanged.
    struct Key {
        uint32_t x, y, z;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
            h ^= (h >> 29) + k.y * 0xBF58476D1CE4E5B9ull;
            h ^= (h >> 31) + k.z * 0x94D049BB133111EBull;
            return size_t(h ^ (h >> 32));
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> weld;
    std::vector<uint32_t> id(mesh.vertices.size());
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        Key k;
        glm::vec3 p = mesh.vertices[i].position + glm::vec3(0.0f);
        std::memcpy(&k.x, &p.x, 4);
        std::memcpy(&k.y, &p.y, 4);
        std::memcpy(&k.z, &p.z, 4);
        id[i] = weld.emplace(k, uint32_t(weld.size())).first->second;
    }
    // Directed edges (a, b) packed in 64 bits. Closed means: no directed edge twice (that would be an
    // inconsistently wound or non-manifold edge) and every (a, b) has its twin (b, a).
    std::unordered_map<uint64_t, uint32_t> edges;
    edges.reserve(mesh.indices.size());
    size_t used = 0;
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
        uint32_t v[3];
        for (int k = 0; k < 3; ++k) {
            uint32_t index = mesh.indices[t + size_t(k)];
            if (index >= id.size()) return false;
            v[k] = id[index];
        }
        // Degenerate triangles (two corners welded together) bound no volume: ignored.
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
        ++used;
        for (int k = 0; k < 3; ++k) {
            uint64_t key = (uint64_t(v[k]) << 32) | v[(k + 1) % 3];
            if (++edges[key] > 1) return false;
        }
    }
    if (used == 0) return false;
    for (const auto& [key, count] : edges) {
        uint64_t twin = (key << 32) | (key >> 32);
        if (edges.find(twin) == edges.end()) return false;
    }
    return true;
}

void updateBounds(Scene& scene) {
    std::vector<glm::vec3> lo(scene.meshes.size()), hi(scene.meshes.size());
    std::vector<bool> has(scene.meshes.size());
    for (size_t i = 0; i < scene.meshes.size(); ++i)
        has[i] = detail::meshBounds(scene.meshes[i], lo[i], hi[i]);
    bool any = false;
    glm::vec3 bmin(0.0f), bmax(0.0f);
    for (const Instance& inst : scene.instances) {
        if (inst.mesh >= scene.meshes.size() || !has[inst.mesh]) continue;
        for (int c = 0; c < 8; ++c) {
            glm::vec3 corner((c & 1) ? hi[inst.mesh].x : lo[inst.mesh].x,
                             (c & 2) ? hi[inst.mesh].y : lo[inst.mesh].y,
                             (c & 4) ? hi[inst.mesh].z : lo[inst.mesh].z);
            glm::vec3 w = glm::vec3(inst.transform * glm::vec4(corner, 1.0f));
            if (!any) {
                bmin = bmax = w;
                any = true;
            }
            bmin = glm::min(bmin, w);
            bmax = glm::max(bmax, w);
        }
    }
    scene.boundsMin = bmin;
    scene.boundsMax = bmax;
}

} // namespace ml
