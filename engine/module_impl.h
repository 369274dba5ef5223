// Internal state of ml::Module. Not part of the public API and not installed: tests include it to read
// back intermediate buffers and compare them with the CPU references; engine/diagnostics.cpp to implement
// the public read-backs (engine/manylights_diagnostics.h). apps/ and host/ never include it.
#pragma once
#include "culling/culling.h"
#include "engine/camera.h"
#include "engine/frame.h"
#include "engine/gbuffer.h"
#include "manylights/glm.h"
#include "manylights/manylights.h"
#include "shaders/shared/enums.h"
#include "shadows/static/static_types.h"
#include "gpu/profiler.h"
#include "shadows/virtual/vsm.h"
#include "shadows/virtual/vsm_meshlets.h"

#include "lights/evaluate_pass.h"

#include <array>
#include <cstring>
#include <map>

namespace ml {

using gpu::GpuInstance;

struct Module::Impl {
    struct MeshRange {
        uint32_t firstVertex, firstIndex, indexCount;
        glm::vec3 lo, hi; // object-space bounds
        bool alive = true;
        bool closed = false;
        // VSM mesh path (shadows/virtual/vsm_meshlets.h): the mesh's meshlets, and whether meshIsClosed
        // verified it closed with outward faces (the task shader's back-facing cone test).
        uint32_t firstMeshlet = 0, meshletCount = 0;
        bool coneCull = false;
    };
    struct InstanceData {
        MeshId mesh;
        glm::mat4 transform;
        glm::vec3 albedo;
        bool dynamic;
        bool alive = true;
        bool castsShadows = true;
        uint32_t generation = 0;
        bool receivesShadows = true;              // setInstanceShadowReceiving
        float roughness = 0.5f, metalness = 0.0f; // setInstanceMaterial
        // Same inputs, bit for bit (what the frame writes from them would be the same).
        bool same(const InstanceData& o) const {
            return mesh == o.mesh && std::memcmp(&transform, &o.transform, sizeof(transform)) == 0 &&
                   std::memcmp(&albedo, &o.albedo, sizeof(albedo)) == 0 && dynamic == o.dynamic &&
                   alive == o.alive && castsShadows == o.castsShadows &&
                   receivesShadows == o.receivesShadows &&
                   std::memcmp(&roughness, &o.roughness, sizeof(float)) == 0 &&
                   std::memcmp(&metalness, &o.metalness, sizeof(float)) == 0;
        }
    };
    // Everything one frame in flight writes from the host.
    struct Slot {
        Buffer frame, lights, counters, slices, instances;
        Buffer wide; // WideLight entries (culling/culling.h wideFootprint)
        uint32_t wideCount = 0, wideThreads = 0;
        Buffer draws; // G-buffer indirect draws, one per instance (rewritten each frame like instances)
        // The slot's copy of the static shadow records (engine/module_uploads.cpp): light i's six at
        // 6 i; rewritten in place for the lights whose lightVersion moved since the slot's last frame.
        Buffer shadowRecords;
        std::vector<uint64_t> shadowVersion; // per light, the lightVersion its records were written from
        // Per instance, the instanceVersion its GpuInstance and draw in this slot's buffers were written
        // from (~0: never): only the instances that changed since the slot's last frame are rewritten.
        std::vector<uint64_t> instanceVersion;
        // Instances changed since this slot's last frame (updateInstanceCache appends to every slot's);
        // the slot rewrites only these, or every instance when instanceVersion is empty (new buffers).
        std::vector<uint32_t> pendingInstances;
        uint64_t recordsEpoch = ~uint64_t(0);
        bool pending = false;
        uint64_t frameNumber = 0;
        uint32_t lightsTotal = 0, lightsVisible = 0, clusters = 0, poolCapacity = 0;
        CullingMode mode = CullingMode::Clustered;
        bool statistics = false;
    };

