// The module behind the public API (manylights/module.h): owns the scene buffers, per-slot frame data,
// the features and the profiler, and records a frame as a list of passes (engine/frame.h; the host
// side of a frame is engine/frame_write.cpp).
#include "manylights/manylights.h"

#include "culling/culling.h"
#include "culling/culling_push.h"
#include "engine/gbuffer.h"
#include "engine/limits.h"
#include "engine/module_impl.h"
#include "lights/lights.h"
#include "shadows/gpu/dual_depth_gpu.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <tuple>

namespace ml {

const char* cullingName(CullingMode mode) {
    switch (mode) {
    case CullingMode::Clustered:
        return "clustered";
    case CullingMode::Tiled:
        return "tiled";
    case CullingMode::None:
        return "none";
    case CullingMode::ClusteredBrute:
        return "clustered-brute";
    }
    return "?";
}

Result<CullingMode> parseCulling(const std::string& name) {
    if (name == "clustered") return CullingMode::Clustered;
    if (name == "tiled") return CullingMode::Tiled;
    if (name == "none") return CullingMode::None;
    if (name == "clustered-brute") return CullingMode::ClusteredBrute;
    return fail("unknown culling mode '" + name + "' (clustered, clustered-brute, tiled or none)");
}

Module::Module(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Module::~Module() {
    if (impl_) impl_->destroy();
}
TimingMode Module::timingMode() const {
    return impl_->timing;
}
uint32_t Module::lightCount() const {
    uint32_t n = 0;
    for (uint8_t alive : impl_->lightAlive) n += alive;
    return n;
}
void Module::setCulling(CullingMode mode) {
    impl_->culling = mode;
}
void Module::setStatistics(bool enabled) {
    impl_->statistics = enabled;
}
void Module::setView(DebugView view) {
    impl_->view = view;
}
Result<void> Module::setExposure(float exposure) {
    if (!(exposure > 0.0f) || !std::isfinite(exposure))
        return fail("setExposure: exposure must be finite and > 0");
    impl_->exposure = exposure;
    return {};
}

// A host's static shadow frustum in the static shadow library's type (glm matrix), at the API boundary.
static LightFrustum lightFrustum(const ShadowFrustum& s) {
    LightFrustum f;
    f.view = toGlm(s.view);
    f.fov = s.fov;
    f.nearPlane = s.nearPlane;
    f.farPlane = s.farPlane;
    f.orthoHalf = s.orthoHalf;
    f.orthoHalfY = s.orthoHalfY;
    f.fitMargin = s.fitMargin;
    return f;
}

static bool finiteMatrix(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// A zero (or vanishing: below 1e-8 per axis) scale has no inverse: normals, bounds and the shadow
// maps' culling would come out NaN or empty. Refused rather than drawn as nothing.
static bool singularMatrix(const glm::mat4& m) {
    return !(std::abs(glm::determinant(glm::mat3(m))) > 1e-24f);
}

Result<std::unique_ptr<Module>> Module::create(const ModuleOptions& options) {
    // Each frame in flight has its own per-frame buffers and queries; 0 is refused, not taken as 1.
    if (options.framesInFlight < 1 || options.framesInFlight > 16)
        return fail("framesInFlight must be 1..16, got " + std::to_string(options.framesInFlight));
    auto impl = std::make_unique<Impl>();
    // A cache belongs to the device it was made on: the host cannot have made one on a device the
    // module has yet to create.
    if (options.pipelineCache && !options.borrow)
        return fail("pipelineCache needs a borrowed device (ModuleOptions::borrow): a cache belongs to the "
                    "device it was created on");
    auto device = options.borrow ? Device::borrow(*options.borrow) : Device::create(options.device);
    if (!device) return fail(device.error());
    impl->device = std::move(device.value());
    impl->device->pipelineCache = options.pipelineCache;
    impl->culling = options.culling;
    impl->statistics = options.statistics;
    // Fenced is an explicit profiling mode (manylights.h): by default record() records into the host's
    // command buffer on every device.
    impl->timing = options.timing == TimingChoice::Fenced ? TimingMode::Fenced : TimingMode::Timestamps;
    const VsmSettings& v = options.vsm;
    if (v.enabled) {
        auto pow2 = [](uint32_t x) { return x && !(x & (x - 1)); };
        if (!pow2(v.resolution) || v.resolution < 256 || v.resolution > 16384)
            return fail("vsm: resolution " + std::to_string(v.resolution) +
                        " is not a power of two in 256..16384");
        if (v.pageSize != 32 && v.pageSize != 64 && v.pageSize != 128)
            return fail("vsm: page size " + std::to_string(v.pageSize) + " is not 32, 64 or 128");
        if (v.pageSize > v.resolution) return fail("vsm: page size is larger than the resolution");
        if (v.poolPages < 1 || v.poolPages > ML_VSM_PHYS_MASK)
            return fail("vsm: pool pages " + std::to_string(v.poolPages) + " outside 1..16777215");
        // With the static layer the pool buffer holds every page twice (the static twins).
        if (uint64_t(v.poolPages) * v.pageSize * v.pageSize * 4 * (v.staticLayer ? 2 : 1) >
            (uint64_t(1) << 32) - 4)
            return fail("vsm: a pool of " + std::to_string(v.poolPages) + " pages of " +
                        std::to_string(v.pageSize) + "^2 exceeds 4 GiB" +
                        (v.staticLayer ? " with its static twins" : ""));
        if (v.maxMaps < 1 || v.maxMaps > 65536) return fail("vsm: max maps outside 1..65536");
        if (v.clipLevels < 1 || v.clipLevels > 20) return fail("vsm: clip levels outside 1..20");
        if (!(v.clipHalfExtent > 0) || !std::isfinite(v.clipHalfExtent) || !(v.clipDepth > 0) ||
            !std::isfinite(v.clipDepth))
            return fail("vsm: clip extent and depth must be finite and > 0");
        if (v.maxDrawsPerMip < 1) return fail("vsm: max draws per mip must be >= 1");
        if (v.cullRowWorkgroups < 1 || v.cullRowWorkgroups > 65535)
            return fail("vsm: cull row workgroups must be 1..65535 (got " +
                        std::to_string(v.cullRowWorkgroups) + ")");
        if (!validTexelsPerPixel(v.texelsPerPixel))
            return fail("vsm: texels per pixel must be a power of two in 1/4..8");
        if (v.meshletVertices < 3 || v.meshletVertices > ML_MESHLET_VERTICES || v.meshletTriangles < 4 ||
            v.meshletTriangles > ML_MESHLET_TRIANGLES || v.meshletTriangles % 4)
            return fail("vsm: meshlets of " + std::to_string(v.meshletVertices) + " vertices / " +
                        std::to_string(v.meshletTriangles) + " triangles: want 3.." +
                        std::to_string(ML_MESHLET_VERTICES) + " / 4.." +
                        std::to_string(ML_MESHLET_TRIANGLES) + " (a multiple of 4)");
    }
    // Sizes against the device (engine/limits.h): map slots and pool pages reduced to fit, said once.
    // (Map slots are not bounded by the device's image array layers: the HPB is a buffer, and the slot
    // pool grows up to maxMaps and the 32-bit entry index, shadows/virtual/vsm.cpp.)
    std::vector<std::string> notes;
    auto fitted = fitVsmSettings(deviceLimitTable(*impl->device), v, notes);
    if (!fitted) return fail(fitted.error());
    for (const std::string& n : notes) std::fprintf(stderr, "%s\n", n.c_str());
    impl->vsmSettings = fitted.value();
    impl->hdrOutput = options.hdrOutput;
    impl->slots.resize(options.framesInFlight);
    std::unique_ptr<Module> module(new Module(std::move(impl)));
    // Out of memory: the module's destructor releases what init made (every destroy takes empty handles).
    if (auto r = module->impl_->init(); !r) return fail("Module::create: " + r.error());
    return module;
}

Result<void> Module::Impl::init() {
    device->frameSetup = &setup; // inactive outside record(): setup work before it submits and waits
    const Device& d = *device;
    ML_TRY(features.create(d, vsmSettings, uint32_t(slots.size())));
    ML_TRY(profiler.create(d, uint32_t(slots.size())));
    profiler.fenced = timing == TimingMode::Fenced;
    // Per slot: uploads the host writes every frame; the counters are the frame's readback.
    for (auto& s : slots) {
        ML_TRY(createBuffer(d, s.frame, sizeof(gpu::FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            "frame_constants"));
        ML_TRY(createBuffer(d, s.lights, sizeof(gpu::GpuLight) * ML_MAX_LIGHTS, kStorageBufferUsage,
                            "visible_lights"));
        ML_TRY(createBuffer(d, s.counters, sizeof(gpu::FrameCounters), kStorageBufferUsage, "frame_counters",
                            MemoryRole::Readback));
        ML_TRY(createBuffer(d, s.slices, sizeof(float) * ML_MAX_SLICES, kStorageBufferUsage, "slice_far"));
        ML_TRY(createBuffer(d, s.wide, sizeof(gpu::WideLight) * ML_MAX_LIGHTS, kStorageBufferUsage,
                            "wide_lights"));
    }
    return {};
}

void Module::Impl::destroy() {
    const Device& d = *device;
    waitIdle();
    features.destroy(d);
    profiler.destroy(d);
    for (auto& s : slots) {
        destroyBuffer(d, s.frame);
        destroyBuffer(d, s.lights);
        destroyBuffer(d, s.counters);
        destroyBuffer(d, s.slices);
        destroyBuffer(d, s.wide);
        destroyBuffer(d, s.instances);
        destroyBuffer(d, s.draws);
        destroyBuffer(d, s.shadowRecords);
    }
    for (Buffer* b : {&vertexBuffer, &indexBuffer, &readback, &staticWords, &meshletBuffer,
                      &meshletVertexBuffer, &meshletTriangleBuffer})
        destroyBuffer(d, *b);
    for (Buffer& b : staging) destroyBuffer(d, b);
    staging.clear();
    stagedCopies.clear();
    destroyTargets();
    releaseRetired(true);
    for (Buffer& b : setup.released) destroyBuffer(d, b); // a failed record() left them queued
    setup = {};
    device->frameSetup = nullptr;
}

Result<MeshId> Module::addMesh(const MeshDesc& mesh) {
    auto& m = *impl_;
    if (mesh.indices.size() % 3) return fail("mesh '" + mesh.name + "': index count is not a multiple of 3");
    for (size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.vertices.size())
            return fail("mesh '" + mesh.name + "': index " + std::to_string(i) + " = " +
                        std::to_string(mesh.indices[i]) + " is past the " +
                        std::to_string(mesh.vertices.size()) + " vertices");
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
        for (float f : mesh.vertices[i].position)
            if (!std::isfinite(f))
                return fail("mesh '" + mesh.name + "': vertex " + std::to_string(i) + " is not finite");
    glm::vec3 lo(mesh.vertices.empty() ? 0.0f : 1e30f), hi(mesh.vertices.empty() ? 0.0f : -1e30f);
    for (const MeshVertex& v : mesh.vertices) {
        glm::vec3 p(v.position[0], v.position[1], v.position[2]);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    Impl::MeshRange r{uint32_t(m.vertices.size()),
                      uint32_t(m.indices.size()),
                      uint32_t(mesh.indices.size()),
                      lo,
                      hi,
                      true,
                      mesh.closed};
    r.firstMeshlet = uint32_t(m.meshlets.meshlets.size());
    r.meshletCount = appendMeshlets(m.meshlets, mesh.vertices.empty() ? nullptr : mesh.vertices[0].position,
                                    sizeof(MeshVertex), mesh.vertices.size(), mesh.indices, r.firstVertex,
                                    m.vsmSettings.meshletVertices, m.vsmSettings.meshletTriangles);
    r.coneCull = meshIsClosed(mesh.vertices.empty() ? nullptr : mesh.vertices[0].position, sizeof(MeshVertex),
                              mesh.vertices.size(), mesh.indices);
    m.vertices.insert(m.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
    m.indices.insert(m.indices.end(), mesh.indices.begin(), mesh.indices.end());
    m.meshes.push_back(r);
    m.meshesDirty = true;
    return MeshId(m.meshes.size() - 1);
}

// Ids carry a generation above the slot index, so an id of a removed object is refused instead of
// reaching whatever reuses its slot. A slot's first object has generation 0: its id is its index.
namespace {
constexpr uint32_t kLightIndexBits = 12;    // ML_MAX_LIGHTS = 4096 slots
constexpr uint32_t kInstanceIndexBits = 20; // 1M instance slots
uint32_t makeId(uint32_t index, uint32_t generation, uint32_t bits) {
    return index | (generation << bits);
}
} // namespace

Result<uint32_t> Module::Impl::lightIndex(LightId id, const char* what) const {
    const uint32_t index = id & ((1u << kLightIndexBits) - 1), gen = id >> kLightIndexBits;
    if (index >= lights.size() || !lightAlive[index] || lightGeneration[index] != gen)
        return fail(std::string(what) + ": light " + std::to_string(id) + " does not exist (or was removed)");
    return index;
}

Result<uint32_t> Module::Impl::instanceIndex(InstanceId id, const char* what) const {
    const uint32_t index = id & ((1u << kInstanceIndexBits) - 1), gen = id >> kInstanceIndexBits;
    if (index >= instances.size() || !instances[index].alive || instances[index].generation != gen)
        return fail(std::string(what) + ": instance " + std::to_string(id) +
                    " does not exist (or was removed)");
    return index;
}

Result<InstanceId> Module::addInstance(MeshId mesh, const Float4x4& transformDesc, Float3 albedoDesc,
                                       bool dynamic) {
    auto& m = *impl_;
    const glm::mat4 transform = toGlm(transformDesc);
    const glm::vec3 albedo = toGlm(albedoDesc);
    if (mesh >= m.meshes.size() || !m.meshes[mesh].alive)
        return fail("addInstance: mesh id " + std::to_string(mesh) + " does not exist (or was removed)");
    if (!finiteMatrix(transform)) return fail("addInstance: transform is not finite");
    if (singularMatrix(transform)) return fail("addInstance: transform is singular (a zero scale)");
    if (!std::isfinite(albedo.x) || !std::isfinite(albedo.y) || !std::isfinite(albedo.z) || albedo.x < 0 ||
        albedo.y < 0 || albedo.z < 0)
        return fail("addInstance: albedo must be finite and >= 0");
    Impl::InstanceData data{mesh, transform, albedo, dynamic}; // reaches the GPU with the next frame's slot
    if (!m.freeInstances.empty()) {
        const uint32_t index = m.freeInstances.back();
        m.freeInstances.pop_back();
        data.generation = (m.instances[index].generation + 1) & ((1u << (32 - kInstanceIndexBits)) - 1);
        m.instances[index] = data;
        m.touchInstance(index);
        return InstanceId(makeId(index, data.generation, kInstanceIndexBits));
    }
    if (m.instances.size() >= (1u << kInstanceIndexBits))
        return fail("addInstance: the module holds at most " + std::to_string(1u << kInstanceIndexBits) +
                    " instances");
    m.instances.push_back(data);
    m.touchInstance(uint32_t(m.instances.size() - 1));
    return InstanceId(m.instances.size() - 1);
}

Result<void> Module::removeInstance(InstanceId id) {
    auto index = impl_->instanceIndex(id, "removeInstance");
    if (!index) return fail(index.error());
    impl_->instances[index.value()].alive = false;
    impl_->touchInstance(index.value());
    impl_->freeInstances.push_back(index.value());
    return {};
}

Result<void> Module::setInstanceShadowCasting(InstanceId id, bool castsShadows) {
    auto index = impl_->instanceIndex(id, "setInstanceShadowCasting");
    if (!index) return fail(index.error());
    impl_->instances[index.value()].castsShadows = castsShadows;
    impl_->touchInstance(index.value());
    return {};
}

Result<void> Module::removeMesh(MeshId mesh) {
    auto& m = *impl_;
    if (mesh >= m.meshes.size() || !m.meshes[mesh].alive)
        return fail("removeMesh: mesh id " + std::to_string(mesh) + " does not exist (or was removed)");
    for (size_t i = 0; i < m.instances.size(); ++i)
        if (m.instances[i].alive && m.instances[i].mesh == mesh)
            return fail("removeMesh: mesh " + std::to_string(mesh) + " is used by instance " +
                        std::to_string(i));
    m.meshes[mesh].alive = false; // its id is never reused; its vertices stay until the module is destroyed
    return {};
}

Result<void> Module::setInstanceTransform(InstanceId id, const Float4x4& transformDesc) {
    const glm::mat4 transform = toGlm(transformDesc);
    auto index = impl_->instanceIndex(id, "setInstanceTransform");
    if (!index) return fail(index.error());
    auto& inst = impl_->instances[index.value()];
    if (!inst.dynamic)
        return fail("setInstanceTransform: instance " + std::to_string(id) +
                    " is static (its baked shadows would go stale); add it with dynamic = true to move it");
    if (!finiteMatrix(transform))
        return fail("setInstanceTransform: instance " + std::to_string(id) + ": transform is not finite");
    if (singularMatrix(transform))
        return fail("setInstanceTransform: instance " + std::to_string(id) +
                    ": transform is singular (a zero scale)");
    inst.transform = transform;
    impl_->touchInstance(index.value());
    return {};
}

Result<LightId> Module::addLight(const LightDesc& light) {
    auto& m = *impl_;
    if (auto v = validateLight(light); !v) return fail("addLight: " + v.error());
    if (!m.freeLights.empty()) {
        const uint32_t index = m.freeLights.back();
        m.freeLights.pop_back();
        m.lights[index] = light;
        m.lightAlive[index] = 1;
        m.lightGeneration[index] = (m.lightGeneration[index] + 1) & ((1u << (32 - kLightIndexBits)) - 1);
        m.shadows[index] = {};
        m.touchShadow(index);
        return LightId(makeId(index, m.lightGeneration[index], kLightIndexBits));
    }
    if (m.lights.size() >= ML_MAX_LIGHTS)
        return fail("addLight: the module holds at most " + std::to_string(ML_MAX_LIGHTS) + " lights");
    m.lights.push_back(light);
    m.lightAlive.push_back(1);
    m.lightGeneration.push_back(0);
    m.shadows.emplace_back();
    m.touchShadow(uint32_t(m.lights.size() - 1));
    return LightId(m.lights.size() - 1);
}

Result<void> Module::removeLight(LightId id) {
    auto index = impl_->lightIndex(id, "removeLight");
    if (!index) return fail(index.error());
    impl_->lightAlive[index.value()] = 0;
    impl_->shadows[index.value()] = {};
    impl_->touchShadow(index.value());
    impl_->freeLights.push_back(index.value());
    return {};
}

Result<void> Module::setLight(LightId id, const LightDesc& light) {
    auto index = impl_->lightIndex(id, "setLight");
    if (!index) return fail(index.error());
    const uint32_t i = index.value();
    if (auto v = validateLight(light); !v) return fail("light " + std::to_string(id) + ": " + v.error());
    if (light.kind != impl_->lights[i].kind) // its bakes were made for the other kind's frustums
        impl_->shadows[i] = {};
    impl_->lights[i] = light;
    impl_->touchShadow(i); // castsShadows may have changed: the light's records are rewritten
    return {};
}

Result<void> Module::setEnvironment(Float3 ambientDesc, Float3 skyDesc) {
    const glm::vec3 ambient = toGlm(ambientDesc), sky = toGlm(skyDesc);
    for (const glm::vec3* v : {&ambient, &sky})
        if (!std::isfinite(v->x) || !std::isfinite(v->y) || !std::isfinite(v->z) || v->x < 0 || v->y < 0 ||
            v->z < 0)
            return fail("setEnvironment: ambient and sky must be finite and >= 0");
    impl_->ambient = ambient;
    impl_->sky = sky;
    return {};
}

Result<void> Module::setStaticShadow(LightId id, const StaticShadowDesc& shadow) {
    auto& m = *impl_;
    auto index = m.lightIndex(id, "setStaticShadow");
    if (!index) return fail(index.error());
    id = index.value();
    const uint32_t faces = m.lights[id].kind == LightKind::Point ? 6u : 1u;
    if (shadow.face >= faces)
        return fail("setStaticShadow: light " + std::to_string(id) + ": face " + std::to_string(shadow.face) +
                    (faces == 1 ? " (a spot light has face 0 only)" : " (a point light has faces 0..5)"));
    // Directional lights take orthographic bakes (directionalLightFrustum), the others perspective ones.
    if (shadow.method != StaticMethod::None &&
        (m.lights[id].kind == LightKind::Directional) != shadow.frustum.orthographic())
        return fail("setStaticShadow: light " + std::to_string(id) +
                    (shadow.frustum.orthographic() ? ": an orthographic bake needs a directional light"
                                                   : ": a directional light needs an orthographic bake"));
    if (shadow.method == StaticMethod::None) {
        m.shadows[id][shadow.face] = {};
        m.touchShadow(id);
        return {};
    }
    if (auto v = validateStatic(shadow.method, shadow.words.data(), shadow.words.size()); !v)
        return fail("setStaticShadow: light " + std::to_string(id) + ": " + v.error());
    const LightFrustum f = lightFrustum(shadow.frustum);
    // fov up to pi (exclusive): bakeStaticShadows renders a spot with fov = 2 x outer, and validateLight
    // accepts outer half angles up to just under pi/2.
    if (!(f.nearPlane > 0) || !(f.farPlane > f.nearPlane) ||
        !(f.orthographic() ? std::isfinite(f.orthoHalf) : f.fov > 0 && f.fov < 3.14159265f))
        return fail("setStaticShadow: light " + std::to_string(id) +
                    ": frustum needs 0 < near < far, 0 < fov < pi (or a finite orthographic half side)");
    if (!rigidView(f.view))
        return fail("setStaticShadow: light " + std::to_string(id) +
                    ": the frustum's view is not a rigid motion (rotation and translation, as lookAt makes)");
    // Every light's words live in one storage buffer: refuse a bake that would take it past the device's
    // storage buffer range (lavapipe: 128 MiB) instead of binding a range the shaders cannot address.
    uint64_t bytes = uint64_t(shadow.words.size()) * 4;
    for (size_t i = 0; i < m.shadows.size(); ++i)
        for (size_t f = 0; f < m.shadows[i].size(); ++f)
            if (!(i == id && f == shadow.face)) bytes += uint64_t(m.shadows[i][f].words.size()) * 4;
    const uint64_t range = m.device->properties.limits.maxStorageBufferRange;
    if (bytes > range)
        return fail("setStaticShadow: light " + std::to_string(id) + ": the static shadows would take " +
                    std::to_string(bytes >> 20) + " MiB, beyond the device's storage buffer range of " +
                    std::to_string(range >> 20) + " MiB");
    m.shadows[id][shadow.face] = {shadow.method, f, {shadow.words.begin(), shadow.words.end()}};
    m.touchShadow(id);
    m.wordsPending = true;
    return {};
}

void Module::clearStaticShadow(LightId light) {
    auto index = impl_->lightIndex(light, "clearStaticShadow");
    if (!index) return;
    const uint32_t id = index.value();
    impl_->shadows[id] = {};
    impl_->touchShadow(id); // all faces
}

Result<uint32_t> Module::bakeStaticShadows(StaticMethod method, uint32_t resolution,
                                           const std::function<void(uint32_t, uint32_t)>& progress) {
    auto& m = *impl_;
    if (method == StaticMethod::None) return fail("bakeStaticShadows: no method");
    if (resolution < 8 || resolution > 16384)
        return fail("bakeStaticShadows: resolution " + std::to_string(resolution) + " outside 8..16384");
    // Static casters in world space; mirrored instances swap winding so front faces stay front faces.
    CasterTriangles casters;
    for (const Impl::InstanceData& inst : m.instances) {
        if (!inst.alive || inst.dynamic || !inst.castsShadows) continue;
        const Impl::MeshRange& r = m.meshes[inst.mesh];
        const bool mirror = glm::determinant(glm::mat3(inst.transform)) < 0.0f;
        for (uint32_t i = 0; i + 2 < r.indexCount; i += 3) {
            glm::vec3 p[3];
            for (int k = 0; k < 3; ++k) {
                const MeshVertex& v = m.vertices[r.firstVertex + m.indices[r.firstIndex + i + k]];
                p[k] =
                    glm::vec3(inst.transform * glm::vec4(v.position[0], v.position[1], v.position[2], 1.0f));
            }
            if (mirror) std::swap(p[1], p[2]);
            casters.add(p[0], p[1], p[2], r.closed);
        }
    }
    auto renderer = DualDepthRenderer::create(*m.device);
    if (!renderer) return fail(renderer.error());
    std::vector<uint32_t> bakeable;
    for (uint32_t i = 0; i < m.lights.size(); ++i) {
        const LightDesc& l = m.lights[i];
        if (m.lightAlive[i] && !l.dynamic && l.castsShadows && l.kind != LightKind::Directional)
            bakeable.push_back(i);
    }
    uint32_t done = 0;
    for (uint32_t i : bakeable) {
        const GlmLight l(m.lights[i]);
        LightShape sl;
        sl.type = l.kind == LightKind::Point ? LightKind::Point : LightKind::Spot;
        sl.position = l.position;
        sl.direction = l.direction;
        sl.range = l.range;
        sl.outerAngle = l.outerAngle;
        const std::vector<LightFrustum> frustums = lightFrustums(sl);
        const LightId id = makeId(i, m.lightGeneration[i], kLightIndexBits);
        for (uint32_t face = 0; face < frustums.size(); ++face) {
            const LightFrustum& f = frustums[face];
            // LightDesc::shadowResolution: the light's own hint, else the bake's.
            auto map =
                renderer.value()->render(casters, f, l.shadowResolution ? l.shadowResolution : resolution);
            if (!map) return fail("bakeStaticShadows: light " + std::to_string(id) + ": " + map.error());
            auto words = encodeStatic(method, map.value(), {f.nearPlane, f.farPlane, {}});
            if (!words) return fail("bakeStaticShadows: light " + std::to_string(id) + ": " + words.error());
            if (auto r = setStaticShadow(id, {method, f, words.value(), face}); !r) return fail(r.error());
        }
        ++done;
        if (progress) progress(done, uint32_t(bakeable.size()));
    }
    return done;
}

Result<void> Module::setShadowFilter(uint32_t radius, bool byLevel) {
    if (radius > ML_MAX_PCF_RADIUS)
        return fail("setShadowFilter: PCF radius " + std::to_string(radius) + " > " +
                    std::to_string(ML_MAX_PCF_RADIUS));
    impl_->pcfRadius = radius;
    impl_->filterByLevel = byLevel;
    impl_->recordsEpoch++; // every record carries the radius
    impl_->vsm.setPcfRadius(radius);
    return {};
}

Result<void> Module::setCamera(const CameraDesc& c) {
    // Finite and bounded position, target and up; target != position; up not parallel to the view;
    // 0 < fovY < pi; 0 < near < far < infinity (lights/lights.h).
    if (auto v = validateCamera(c); !v) return v; // its reasons start with "camera: "
    if (auto v = validateJitter(toGlm(c.jitter)); !v) return v;
    impl_->camera = c;
    impl_->hostCamera.reset();
    impl_->cameraSet = true;
    return {};
}

Result<void> Module::setCameraMatrices(const Float4x4& viewDesc, const Float4x4& projectionDesc,
                                       Float2 jitter) {
    const glm::mat4 view = toGlm(viewDesc), projection = toGlm(projectionDesc);
    auto c = cameraFromMatrices(view, projection);
    if (!c) return fail(c.error());
    if (auto v = validateJitter(toGlm(jitter)); !v) return v;
    impl_->camera = c.value();
    impl_->camera.jitter = jitter;
    impl_->hostCamera = CameraMatrices{view, projection};
    impl_->cameraSet = true;
    return {};
}

CameraMatrices Module::Impl::frameCamera() const {
    const uint32_t w = std::max(width, 1u), h = std::max(height, 1u);
    CameraMatrices m = hostCamera ? *hostCamera : cameraMatrices(camera, float(w) / float(h));
    m.projection = jittered(m.projection, toGlm(camera.jitter), w, h);
    return m;
}

Float4x4 Module::viewProjection() const {
    if (!impl_->width) return Float4x4{};
    const CameraMatrices m = impl_->frameCamera();
    return fromGlm(m.projection * m.view);
}

Result<void> Module::record(VkCommandBuffer cmd) {
    auto& m = *impl_;
    if (!m.width)
        return fail(m.targetsDetached
                        ? "record: no targets: detachTargets() released them (call setTargets or "
                          "createTargets with live images first)"
                        : "record: no targets (call createTargets or setTargets first)");
    // A default camera would render a frame the host never asked for (often empty): refused.
    if (!m.cameraSet) return fail("record: no camera (call setCamera or setCameraMatrices first)");
    if (m.timing == TimingMode::Timestamps && cmd == VK_NULL_HANDLE)
        return fail("record: no command buffer (the module records into the host's)");
    // Fenced timing submits every pass itself, before the host's command buffer runs: a host G-buffer
    // recorded into `cmd` would be read before it is drawn (and in the wrong layout).
    if (m.timing == TimingMode::Fenced && !m.ownTargets && cmd != VK_NULL_HANDLE)
        return fail("record: Fenced timing with host targets submits the passes before the host's command "
                    "buffer: submit and wait for the G-buffer, then call record(VK_NULL_HANDLE), or use "
                    "TimingChoice::Timestamps");
    // Every submit and wait made from here on is counted as record()'s (Device::recordQueueCounts): there
    // must be none outside Fenced timing. While the frame is prepared, setup work that would otherwise be a
    // one-time submit (a new buffer's fill, a grown buffer's copy) is queued for the frame's own command
    // buffer instead (m.setup); during the passes nothing is queued, so a buffer made there would show up
    // as a counted submit rather than go unfilled.
    const Device::RecordScope inRecord(*m.device);
    m.setup.active = true;
    auto began = m.beginFrame();
    m.setup.active = false;
    if (!began) return fail("record: " + began.error());
    const uint32_t slotIndex = began.value();
    FrameContext frame = m.frameContext(cmd, slotIndex);
    frame.own.setup = &m.setup;
    // The frame's list of passes, in order (engine/frame_passes.cpp); runFrame times them.
    if (auto r = recordFrame(m.profiler, frame, m.features); !r) return fail("record: " + r.error());
    m.endFrame(slotIndex);
    m.ownOutputRecorded = m.ownOutputRecorded || m.ownTargets;
    m.retireStaged(); // the staging buffers this frame copied from (and replaced): freed once it is done
    return {};
}

void Module::collect() {
    for (uint32_t i = 0; i < impl_->slots.size(); ++i) {
        // Oldest first: slot of frame (frameIndex - slots + k).
        uint64_t f = impl_->frameIndex + i;
        uint32_t slot = uint32_t(f % impl_->slots.size());
        if (impl_->slots[slot].pending) impl_->collectSlot(slot);
    }
}

std::vector<FrameReport> Module::takeReports() {
    std::vector<FrameReport> out;
    out.swap(impl_->reports);
    return out;
}

Result<void> Module::readOutput(std::vector<uint8_t>& rgba) {
    auto& m = *impl_;
    if (!m.width) return fail("readOutput: no targets (call createTargets first)");
    if (!m.ownTargets) return fail("readOutput: the output image belongs to the host (setTargets)");
    if (m.hdrOutput) return fail("readOutput: the module writes HDR only (ModuleOptions::hdrOutput)");
    if (!m.ownOutputRecorded)
        return fail("readOutput: no frame was recorded into these targets yet (record or submitFrame first)");
    const Device& d = *m.device;
    ML_VK_CHECK(d.waitQueue());
    size_t bytes = size_t(m.width) * m.height * 4;
    if (auto r = ensureBuffer(d, m.readback, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "readback",
                              MemoryRole::Readback);
        !r)
        return fail("readOutput: " + r.error());
    auto began = m.device->tryBeginOneTime("readOutput");
    if (!began) return fail("readOutput: " + began.error());
    VkCommandBuffer cmd = began.value();
    imageBarrier(cmd, m.output.image, m.output.aspect, VK_IMAGE_LAYOUT_GENERAL,
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                 VK_ACCESS_2_TRANSFER_READ_BIT);
    copyImageToBuffer(cmd, m.output, m.readback);
    imageBarrier(cmd, m.output.image, m.output.aspect, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                 VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    if (auto r = m.device->tryEndOneTime(cmd, "readOutput"); !r) return fail("readOutput: " + r.error());
    rgba.resize(bytes);
    std::memcpy(rgba.data(), m.readback.data, bytes);
    return {};
}

} // namespace ml
