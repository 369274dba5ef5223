// manylights: the public module API. A host engine uses only this header.
//
//   auto module = ml::Module::create({});                 // or borrow the host's device: options.borrow
//   ml::MeshId box = module->addMesh({vertices, indices, /*closed*/ true}).value();
//   module->addInstance(box, transform, albedo, /*dynamic*/ false);
//   module->addLight(spot);                               // validated: a bad value returns an error
//   module->createTargets(1280, 720);                     // or setTargets(host G-buffer views)
//   each frame: module->setCamera(cam); module->setInstanceTransform(...);
//               module->record(cmd);                      // G-buffer (own targets), culling, shadows,
//               evaluation submit cmd; later module->collect(); module->takeReports() give per-pass GPU ms
//               and stats.
//
// Frames in flight: record() uses slot (frame % framesInFlight) for its per-frame buffers and
// queries. The host must have waited for the frame that last used a slot before recording into it
// again (the usual fence per frame in flight); record() then reads that frame's results without
// stalling.
//
// This header and the ones it includes are the public folder manylights/ and hold API types only (no
// Vulkan wrapper classes, no internal state, no glm: vectors and matrices are manylights/types.h, whose
// layout no host compile definition changes; manylights/glm.h converts them).
#pragma once
#include "manylights/device.h"
#include "manylights/enums.h"
#include "manylights/host_bindings.h"
#include "manylights/lights.h"
#include "manylights/pass_times.h"
#include "manylights/result.h"
#include "manylights/types.h"
#include "manylights/vsm_settings.h"

#include <vulkan/vulkan.h>

