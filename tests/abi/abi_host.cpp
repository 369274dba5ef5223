// A small host built twice against the module (tests/CMakeLists.txt, PublicAbiLayout): plainly, and with
// the GLM configuration macros that change glm's own layout (GLM_FORCE_DEFAULT_ALIGNED_GENTYPES makes a
// vec3 16 bytes, GLM_FORCE_INTRINSICS uses SIMD types). The module itself is built without them. Each
// build prints the size and member offsets of every public struct, then hands the module glm values (a
// light, a camera, an instance transform), renders a frame and prints what came back; the test fails
// unless both builds link, run and print the same lines. Includes the public headers only.
#include <manylights/glm.h>
#include <manylights/manylights.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

int failures = 0;
void check(bool ok, const char* what) {
    if (!ok) {
        std::printf("FAILED: %s\n", what);
        ++failures;
    }
}

#define ML_LAYOUT(T) std::printf("sizeof %s %zu align %zu\n", #T, sizeof(ml::T), alignof(ml::T))
#define ML_OFFSET(T, member) std::printf("offsetof %s::%s %zu\n", #T, #member, offsetof(ml::T, member))

void printLayout() {
    ML_LAYOUT(Float2);
    ML_LAYOUT(Float3);
    ML_LAYOUT(Float4x4);
    ML_LAYOUT(LightDesc);
    ML_OFFSET(LightDesc, position);
    ML_OFFSET(LightDesc, direction);
    ML_OFFSET(LightDesc, color);
    ML_OFFSET(LightDesc, intensity);
    ML_OFFSET(LightDesc, unit);
    ML_OFFSET(LightDesc, shadowResolution);
    ML_OFFSET(LightDesc, shadowTexelScale);
    ML_LAYOUT(CameraDesc);
    ML_OFFSET(CameraDesc, target);
    ML_OFFSET(CameraDesc, up);
    ML_OFFSET(CameraDesc, fovY);
    ML_OFFSET(CameraDesc, jitter);
    ML_LAYOUT(ShadowFrustum);
    ML_OFFSET(ShadowFrustum, fov);
    ML_OFFSET(ShadowFrustum, fitMargin);
    ML_LAYOUT(StaticShadowDesc);
    ML_OFFSET(StaticShadowDesc, words);
    ML_OFFSET(StaticShadowDesc, face);
    ML_LAYOUT(MeshVertex);
    ML_LAYOUT(MeshDesc);
    ML_LAYOUT(HostImage);
    ML_LAYOUT(HostTargets);
    ML_OFFSET(HostTargets, material);
    ML_OFFSET(HostTargets, hdrOutput);
    ML_LAYOUT(HostShaderBuffer);
    ML_LAYOUT(HostShaderBindings);
    ML_OFFSET(HostShaderBindings, stages);
    ML_LAYOUT(DeviceOptions);
    ML_LAYOUT(DeviceBorrow);
    ML_LAYOUT(DeviceInfo);
    ML_LAYOUT(MemoryUsage);
    ML_LAYOUT(VsmSettings);
    ML_OFFSET(VsmSettings, texelsPerPixel);
    ML_OFFSET(VsmSettings, meshletTriangles);
    ML_LAYOUT(VsmStats);
    ML_LAYOUT(PassTimes);
    ML_LAYOUT(FrameStats);
    ML_OFFSET(FrameStats, vsm);
    ML_OFFSET(FrameStats, memory);
    ML_LAYOUT(FrameReport);
    ML_LAYOUT(ModuleOptions);
    ML_OFFSET(ModuleOptions, vsm);
    ML_OFFSET(ModuleOptions, pipelineCache);
}

// Values handed over as glm, read back as glm: what a glm host does. The module validates them, so a
// misread layout shows as a refusal or as a different frame.
int run() {
    ml::LightDesc light;
    light.kind = ml::LightKind::Spot;
    light.position = glm::vec3(0.0f, 3.0f, 0.0f);
    light.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    light.color = glm::vec3(1.0f, 0.9f, 0.8f);
    light.intensity = 20.0f;
    light.range = 8.0f;
    check(ml::validateLight(light).ok(), "validateLight refused a valid light");
    check(ml::toGlm(light.color) == glm::vec3(1.0f, 0.9f, 0.8f), "toGlm(LightDesc::color)");
    ml::LightDesc negative = light;
    negative.color = glm::vec3(1.0f, -1.0f, 0.0f);
    auto refused = ml::validateLight(negative);
    check(!refused.ok() && refused.error().find("colour") != std::string::npos,
          "validateLight did not refuse a negative colour");

    ml::CameraDesc camera;
    camera.position = glm::vec3(0.0f, 2.0f, 5.0f);
    camera.target = glm::vec3(0.0f, 0.0f, 0.0f);
    camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    camera.fovY = 0.9f;
    check(ml::validateCamera(camera).ok(), "validateCamera refused a valid camera");

    auto created = ml::Module::create({});
    if (!created) {
        std::printf("FAILED: Module::create: %s\n", created.error().c_str());
        return 1;
    }
    auto& module = *created.value();
    // A floor quad (two triangles, normal +y) 8 m wide, moved 0.5 m down by a glm transform.
    const ml::MeshVertex vertices[] = {
        {{-4, 0, -4}, {0, 1, 0}}, {{-4, 0, 4}, {0, 1, 0}}, {{4, 0, 4}, {0, 1, 0}}, {{4, 0, -4}, {0, 1, 0}}};
    const uint32_t indices[] = {0, 1, 2, 0, 2, 3};
    auto mesh = module.addMesh({vertices, indices, false, "floor"});
    check(mesh.ok(), "addMesh");
    const glm::mat4 transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -0.5f, 0.0f));
    check(module.addInstance(mesh.value(), transform, glm::vec3(0.8f), false).ok(), "addInstance");
    check(module.addLight(light).ok(), "addLight");
    check(module.setEnvironment(glm::vec3(0.01f), glm::vec3(0.0f)).ok(), "setEnvironment");
    check(module.setCamera(camera).ok(), "setCamera");
    check(module.createTargets(32, 32).ok(), "createTargets");
    auto frame = module.submitFrame();
    check(frame.ok(), frame.ok() ? "" : frame.error().c_str());
    std::vector<uint8_t> rgba;
    check(module.readOutput(rgba).ok() && rgba.size() == 32 * 32 * 4, "readOutput");
    uint64_t sum = 0, lit = 0;
    for (size_t i = 0; i < rgba.size(); ++i) {
        sum += rgba[i];
        if (i % 4 == 0 && rgba[i] > 8) ++lit;
    }
    // The floor under the spot light fills the lower half of the view: a misread transform or light
    // leaves it dark or elsewhere.
    check(lit > 64, "the lit floor is missing from the frame");
    std::printf("frame: %llu lit pixels, channel sum %llu\n", (unsigned long long)lit,
                (unsigned long long)sum);
    const glm::mat4 vp = ml::toGlm(module.viewProjection());
    const glm::vec4 clip = vp * glm::vec4(0.0f, -0.5f, 0.0f, 1.0f);
    std::printf("viewProjection * origin: %.5f %.5f %.5f\n", clip.x / clip.w, clip.y / clip.w,
                clip.z / clip.w);
    return failures == 0 ? 0 : 1;
}

} // namespace

int main() {
#if defined(GLM_FORCE_DEFAULT_ALIGNED_GENTYPES)
    // The configuration this build is for: glm's own vec3 is no longer 12 bytes.
    std::printf("# glm aligned: sizeof(glm::vec3) %zu\n", sizeof(glm::vec3));
#endif
    printLayout();
    return run();
}