    std::unique_ptr<Device> device;
    CullingMode culling = CullingMode::Clustered;
    CullingMode cullingMode = CullingMode(~0u); // mode the cluster buffers are sized for
    bool statistics = false;
    DebugView view = DebugView::Shaded;
    TimingMode timing = TimingMode::Timestamps;
    float exposure = 3.0f;     // night scenes: lamps of ~40 cd at 6 m give ~0.1 before exposure
    uint32_t poolOverride = 0; // tests: force a small light-list pool

    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    std::vector<MeshRange> meshes;
    std::vector<InstanceData> instances;
    std::vector<LightDesc> lights;
    std::vector<uint8_t> lightAlive;
    std::vector<uint32_t> lightGeneration;
    std::vector<uint32_t> freeLights, freeInstances;
    glm::vec3 ambient{0.020f, 0.024f, 0.040f}; // night: moonlit blue, before exposure
    glm::vec3 sky{0.006f, 0.009f, 0.022f};
    struct StaticShadow {
        StaticMethod method = StaticMethod::None;
        LightFrustum frustum;
        std::vector<uint32_t> words;
        uint32_t base = 0;     // first word in staticWords, once resident
        bool resident = false; // uploaded into the current staticWords
    };
    std::vector<std::array<StaticShadow, 6>> shadows; // per light and cube face (spots: face 0)
    uint32_t pcfRadius = 0;
    bool filterByLevel = false; // GpuShadowRecord.info.z bit 0 (setShadowFilter)
    // Static shadows reach the GPU without a device wait (engine/module_uploads.cpp): the words are
    // appended to one shared arena, staticWords (a frame in flight reads only ranges written before it;
    // removed bakes leave garbage until the arena is rebuilt into a new buffer, the old one retired), and
    // the records live per slot, rewritten for the lights whose version moved.
    Buffer staticWords;
    uint64_t wordsUsed = 0;           // arena cursor (words)
    bool wordsPending = false;        // a face has words not yet resident
    uint64_t recordsEpoch = 0;        // bumped when every record changes (PCF radius, arena rebuilt)
    void touchShadow(uint32_t light); // stamps lightVersion (below): the records and light caches follow
    uint32_t shadowRecordOf(uint32_t light) const; // 6 light, or ML_NO_SHADOW
    Result<void> uploadShadowWords();
    Result<void> writeShadowRecords(Slot& slot);
    // The records the last recorded frame read (its slot's copy), for the CPU references.
    const gpu::GpuShadowRecord* lastShadowRecords() const {
        return slots[lastSlot].shadowRecords.as<gpu::GpuShadowRecord>();
    }
    uint64_t recordsWritten = 0; // lights whose records a slot rewrote (tests: one light costs one)
    CameraDesc camera;           // setCamera's, or the one setCameraMatrices' matrices describe
    std::optional<CameraMatrices> hostCamera; // setCameraMatrices: used as given (plus jitter)
    bool cameraSet = false;             // record() refuses a frame before setCamera or setCameraMatrices
    CameraMatrices frameCamera() const; // view and jittered projection for the current target size
    bool meshesDirty = true; // addMesh: the new vertices, indices and meshlets to upload (uploadMeshes)
    // Mesh data is append-only (removeMesh keeps its vertices), so each of the five mesh buffers
    // (vertices, indices, meshlets, meshlet vertices, meshlet triangles) holds a prefix of its CPU array:
    // the bytes uploaded, with capacity to spare (doubling). Tests read meshBytesStaged: the bytes sent.
    std::array<size_t, 5> meshBytesUploaded{};
    uint64_t meshBytesStaged = 0;
    Buffer vertexBuffer, indexBuffer, readback;
    MeshletSet meshlets;
    Buffer meshletBuffer, meshletVertexBuffer, meshletTriangleBuffer;

    uint32_t width = 0, height = 0;
    bool ownTargets = false;
    bool targetsDetached = false; // detachTargets() was the last call on targets: record() says so
    // A frame was recorded into the module's current own targets: before one, their output is still in
    // UNDEFINED layout with nothing in it, and readOutput refuses instead of copying from it.
    bool ownOutputRecorded = false;
    bool ownMaterials = false; // createTargets(..., materials): GGX from the module's material target
    GBufferTargets targets;
    HostTargets host;
    Image hdr, output;

    // The features the frame's passes record (engine/frame.h), and the names the module's code and the
    // tests use for the ones it also drives outside the frame (targets, pipelines, VSM preparation).
    FrameFeatures features;
    GBufferPass& gbuffer = features.gbuffer;
    LightCulling& cull = features.cull;
    EvaluatePass& evaluate = features.evaluate;
    VirtualShadowMaps& vsm = features.vsm; // state: map slots, page tables, pool
    VsmPasses& vsmPasses = features.vsmPasses;
    bool hdrOutput = false;
    VsmSettings vsmSettings;
    // What the frame writes per instance, kept between frames and recomputed only for the instances whose
    // inputs changed (so that a frame with 1 % of 10,000 instances moving stays cheap): the inputs it was
    // made from, the GPU records, the VSM caster (world box: 8 corners transformed), and a version stamped
    // from instanceStamp at each change.
    std::vector<InstanceData> instanceFrom;
    std::vector<GpuInstance> instanceRecords;
    std::vector<VkDrawIndexedIndirectCommand> instanceDraws;
    std::vector<VsmInstance> casters;
    std::vector<uint64_t> instanceVersion;
    uint64_t instanceStamp = 0;
    // Instances the host touched since the last frame (touchInstance at every mutation point: add,
    // remove, transform, casting, receiving, material): only they are compared with their inputs, so a
    // frame costs the changes, not the instance count. instanceTouched dedups the list.
    std::vector<uint32_t> touchedInstances;
    std::vector<uint8_t> instanceTouched;
    void touchInstance(uint32_t i) {
        if (instanceTouched.size() <= i) instanceTouched.resize(size_t(i) + 1, 0);
        if (!instanceTouched[i]) touchedInstances.push_back(i);
        instanceTouched[i] = 1;
    }
    // Instances whose records changed since the VSM's last successful prepare() (it compares their
    // boxes with the ones its maps saw); kept when prepare() fails, so the next frame still sees them.
    std::vector<uint32_t> vsmChangedInstances;
    // Work counters for the tests (cumulative): instances updateInstanceCache visited, light records
    // updateLightRecords remade. A frame where nothing changed adds 0 to both.
    uint64_t instancesVisited = 0, lightRecordsMade = 0;
    // Per light, what a frame writes of it, kept between frames and remade only when the light's version
    // moved (touchShadow stamps it at every change: addLight, setLight, removeLight, static shadows):
    // the GPU record with its static record index, the bounding sphere the frustum test takes, and what
    // the VSM is given (VsmLight::version carries the stamp, so the VSM compares stamps, not lights).
    struct LightRecord {
        uint64_t version = 0; // lightVersion it was made from (0: never)
        gpu::GpuLight gpu{};
        glm::vec4 sphere{0.0f};
    };
    std::vector<LightRecord> lightRecords;
    std::vector<uint64_t> lightVersion; // per light, from lightStamp (never 0 once the light exists)
    uint64_t lightStamp = 0;
    std::vector<VsmLight> vsmLights;       // what the VSM is given of every light (by id)
    std::vector<uint32_t> visibleLightIds; // this frame's visible lights, in GpuLight order
    void updateLightRecords();
    void updateInstanceCache();
    Profiler profiler;
    std::vector<Slot> slots;
    uint64_t frameIndex = 0;
    std::vector<FrameReport> reports;

