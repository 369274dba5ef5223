#include "host/scene_host.h"

#include <stb/stb_image_write.h>

#include "io/safe_io.h"

#include "shadows/static/bake_file.h"

#include <chrono>
#include <cstdio>
#include <vector>

namespace ml {

LightDesc toLightDesc(const Light& l) {
    LightDesc d;
    d.kind = LightKind(uint32_t(l.type));
    d.position = l.position;
    d.direction = l.direction;
    d.color = l.color;
    d.intensity = l.intensity;
    d.range = l.range;
    d.outerAngle = l.outerAngle;
    d.innerAngle = l.innerAngle;
    d.dynamic = l.dynamic;
    return d;
}

CameraDesc toCameraDesc(const Camera& c) {
    CameraDesc d;
    d.position = c.position;
    d.target = c.target;
    d.fovY = c.fovY;
    d.nearPlane = c.nearPlane;
    d.farPlane = c.farPlane;
    return d;
}

Result<SceneBinding> bindScene(Module& module, const Scene& scene) {
    static_assert(sizeof(Vertex) == sizeof(MeshVertex), "scene and module vertices share a layout");
    SceneBinding b;
    std::vector<MeshId> meshIds;
    for (const Mesh& m : scene.meshes) {
        MeshDesc d;
        d.vertices = {reinterpret_cast<const MeshVertex*>(m.vertices.data()), m.vertices.size()};
        d.indices = m.indices;
        d.closed = m.closed;
        d.name = m.name;
        auto id = module.addMesh(d);
        if (!id) return fail(scene.name + ": " + id.error());
        meshIds.push_back(id.value());
    }
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        if (inst.mesh >= meshIds.size())
            return fail(scene.name + ": instance " + std::to_string(i) + " has no mesh");
        auto id = module.addInstance(meshIds[inst.mesh], inst.transform, inst.albedo, inst.dynamic);
        if (!id) return fail(scene.name + ": " + id.error());
        if (auto r = module.setInstanceMaterial(id.value(), inst.roughness, inst.metalness); !r)
            return fail(scene.name + ": instance " + std::to_string(i) + ": " + r.error());
        b.instances.push_back(id.value());
    }
    for (const Light& l : scene.lights) {
        auto id = module.addLight(toLightDesc(l));
        if (!id) return fail(scene.name + ": " + id.error());
        b.lights.push_back(id.value());
    }
    if (auto r = module.setCamera(toCameraDesc(scene.camera)); !r) return fail(scene.name + ": " + r.error());
    return b;
}

Result<void> updateScene(Module& module, const Scene& scene, const SceneBinding& b) {
    for (size_t i = 0; i < scene.instances.size(); ++i)
        if (scene.instances[i].dynamic)
            if (auto r = module.setInstanceTransform(b.instances[i], scene.instances[i].transform); !r)
                return r;
    for (size_t i = 0; i < scene.lights.size(); ++i)
        if (scene.lights[i].dynamic)
            if (auto r = module.setLight(b.lights[i], toLightDesc(scene.lights[i])); !r) return r;
    return {};
}

Result<uint32_t> bakeStaticShadows(Module& module, const Scene& scene, const SceneBinding&,
                                   StaticMethod method, uint32_t resolution) {
    auto t0 = std::chrono::steady_clock::now();
    auto baked = module.bakeStaticShadows(method, resolution, [&](uint32_t done, uint32_t total) {
        if (done % 16 == 0 || done == total)
            std::fprintf(stderr, "  baked %u/%u static lights (%s %u^2), %.1f s\n", done, total,
                         staticMethodName(method), resolution,
                         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    });
    if (!baked) return fail(scene.name + ": " + baked.error());
    return baked.value();
}

Result<uint32_t> attachBakeFile(Module& module, const SceneBinding& binding, const std::string& path,
                                const std::string& sceneName, uint32_t sceneLights, uint32_t seed,
                                std::map<uint64_t, std::string>* attached,
                                std::vector<std::string>* replaced) {
    auto file = readBakeFile(path);
    if (!file) return fail(file.error());
    const SceneSpec& s = file->scene;
    if (s.scene != sceneName || s.lights != sceneLights || s.seed != seed)
        return fail(path + ": baked for scene '" + s.scene + "' with " + std::to_string(s.lights) +
                    " lights, seed " + std::to_string(s.seed) + ", not '" + sceneName + "' with " +
                    std::to_string(sceneLights) + " lights, seed " + std::to_string(seed));
    for (const BakeRecord& r : file->records) {
        if (r.light >= binding.lights.size())
            return fail(path + ": light " + std::to_string(r.light) + " not in scene");
        if (auto a = module.setStaticShadow(binding.lights[r.light], {r.method, r.frustum, r.data, r.face});
            !a)
            return fail(path + ": " + a.error());
        if (attached) {
            const uint64_t key = uint64_t(r.light) * 8u + r.face;
            if (auto it = attached->find(key); it != attached->end() && replaced)
                replaced->push_back("light " + std::to_string(r.light) + " face " + std::to_string(r.face) +
                                    ": " + path + " (" + std::to_string(r.resolution) + "^2) replaces " +
                                    it->second);
            (*attached)[key] = path;
        }
    }
    return uint32_t(file->records.size());
}

Result<void> writePng(const std::string& path, uint32_t width, uint32_t height,
                      const std::vector<uint8_t>& rgba) {
    if (rgba.size() < size_t(width) * height * 4) return fail(path + ": image data is smaller than its size");
    // Encoded in memory, then written like every other output (io/safe_io.h: exclusive temporary beside
    // the target, checked writes, no write through a symlink or over a non-regular file).
    std::vector<unsigned char> png;
    auto sink = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<unsigned char>*>(context);
        out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
    };
    if (!stbi_write_png_to_func(sink, &png, int(width), int(height), 4, rgba.data(), int(width * 4)))
        return fail(path + ": cannot encode PNG");
    return io::writeFileAtomically(path, png.data(), png.size());
}

} // namespace ml
