// A host of the module API: hands a Scene (scenes/) to ml::Module and keeps dynamic instances and
// lights moving. Uses only manylights/module.h, like any host engine would.
#pragma once
#include "manylights/manylights.h"
#include "scenes/scene.h"

#include <map>
#include <string>
#include <vector>

namespace ml {

struct SceneBinding {
    std::vector<InstanceId> instances; // scene instance -> module instance
    std::vector<LightId> lights;       // scene light -> module light
};

LightDesc toLightDesc(const Light& light);
CameraDesc toCameraDesc(const Camera& camera);

// Registers meshes, instances and lights; sets the camera.
Result<SceneBinding> bindScene(Module& module, const Scene& scene);
// After animateScene: pushes dynamic instance transforms and dynamic lights.
Result<void> updateScene(Module& module, const Scene& scene, const SceneBinding& binding);

// Bakes every static spot and point light's shadow in-process through Module::bakeStaticShadows and
// attaches it. Progress on stderr. Returns the number of lights baked.
Result<uint32_t> bakeStaticShadows(Module& module, const Scene& scene, const SceneBinding& binding,
                                   StaticMethod method, uint32_t resolution);

// Attaches every record of a bake file (shadows/static/bake_file.h) to its light. The file must have
// been baked from this scene (same name, light count and seed), else a one-line error says what differs.
// `attached` (optional) maps light * 8 + face to the file that attached it, across calls: a record for a
// map another file attached replaces it, and `replaced` gets one line saying so.
Result<uint32_t> attachBakeFile(Module& module, const SceneBinding& binding, const std::string& path,
                                const std::string& sceneName, uint32_t sceneLights, uint32_t seed,
                                std::map<uint64_t, std::string>* attached = nullptr,
                                std::vector<std::string>* replaced = nullptr);

// PNG writing for RGBA8 rows (top row first). One-line error naming the path.
Result<void> writePng(const std::string& path, uint32_t width, uint32_t height,
                      const std::vector<uint8_t>& rgba);

} // namespace ml
