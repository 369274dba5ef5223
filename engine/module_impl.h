// Internal state of ml::Module. Not part of the public API: the demo never includes it; tests do, to
// read back intermediate buffers and compare them with the CPU references.
#pragma once
#include "culling/culling.h"
#include "engine/gbuffer.h"
#include "engine/manylights.h"
#include "engine/profiler.h"

#include "evaluate.comp.spv.h"

#include <array>
#include <map>

namespace ml {

// Per-instance GPU data (gbuffer.vert's GpuInstance).
struct GpuInstance {
    glm::mat4 model;
    glm::mat4 normalMatrix;
    glm::vec4 albedo;
};
static_assert(sizeof(GpuInstance) == 144);

struct Module::Impl {
    struct MeshRange {
        uint32_t firstVertex, firstIndex, indexCount;
    };
    struct InstanceData {
        MeshId mesh;
        glm::mat4 transform;
        glm::vec3 albedo;
        bool dynamic;
    };
    // Everything one frame in flight writes from the host.
    struct Slot {
        Buffer frame, lights, counters, slices, instances;
        bool pending = false;
        uint64_t frameNumber = 0;
        uint32_t lightsTotal = 0, lightsVisible = 0, clusters = 0, poolCapacity = 0;
        CullingMode mode = CullingMode::Clustered;
    };

    std::unique_ptr<Device> device;
    CullingMode culling = CullingMode::Clustered;
    CullingMode cullingMode = CullingMode(~0u); // mode the cluster buffers are sized for
    bool statistics = true;
    DebugView view = DebugView::Shaded;
    TimingMode timing = TimingMode::Timestamps;
    float exposure = 3.0f; // night scenes: lamps of ~40 cd at 6 m give ~0.1 before exposure
    uint32_t poolOverride = 0; // tests: force a small light-list pool

    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    std::vector<MeshRange> meshes;
    std::vector<InstanceData> instances;
    std::vector<LightDesc> lights;
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
    CameraDesc camera;
    bool geometryDirty = true;
    Buffer vertexBuffer, indexBuffer, drawBuffer, readback;

    uint32_t width = 0, height = 0;
    bool ownTargets = false;
    GBufferTargets targets;
    HostTargets host;
    Image hdr, output;

    GBufferPass gbuffer;
    LightCulling cull;
    ShaderModule evalShader;
    std::map<uint32_t, Program> evalPrograms;
    Profiler profiler;
    std::vector<Slot> slots;
    uint64_t frameIndex = 0;
    std::vector<FrameReport> reports;

    // Inputs of the last recorded frame, for the CPU references.
    gpu::FrameConstants lastConstants{};
    std::vector<float> lastSliceFar;
    std::vector<gpu::GpuLight> lastLights;

    void init();
    void destroy();
    void destroyTargets();
    void createOutput(bool withOutput);
    void uploadGeometry();
    void uploadShadows();
    const Program& evalProgram();
    void collectSlot(uint32_t index);
};

} // namespace ml