    // Inputs of the last recorded frame, for the CPU references.
    gpu::FrameConstants lastConstants{};
    std::vector<float> lastSliceFar;
    std::vector<gpu::GpuLight> lastLights;
    uint32_t lastSlot = 0;
    std::optional<HostShaderBindings> hostBindings; // the last frame's (engine/host_shader.cpp)
    void captureHostBindings(uint32_t slot);        // endFrame

    // Out of memory in any of these is an error naming what failed; the state stays destroyable and the
    // dirty flags stay set, so a later call retries.
    Result<void> init();
    void destroy();
    // Targets and output mode (engine/module_targets.cpp).
    void destroyTargets();               // retires the module's images (host ones are the host's)
    Result<void> createOutput(bool own); // own: full-size HDR and output; host targets: 1x1 stubs
    // The evaluation variant for the current targets in an output mode, and the pipelines of both modes
    // (engine/frame_write.cpp): built by createTargets and setTargets, never by record().
    EvaluateOutputs evaluateOutputs(bool hdr) const;
    bool evaluatePbr() const;
    Result<void> preparePipelines();
    // Every device-wide wait of the module goes through waitIdle, which counts it (deviceWaits;
    // diag::deviceWaitCount): docs/integration.md lists the calls that still wait.
    uint64_t deviceWaits = 0;
    uint64_t waitIdle();
    // Deferred release: a buffer or image a frame in flight may still use is retired (its handle
    // cleared) and destroyed at the first record() whose slot contract proves that frame done.
    struct Retired {
        uint64_t frame; // frameIndex when retired
        Buffer buffer;
        Image image;
    };
    std::vector<Retired> retired;
    void retire(Buffer& buffer);
    void retire(Image& image);
    // Staged uploads (engine/module_uploads.cpp): load-time data for GPU-only buffers, copied by the
    // next recorded frame (FrameOwnInputs::copies); the staging buffers are retired with that frame.
    std::vector<Buffer> staging;
    std::vector<StagedCopy> stagedCopies;
    // Writes `bytes` into a new staging buffer and queues `copies` from it (their regions' srcOffset
    // index `bytes`). Nothing is queued on failure.
    Result<void> stage(const std::vector<uint8_t>& bytes, std::vector<StagedCopy> copies, const char* name);
    void retireStaged(); // after the frame that recorded the copies (and the setup's commands, below)
    // Fills of new GPU-only buffers, copies of grown ones and the buffers they replace, queued while
    // record() prepares a frame (beginFrame) and recorded by its frame-begin pass instead of one-time
    // submits (gpu/resources.h; Device::frameSetup points here from init() to destroy()).
    FrameSetup setup;
    void releaseRetired(bool all);
    Result<void> uploadMeshes();
    void collectSlot(uint32_t index);
    Result<uint32_t> lightIndex(LightId id, const char* what) const;
    Result<uint32_t> instanceIndex(InstanceId id, const char* what) const;
    // The host side of Module::record (engine/frame_write.cpp): uploads, the slot's collection and
    // buffers (returns the slot), the passes' context; endFrame marks the slot pending.
    Result<uint32_t> beginFrame();
    FrameContext frameContext(VkCommandBuffer cmd, uint32_t slot) const;
    void endFrame(uint32_t slot);
    Result<void> writeFrame(Slot& slot, uint32_t slotIndex, const ClusterGrid& grid, CullingMode mode);
};

// setTargets' checks (HostTargets' table in manylights/module.h), for an output mode.
Result<void> checkHostTargets(const HostTargets& targets, bool hdr);

// The module's internal state and device, for tests and engine/diagnostics.cpp (not for apps/ or host/:
// the test PublicApiIncludes checks that they include only public headers).
inline Module::Impl& internals(Module& module) {
    return *module.impl_;
}
inline const Module::Impl& internals(const Module& module) {
    return *module.impl_;
}
inline Device& deviceOf(Module& module) {
    return *internals(module).device;
}

} // namespace ml
