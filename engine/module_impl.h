// Internal state of ml::Module. Not part of the public API and not installed: tests include it to read
// back intermediate buffers and compare them with the CPU references; engine/diagnostics.cpp to implement
// the public read-backs (engine/manylights_diagnostics.h). apps/ and host/ never include it.
#pragma once
#include "culling/culling.h"
#include "engine/camera.h"
#include "engine/frame.h"
#include "engine/gbuffer.h"
#include "engine/manylights.h"
#include "gpu/profiler.h"
#include "shadows/virtual/vsm.h"
#include "shadows/virtual/vsm_meshlets.h"

#include "lights/evaluate_pass.h"

#include <array>
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
    };
    // Everything one frame in flight writes from the host.
    struct Slot {
        Buffer frame, lights, counters, slices, instances;
        Buffer wide; // WideLight entries (culling/culling.h wideFootprint)
        uint32_t wideCount = 0, wideThreads = 0;
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
    };
    std::vector<std::array<StaticShadow, 6>> shadows; // per light and cube face (spots: face 0)
    uint32_t pcfRadius = 0;
    bool shadowsDirty = true;
    Buffer staticWords, shadowRecords;
    std::vector<uint32_t> recordOfLight; // light -> record index or ML_NO_SHADOW
    std::vector<gpu::GpuShadowRecord> records;
    CameraDesc camera;                        // setCamera's, or the one setCameraMatrices' matrices describe
    std::optional<CameraMatrices> hostCamera; // setCameraMatrices: used as given (plus jitter)
    bool cameraSet = false;             // record() refuses a frame before setCamera or setCameraMatrices
    CameraMatrices frameCamera() const; // view and jittered projection for the current target size
    bool geometryDirty = true;
    Buffer vertexBuffer, indexBuffer, drawBuffer, readback;
    MeshletSet meshlets;
    Buffer meshletBuffer, meshletVertexBuffer, meshletTriangleBuffer;

    uint32_t width = 0, height = 0;
    bool ownTargets = false;
    GBufferTargets targets;
    HostTargets host;
    Image hdr, output;

    GBufferPass gbuffer;
    LightCulling cull;
    EvaluatePass evaluate;
    StatisticsPass statisticsPass;
    bool hdrOutput = false;
    VirtualShadowMaps vsm; // state: map slots, page tables, pool
    VsmPasses vsmPasses;   // its GPU passes
    VsmSettings vsmSettings;
    std::vector<InstanceData> lastInstances; // for moved-caster detection (by the VSM)
    Profiler profiler;
    FramePasses passes{gbuffer, cull, vsm, vsmPasses, evaluate, statisticsPass}; // Module::record's list
    std::vector<Slot> slots;
    uint64_t frameIndex = 0;
    std::vector<FrameReport> reports;

    // Inputs of the last recorded frame, for the CPU references.
    gpu::FrameConstants lastConstants{};
    std::vector<float> lastSliceFar;
    std::vector<gpu::GpuLight> lastLights;
    uint32_t lastSlot = 0;

    // Out of memory in any of these is an error naming what failed; the state stays destroyable and the
    // dirty flags stay set, so a later call retries.
    Result<void> init();
    void destroy();
    void destroyTargets();
    Result<void> createOutput(bool withOutput);
    Result<void> uploadGeometry();
    Result<void> uploadShadows();
    void collectSlot(uint32_t index);
    Result<uint32_t> lightIndex(LightId id, const char* what) const;
    Result<uint32_t> instanceIndex(InstanceId id, const char* what) const;
    // The host side of Module::record (engine/frame_write.cpp): uploads, the slot's collection and
    // buffers (returns the slot), the passes' context; endFrame marks the slot pending.
    Result<uint32_t> beginFrame();
    FrameContext frameContext(VkCommandBuffer cmd, uint32_t slot) const;
    void endFrame(uint32_t slot);
    void writeFrame(Slot& slot, uint32_t slotIndex, const ClusterGrid& grid, CullingMode mode);
};

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