#include <cstddef>

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ml {

// CullingMode, LightKind and StaticMethod: manylights/enums.h.
const char* cullingName(CullingMode mode);
Result<CullingMode> parseCulling(const std::string& name);

// What record() leaves in the output: the shaded frame, or the light-complexity heat map of lights
// evaluated / reaching per pixel (a colour ramp from blue through green to red as the count grows).
// Vsm: pixels coloured by the virtual shadow map page their first shadowed light reads (mip, drawn
// this frame or cached, no caster, fallback).
enum class DebugView : uint32_t { Shaded, LightsEvaluated, LightsReaching, Vsm };

// How per-pass GPU times are measured (manylights/pass_times.h).
//   Auto, Timestamps: record() records every pass into the host's command buffer, after the host's own
//     commands, with a timestamp pair around each. Auto picks Fenced on a CPU device instead, whose
//     timestamps need not bracket compute work (compute passes can read near zero there).
//   Fenced: a profiling mode the host opts into: record() submits each pass in its own command buffer
//     and waits for it, timing it with the host clock (honest per-pass times on CPU devices); the host's
//     command buffer receives nothing, so the host must have submitted and waited for its G-buffer work
//     before calling record(). The demo and the benchmarks use it on CPU devices.
enum class TimingChoice : uint32_t { Auto, Timestamps, Fenced };

struct ModuleOptions {
    DeviceOptions device;               // when the module makes its own device
    std::optional<DeviceBorrow> borrow; // when the host hands over its device
    CullingMode culling = CullingMode::Clustered;
    bool statistics = false; // per-pixel light counts: a pass of its own (a brute-force loop)
    // false: the output is tone-mapped sRGB values in an RGBA8 UNORM image (an sRGB swapchain would apply
    // gamma twice: copy into a UNORM image, or use hdrOutput). true: HostTargets::output must be an
    // RGBA16F storage image and receives linear HDR radiance (times exposure not applied); with
    // module-owned targets, the HDR image is outputImage() and readOutput refuses. The initial mode:
    // Module::setHdrOutput switches it later.
    bool hdrOutput = false;
    VsmSettings vsm; // virtual shadow maps for dynamic casters (vsm.enabled)
    uint32_t framesInFlight = 2;
    TimingChoice timing = TimingChoice::Auto;
    // A pipeline cache the host owns, created on the borrowed device (a module on its own device refuses
    // one): every pipeline the module builds (create(), createTargets, setTargets; never record()) goes
    // through it, so the host can save it (vkGetPipelineCacheData) and start the next run from it. It must
    // outlive the module; the module only reads and adds to it (externally synchronised: the host does
    // not use it from another thread during those calls).
    VkPipelineCache pipelineCache = VK_NULL_HANDLE;
};

struct MeshVertex {
    float position[3];
    float normal[3];
};
static_assert(sizeof(MeshVertex) == 24);

struct MeshDesc {
    std::span<const MeshVertex> vertices;
    std::span<const uint32_t> indices; // triangle list, CCW front faces
    bool closed = false;               // watertight: static shadow bakes may use exit depths
    std::string name;
};

// LightDesc and validateLight: manylights/lights.h.

// The frustum a light's static shadow was rendered with. `view`: world -> light view (looking down -Z), a
// rigid motion. Perspective (spot, point faces): square, `fov` the full vertical = horizontal angle (< pi),
// depth range [nearPlane, farPlane]. Orthographic (directional, orthoHalf > 0): the square volume's half
// side in metres, fov unused; a map fitted to a box (orthoHalfY > 0, at most orthoHalf) covers view y in
// [-orthoHalf, -orthoHalf + 2 orthoHalfY] only, and fitMargin (metres) is what the fit added on every side.
// Converts implicitly from any frustum type with these members (the bake files' own frustum type).
template <class F>
concept ShadowFrustumLike = requires(const F& f) {
    Float4x4(f.view);
    float(f.fov) + float(f.nearPlane) + float(f.farPlane) + float(f.orthoHalf) + float(f.orthoHalfY) +
        float(f.fitMargin);
};
struct ShadowFrustum {
    Float4x4 view;
    float fov = 1.0f;
    float nearPlane = 0.05f;
    float farPlane = 10.0f;
    float orthoHalf = 0.0f;
    float orthoHalfY = 0.0f;
    float fitMargin = 0.0f;
    ShadowFrustum() = default;
    template <ShadowFrustumLike F>
    ShadowFrustum(const F& f)
        : view(f.view), fov(f.fov), nearPlane(f.nearPlane), farPlane(f.farPlane), orthoHalf(f.orthoHalf),
          orthoHalfY(f.orthoHalfY), fitMargin(f.fitMargin) {}
    bool orthographic() const { return orthoHalf > 0.0f; }
};
static_assert(sizeof(ShadowFrustum) == 88 && offsetof(ShadowFrustum, fitMargin) == 84);

// A light's baked static shadow: the encoding (validated by setStaticShadow, so shaders never read
// out of bounds) and the frustum it was rendered with, whose view must be a rigid motion (rotation and
// translation, as lookAt makes: the shadow record keeps it as a quaternion). A bake file holds these per
// light.
struct StaticShadowDesc {
    StaticMethod method = StaticMethod::None;
    ShadowFrustum frustum;
    std::span<const uint32_t> words;
    uint32_t face = 0; // point lights: cube face 0..5 (+X, -X, +Y, -Y, +Z, -Z)
};

struct CameraDesc {
    Float3 position{0.0f};
    Float3 target{0.0f, 0.0f, -1.0f};
    Float3 up{0.0f, 1.0f, 0.0f};
    float fovY = 1.0f;
    float nearPlane = 0.1f;
    float farPlane = 500.0f;
    // Sub-pixel offset (pixels, x right, y down, |x|, |y| <= 1) of every projected point: temporal
    // anti-aliasing's per-frame jitter. The module's own G-buffer pass and its reconstruction of world
    // positions both apply it; a host G-buffer must be rendered with viewProjection().
    Float2 jitter{0.0f, 0.0f};
};
static_assert(sizeof(CameraDesc) == 56 && offsetof(CameraDesc, fovY) == 36 &&
              offsetof(CameraDesc, jitter) == 48);

// One image the host hands over (setTargets): the image, a 2D view of its first mip and layer, and what the
// image was created with (VkImageCreateInfo's format, extent and usage), so that setTargets can check them.
struct HostImage {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{0, 0};
    VkImageUsageFlags usage = 0;
};

// G-buffer images the host renders itself, with Module::viewProjection(). Required (setTargets refuses
// anything else with one line naming the target and what is wrong; docs/integration.md has the table):
//   depth   D32_SFLOAT, SAMPLED usage, reversed Z (cleared to 0, compare GREATER: 1 at the near plane,
//           0 at the far plane and the sky)
//   normal  R16G16B16A16_SFLOAT, SAMPLED (world-space unit normal in xyz)
//   albedo  R8G8B8A8_UNORM, SAMPLED (linear)
//   output  STORAGE; R8G8B8A8_UNORM (tone-mapped sRGB values) or, in HDR mode, R16G16B16A16_SFLOAT
//           (linear radiance, exposure not applied)
//   material optional: R8G8_UNORM, SAMPLED (r perceptual roughness, g metalness: glTF's metallicRoughness
//           factors or texels). Given, the evaluation shades with GGX (Filament / glTF conventions);
//           absent, with Lambert + Blinn-Phong. Same layout and visibility rules as the G-buffer below.
// The normal's w says whether the pixel receives shadows: >= 0 (e.g. 1) yes, ML_NOT_A_RECEIVER (-1) no
// (lit unshadowed: Module::setInstanceShadowReceiving).
// Every extent at least width x height. Depth, normal and albedo in SHADER_READ_ONLY_OPTIMAL when the
// command buffer reaches record()'s commands, their writes made visible to COMPUTE_SHADER sampled reads;
// the output in GENERAL (its old contents are overwritten). record() leaves the output written by a
// compute shader and made visible to copy, fragment and compute reads only: a host that reads it otherwise
// (e.g. presents it) adds its own barrier from COMPUTE_SHADER / SHADER_STORAGE_WRITE.
struct HostTargets {
    uint32_t width = 0, height = 0;
    HostImage depth, normal, albedo, output;
    HostImage material; // optional (image and view VK_NULL_HANDLE: absent)
    // Set: the output mode these targets are for (setHdrOutput's, switched together with the targets);
    // unset: the module's current mode.
    std::optional<bool> hdrOutput;
};

// The module's lights and shadows in the host's own shaders (forward, transparent, decal passes): the
// GLSL include #include "manylights/manylights.glsl" (glslangValidator -I<prefix>/include) declares 12
// buffers in descriptor set ML_LIGHTS_SET at bindings ML_LIGHTS_BINDING + offset (offsets and types:
// manylights/host_bindings.h); the evaluation pass reads the same ones.
// Contract of Module::hostShaderBindings(), called after record():
//   - the handles, offsets and ranges are the frame record() just recorded (they change between frames:
//     the module grows and retires buffers), so the host writes its descriptor set each frame, e.g. one
//     set per frame in flight, rewritten before the draw or dispatch that reads it;
//   - the host's reads come after record()'s commands and before the next record()'s in queue order
//     (typically: in the same command buffer, after record()); record() leaves the buffers' GPU writes
//     visible to `stages` / `accesses` (fragment and compute shader reads); another stage (vertex, task,
//     mesh) adds its own barrier from COMPUTE_SHADER | FRAGMENT_SHADER, SHADER_STORAGE_WRITE. The next
//     record()'s frame-begin barrier orders its rewrites after those reads (vertex to compute stages);
//   - the handles stay valid while that frame is in flight (the slot contract: the module destroys a
//     retired buffer only once the host has waited for the frames that used it).
struct HostShaderBuffer {
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER; // or UNIFORM_BUFFER (offsets 0 and 7)
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize offset = 0, range = 0; // bytes; range > 0, within the buffer
};
struct HostShaderBindings {
    uint64_t frame = 0; // the frame they belong to (0 for the first record())
    uint32_t slot = 0;  // its frame-in-flight slot (frame % framesInFlight)
    std::array<HostShaderBuffer, ML_HOST_BINDING_COUNT> buffers{}; // index = offset of host_bindings.h
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 accesses = 0;
};
// The descriptor set layout bindings of the include at bindings first .. first + 11 for `stages` (one
// descriptor each), for the host's vkCreateDescriptorSetLayout.
std::array<VkDescriptorSetLayoutBinding, ML_HOST_BINDING_COUNT> hostShaderLayout(uint32_t first,
                                                                                 VkShaderStageFlags stages);

struct FrameStats {
    uint32_t lightsTotal = 0;
    uint32_t lightsVisible = 0;
    uint32_t clusters = 0;         // clusters in the grid (tiles x slices)
    uint32_t clustersOccupied = 0; // clusters holding at least one pixel
    double clusterLightsMean = 0;  // over occupied clusters
    uint32_t clusterLightsMax = 0;
    uint32_t clusterOverflowCount = 0;
    uint32_t poolEntries = 0; // light-list entries used (capacity in poolCapacity)
    uint32_t poolCapacity = 0;
    uint64_t surfacePixels = 0;
    double lightsPerPixelEvaluatedMean = 0; // over pixels with geometry
    double lightsPerPixelReachingMean = 0;
    VsmStats vsm;       // virtual shadow maps (zero when disabled)
    MemoryUsage memory; // the module's live buffer and image bytes per memory kind when collected
};

struct FrameReport {
    uint64_t frame = 0;
    PassTimes times;
    FrameStats stats;
};

// Validation a host (or a command line) can run before handing values over (validateLight:
// manylights/lights.h); setCamera calls it. validateCamera: a one-line reason ("camera: ...") when a camera
// cannot give a picture: a non-finite or huge (|x| > kMaxCameraCoordinate) position, target or up; target at
// the position; view direction parallel to up (the view matrix would be NaN); fovY outside (0, pi); not 0 <
// near < far.
constexpr float kMaxCameraCoordinate = 1.0e6f; // metres; float spacing there is 0.06 m
Result<void> validateCamera(const CameraDesc& camera);

using MeshId = uint32_t;
using InstanceId = uint32_t;
using LightId = uint32_t;

class Module {
  public:
    static Result<std::unique_ptr<Module>> create(const ModuleOptions& options);
    ~Module();

    Result<MeshId> addMesh(const MeshDesc& mesh);
    Result<InstanceId> addInstance(MeshId mesh, const Float4x4& transform, Float3 albedo, bool dynamic);
    // Dynamic instances only: a static instance's baked shadows would go stale, so moving one is refused.
    // A non-finite transform is refused.
    Result<void> setInstanceTransform(InstanceId instance, const Float4x4& transform);
    Result<LightId> addLight(const LightDesc& light);
    Result<void> setLight(LightId id, const LightDesc& light);
    // Removal. Ids carry a generation: a removed object's id is refused afterwards, also once its slot
    // holds a new object (lights and instances reuse slots; mesh ids are never reused). A mesh still
    // used by an instance is not removed.
    Result<void> removeLight(LightId id);
    Result<void> removeInstance(InstanceId id);
    Result<void> removeMesh(MeshId id);
    // An instance that casts no shadow (static bakes made afterwards and virtual shadow maps skip it).
    Result<void> setInstanceShadowCasting(InstanceId id, bool castsShadows);
    // An instance that receives no shadows (Bevy's NotShadowReceiver): its pixels get every light
    // unshadowed (it may still cast). The module's G-buffer carries the flag in the normal's w.
    Result<void> setInstanceShadowReceiving(InstanceId id, bool receivesShadows);
    // The instance's material for GGX shading (module-owned targets made with materials): perceptual
    // roughness in [0, 1] (clamped to 0.045 when shading) and metalness in [0, 1], glTF's factors.
    // Default 0.5 and 0. NaN or out of range is refused.
    Result<void> setInstanceMaterial(InstanceId id, float roughness, float metalness);
    // Linear radiance of the ambient term (times albedo) and of pixels without geometry.
    Result<void> setEnvironment(Float3 ambient, Float3 sky);
    // Refuses non-finite values, near/far/fov out of range, target == position and `up` parallel to the
    // view direction.
    Result<void> setCamera(const CameraDesc& camera);
    // The host's own camera matrices instead: `view` rigid (world to view, right-handed, looking down -Z);
    // `projection` a reversed-Z perspective into Vulkan clip space: depth 1 at the near plane and 0 at a
    // finite far plane, y down, off-centre allowed, e.g. glm::perspectiveRH_ZO(fovY, aspect, far, near)
    // with [1][1] negated. Standard Z, infinite far planes, shear and non-finite values are refused with
    // one line. `jitter` as in CameraDesc, applied by the module on top of `projection`.
    Result<void> setCameraMatrices(const Float4x4& view, const Float4x4& projection, Float2 jitter = {});
    // The jittered view-projection of the camera last set, for the targets' current size (a host that
    // renders its own G-buffer draws with it). Identity before the camera and targets are set.
    Float4x4 viewProjection() const;
    // Static shadows: attach or remove a light's bake; the PCF radius applies to every static lookup
    // (0 = one tap, 1 = 3x3, 2 = 5x5, up to 4 = 9x9). byLevel: MH, MMH, DAG-MH and CPVS bakes take the
    // kernel's taps on the coarsest hierarchy level whose texel is at most a quarter of the receiver's
    // pixel (hierarchical PCF: a distant receiver's taps move with the level's texels, not the finest);
    // SM bakes filter at the finest level.
    Result<void> setStaticShadow(LightId id, const StaticShadowDesc& shadow);
    void clearStaticShadow(LightId id);
    Result<void> setShadowFilter(uint32_t pcfRadius, bool byLevel = false);
    // Bakes and attaches the static shadows of every static, shadow-casting spot and point light (six
    // cube faces) from the module's own static, shadow-casting instances: dual depth maps rendered on this
    // device, encoded with `method` at `resolution`^2. `progress` (may be empty) gets (lights done, total).
    // Returns the number of lights baked. Waits for the device (a load-time operation).
    Result<uint32_t> bakeStaticShadows(StaticMethod method, uint32_t resolution,
                                       const std::function<void(uint32_t, uint32_t)>& progress = {});
    void setCulling(CullingMode mode);
    void setStatistics(bool enabled);
    void setView(DebugView view);
    Result<void> setExposure(float exposure); // scale on HDR before tone mapping (default 3)
    // Physical exposure for photometric lights (LightDesc::unit): setExposure(exposureFromEV100(ev100)),
    // e.g. ev100FromCamera(16, 1/125, 100) = 14.97 for a sunny day (manylights/lights.h).
    Result<void> setExposureEV100(float ev100);

    // Module-owned G-buffer and output at this size (record() then draws the G-buffer too). materials: the
    // evaluation shades with GGX from the instances' materials (the G-buffer always writes its material
    // target, R8G8_UNORM); false: Lambert + Blinn-Phong.
    Result<void> createTargets(uint32_t width, uint32_t height, bool materials = false);
    // Host-owned G-buffer (record() skips the G-buffer pass). Checked against HostTargets' table.
    Result<void> setTargets(const HostTargets& targets);
    // Lets go of the targets (the host's, or the module's own) so that the host may destroy its images:
    // record() refuses with one line until createTargets or setTargets gives new ones, instead of writing
    // descriptors of destroyed views. The module cannot tell a destroyed image from a live one, so the
    // order for host targets is: wait for the frames that used them (their fences), detachTargets() (or
    // destroy the module), then destroy the images. The module's own images are released once the frames
    // in flight that use them are done (the slot contract). Idempotent.
    void detachTargets();
    // LDR (tone-mapped RGBA8) or HDR (linear RGBA16F) output from the next record() on, without rebuilding
    // anything: module-owned targets hold both images (outputImage() follows the mode); host targets must
    // already have an output of the mode's format (else refused: pass HostTargets::hdrOutput to setTargets
    // with the new output instead). ModuleOptions::hdrOutput is the initial mode.
    Result<void> setHdrOutput(bool hdr);
    bool hdrOutput() const;

    // Records the frame's passes into the host's command buffer.
    Result<void> record(VkCommandBuffer cmd);
    // The buffers behind manylights/manylights.glsl for the frame the last record() recorded
    // (HostShaderBindings has the contract). Refused before the first record().
    Result<HostShaderBindings> hostShaderBindings() const;
    // Reports of frames whose results have arrived, oldest first; clears them. Call after the host
    // waited for the frames (e.g. vkQueueWaitIdle) to get the newest ones too: collect() reads every
    // slot without waiting.
    void collect();
    std::vector<FrameReport> takeReports();

    // Convenience for headless hosts: waits for the queue, copies the output image (module-owned
    // targets) to RGBA8 bytes, row-major, top row first. Refused until a frame was recorded into the
    // current targets (a new createTargets starts them empty).
    Result<void> readOutput(std::vector<uint8_t>& rgba);

    // The module-owned output (RGBA8, GENERAL layout after record()); for hosts that present or copy it.
    VkImage outputImage() const;
    // The device the module runs on (its own or the borrowed one), as plain handles.
    DeviceInfo deviceInfo() const;
    // Convenience for headless hosts on the module's own device: records the frame into a one-off command
    // buffer, submits it to the module's queue and waits for it.
    Result<void> submitFrame();
    TimingMode timingMode() const;
    uint32_t lightCount() const; // lights not removed

    // Internal state (not installed): the module's own tests and read-backs reach it through
    // internals(Module&); a host has no use for it.
    struct Impl;
    friend Impl& internals(Module& module);
    friend const Impl& internals(const Module& module);

  private:
    explicit Module(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

} // namespace ml
