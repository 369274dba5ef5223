// The host side of a frame (Module::record): geometry and shadow uploads, the slot's collection and
// buffers (frame constants, visible lights with their static records and virtual maps, instances), and
// the FrameContext the passes read (engine/frame.h). Per-instance and per-light records are kept and
// remade only for what the host touched (touchInstance, touchShadow): a frame visits the changes, plus
// one pass over the lights' compact records for the frustum test.
#include "culling/culling_push.h"
#include "engine/module_impl.h"
#include "lights/lights.h"

#include <algorithm>
#include <cmath>

namespace ml {

EvaluateOutputs Module::Impl::evaluateOutputs(bool hdr) const {
    if (hdr) return EvaluateOutputs::HdrOnly;
    return ownTargets ? EvaluateOutputs::Both : EvaluateOutputs::ToneOnly;
}

bool Module::Impl::evaluatePbr() const {
    return ownTargets ? ownMaterials : host.material.view != VK_NULL_HANDLE;
}

// Every evaluation variant the targets can reach, so that no record() builds a pipeline: a build compiles
// shaders on the CPU, far longer than a frame's recording (the figures: docs/results/log.md). The
// module's own targets switch between LDR and HDR with setHdrOutput alone: both. A host's output has one
// format, and setHdrOutput refuses the other mode until setTargets brings a new output: the current mode.
Result<void> Module::Impl::preparePipelines() {
    for (bool hdr : {false, true})
        if (ownTargets || hdr == hdrOutput)
            ML_TRY(evaluate.prepare(*device, evaluateOutputs(hdr), evaluatePbr()));
    return {};
}

Result<uint32_t> Module::Impl::beginFrame() {
    // No device-wide wait here (engine/module_uploads.cpp): shared buffers are replaced and the old ones
    // retired; the slot's own buffers are rewritten in place, its previous frame being done. Out of
    // memory leaves the dirty flags set, so the next record() retries.
    releaseRetired(false);
    if (meshesDirty) ML_TRY(uploadMeshes());
    ML_TRY(uploadShadowWords());
    const Device& d = *device;
    const uint32_t slotIndex = uint32_t(frameIndex % slots.size());
    Slot& slot = slots[slotIndex];
    if (slot.pending) collectSlot(slotIndex); // the host waited for this slot's previous frame
    const size_t instanceSlots = std::max<size_t>(instances.size(), 1);
    auto grownInstances = ensureBuffer(d, slot.instances, instanceSlots * sizeof(GpuInstance),
                                       kStorageBufferUsage, "instances");
    if (!grownInstances) return fail(grownInstances.error());
    auto grownDraws = ensureBuffer(d, slot.draws, instanceSlots * sizeof(VkDrawIndexedIndirectCommand),
                                   VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, "draws");
    if (!grownDraws) return fail(grownDraws.error());
    if (grownInstances.value() || grownDraws.value()) slot.instanceVersion.clear(); // new buffers: all

    ML_TRY(writeShadowRecords(slot));

    const CullingMode mode = culling;
    const ClusterGrid grid =
        mode == CullingMode::None ? ClusterGrid{1, 1, 1} : clusterGrid(width, height, mode);
    if (mode != cullingMode || grid.count() != cull.grid.count()) {
        // The cluster buffers are shared by the frames in flight: the old ones are retired, not waited on.
        // All ten (the sorted fill's four too: ensureBuffer would destroy one that must grow while a
        // frame in flight still reads it; a host with 2 frames in flight caught it once record() stopped
        // draining the queue).
        for (Buffer* b :
             {&cull.bounds, &cull.receivers, &cull.ranges, &cull.pool, &cull.tileMasks, &cull.counts,
              &cull.hits, &cull.tileBits, &cull.tilePrefix, &cull.tileRanges, &cull.tileSlices})
            retire(*b);
        ML_TRY(cull.resize(d, grid, poolOverride));
        cullingMode = mode;
    }
    // Page marking per cluster reads the clusters' receiver bounds (cluster_bounds' receiver variant).
    cull.wantReceivers = vsm.enabled() && vsm.settings().clusterMarking &&
                         (mode == CullingMode::Clustered || mode == CullingMode::ClusteredBrute);
    if (cull.wantReceivers) ML_TRY(cull.ensureReceivers(d));
    if (view == DebugView::LightsEvaluated || view == DebugView::LightsReaching)
        ML_TRY(cull.prepareView(d, width, height));
    // Built by createTargets / setTargets for both output modes (preparePipelines): a no-op here unless
    // a test switched the evaluation's loop, in which case record() builds (and counts) it.
    ML_TRY(evaluate.prepare(d, evaluateOutputs(hdrOutput), evaluatePbr()));
    ML_TRY(writeFrame(slot, slotIndex, grid, mode));
    return slotIndex;
}

// The per-instance records, recomputed where a touched instance's inputs differ from those they were
// made from (meshes are append-only and their ranges never change, so the inputs are the InstanceData
// alone). Only the touched instances are visited; each change goes to every slot's pending list and to
// the VSM's.
void Module::Impl::updateInstanceCache() {
    const size_t n = instances.size();
    const size_t had = std::min(instanceFrom.size(), n);
    instanceFrom.resize(n);
    instanceRecords.resize(n);
    instanceDraws.resize(n);
    casters.resize(n);
    instanceVersion.resize(n);
    instancesVisited += touchedInstances.size();
    for (uint32_t i : touchedInstances) {
        instanceTouched[i] = 0;
        const InstanceData& id = instances[i];
        if (i < had && instanceVersion[i] != 0 && id.same(instanceFrom[i])) continue;
        instanceFrom[i] = id;
        instanceVersion[i] = ++instanceStamp;
        for (Slot& s : slots) s.pendingInstances.push_back(i);
        vsmChangedInstances.push_back(i);
        const MeshRange& r = meshes[id.mesh];
        instanceDraws[i] = {id.alive ? r.indexCount : 0u, 1, r.firstIndex, int32_t(r.firstVertex),
                            uint32_t(i)};
        GpuInstance& g = instanceRecords[i];
        g.model = id.transform;
        g.normalMatrix = glm::mat4(glm::transpose(glm::inverse(glm::mat3(id.transform))));
        g.albedo = glm::vec4(id.albedo, 1.0f);
        g.material = glm::vec4(id.roughness, id.metalness, id.receivesShadows ? 1.0f : ML_NOT_A_RECEIVER, 0);
        VsmInstance& v = casters[i];
        v.lo = glm::vec3(1e30f);
        v.hi = glm::vec3(-1e30f);
        for (uint32_t k = 0; k < 8; ++k) {
            glm::vec3 p((k & 1) ? r.hi.x : r.lo.x, (k & 2) ? r.hi.y : r.lo.y, (k & 4) ? r.hi.z : r.lo.z);
            glm::vec3 w = glm::vec3(id.transform * glm::vec4(p, 1.0f));
            v.lo = glm::min(v.lo, w);
            v.hi = glm::max(v.hi, w);
        }
        v.indexCount = r.indexCount;
        v.firstIndex = r.firstIndex;
        v.vertexOffset = r.firstVertex;
        v.firstMeshlet = r.firstMeshlet;
        v.meshletCount = r.meshletCount;
        v.closed = r.coneCull;
        v.dynamic = id.dynamic;
        v.castsShadows = id.alive && id.castsShadows;
        v.version = instanceVersion[i];
    }
    touchedInstances.clear();
}

// The per-light records, remade where the light's version moved since they were made (touchShadow).
void Module::Impl::updateLightRecords() {
    const size_t n = lights.size();
    lightRecords.resize(n);
    vsmLights.resize(n);
    lightVersion.resize(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
        LightRecord& r = lightRecords[i];
        if (r.version == lightVersion[i] && r.version != 0) continue;
        const GlmLight l(lights[i]);
        r.version = lightVersion[i];
        ++lightRecordsMade;
        r.gpu = toGpuLight(l, i);
        r.gpu.info.z = shadowRecordOf(i);
        r.sphere = lightBoundingSphere(l);
        VsmLight& v = vsmLights[i];
        v.kind = uint32_t(l.kind);
        v.position = l.position;
        v.direction = l.direction;
        v.range = l.range;
        v.outerAngle = l.outerAngle;
        v.moving = l.dynamic;
        v.castsShadows = lightAlive[i] && l.castsShadows;
        v.depthBias = l.shadowDepthBias;
        v.normalBias = l.shadowNormalBias;
        v.texelScaleLog2 = int32_t(std::lround(std::log2(l.shadowTexelScale))); // a power of two: exact
        const uint32_t faces = l.kind == LightKind::Point ? 6u : 1u;
        bool baked = true; // spot: face 0, point: six faces, directional: its orthographic bake
        for (uint32_t f = 0; f < faces; ++f) baked = baked && shadows[i][f].method != StaticMethod::None;
        // A moving light's bake (if any) no longer matches it: its maps take every caster.
        v.staticBake = baked && !l.dynamic;
        v.version = r.version;
    }
}

FrameContext Module::Impl::frameContext(VkCommandBuffer cmd, uint32_t slotIndex) const {
    const Slot& slot = slots[slotIndex];
    FrameContext f;
    f.device = device.get();
    f.cmd = cmd;
    f.culling = slot.mode;
    f.statistics = statistics;
    f.view = view;
    // The module's two evaluation images: full-size with its own targets, 1x1 stubs with the host's
    // (engine/module_targets.cpp); both transitioned each frame.
    f.own = {.slot = slotIndex,
             .counters = &slot.counters,
             .copies = stagedCopies,
             .hdr = &hdr,
             .output = &output};
    const VkImageView depth = ownTargets ? targets.depth.view : host.depth.view;
    const VkImageView normal = ownTargets ? targets.normal.view : host.normal.view;
    const VkImageView albedo = ownTargets ? targets.albedo.view : host.albedo.view;
    // The RGBA8 output the debug views overwrite (LDR only; in HDR mode no view runs).
    const VkImageView ldrOutput = ownTargets ? output.view : host.output.view;
    f.gbuffer = {.targets = ownTargets ? &targets : nullptr,
                 .frame = &slot.frame,
                 .vertices = &vertexBuffer,
                 .indices = &indexBuffer,
                 .instances = &slot.instances,
                 .draws = &slot.draws,
                 .drawCount = uint32_t(instances.size())};
    f.bounds = {&slot.frame, &slot.slices, depth, normal, &slot.counters};
    f.assign = {&slot.frame,    &slot.slices,     &slot.lights,  &slot.wide,
                slot.wideCount, slot.wideThreads, &slot.counters};
    f.vsm = {.slot = slotIndex,
             .frame = &slot.frame,
             .slices = &slot.slices,
             .lights = &slot.lights,
             .ranges = &cull.ranges,
             .pool = &cull.pool,
             .depth = depth,
             .normal = normal,
             .vertices = &vertexBuffer,
             .indices = &indexBuffer,
             .instances = &slot.instances,
             .meshlets = &meshletBuffer,
             .meshletVertices = &meshletVertexBuffer,
             .meshletTriangles = &meshletTriangleBuffer,
             .clusterReceivers = cull.wantReceivers ? &cull.receivers : nullptr,
             .tileMasks = &cull.tileMasks,
             .viewOutput = ldrOutput};
    EvaluateInputs& e = f.evaluate;
    e.shading = {&slot.frame, &slot.slices, &slot.lights, &cull.ranges, &cull.pool,
                 depth,       normal,       albedo,       width,        height};
    e.shading.material =
        ownTargets ? (ownMaterials ? targets.material.view : VK_NULL_HANDLE) : host.material.view;
    const bool vsmOn = vsm.enabled(); // without VSM any valid buffers fill its bindings (never read)
    e.shadows = {&staticWords,
                 &slot.shadowRecords,
                 vsmOn ? &vsm.constants(slotIndex) : &slot.frame,
                 vsmOn ? &vsm.maps(slotIndex) : &staticWords,
                 vsmOn ? &vsm.coverage(slotIndex) : &staticWords,
                 vsmOn ? &vsm.table() : &staticWords,
                 vsmOn ? &vsm.pagePool() : &staticWords};
    if (ownTargets) // LDR writes both (tests and tools read the HDR image); HDR: outputImage() is hdr
        e.targets = {hdrOutput ? EvaluateOutputs::HdrOnly : EvaluateOutputs::Both, hdr.view, output.view};
    else // the host's output takes what the mode writes; the other binding gets the stub
        e.targets = {hdrOutput ? EvaluateOutputs::HdrOnly : EvaluateOutputs::ToneOnly,
                     hdrOutput ? host.output.view : hdr.view, hdrOutput ? output.view : host.output.view};
    f.stats = {&slot.frame, &slot.slices, &slot.lights, &cull.ranges,  &cull.pool,
               depth,       width,        height,       &slot.counters};
    f.views = {&slot.frame, &slot.slices, &slot.lights, depth,
               ldrOutput,   width,        height,       view == DebugView::LightsReaching};
    return f;
}

void Module::Impl::endFrame(uint32_t slotIndex) {
    Slot& slot = slots[slotIndex];
    slot.pending = true;
    slot.statistics = statistics;
    lastSlot = slotIndex;
    captureHostBindings(slotIndex);
    frameIndex++;
}

// Frame constants, visible lights (with their static records and virtual maps), instances: everything
// the host side writes into the slot's buffers for one frame.
Result<void> Module::Impl::writeFrame(Slot& slot, uint32_t slotIndex, const ClusterGrid& grid,
                                      CullingMode mode) {
    const CameraDesc& c = camera;
    const CameraMatrices cm = frameCamera(); // reversed Z (engine/camera.h)
    gpu::FrameConstants fc{};
    fc.viewProj = cm.projection * cm.view;
    fc.invViewProj = glm::inverse(fc.viewProj);
    // w: the squared size of a pixel at unit distance (shadowFootprint2; filtering static shadows by level).
    const float pixelAngle = 2.0f / (std::abs(cm.projection[1][1]) * float(height));
    fc.cameraPosition = glm::vec4(toGlm(c.position), pixelAngle * pixelAngle);
    fc.size = glm::uvec4(width, height, grid.tilesX, grid.tilesY);
    fc.depth = glm::vec4(c.nearPlane, c.farPlane, c.nearPlane * c.farPlane, c.farPlane - c.nearPlane);
    fc.ambient = glm::vec4(ambient, exposure);
    fc.sky = glm::vec4(sky, 0.0f);
    fc.limits = glm::uvec4(cull.poolCapacity, grid.count(), 0, 0);

    // Visible lights: bounding sphere against the camera frustum. The records are built in host memory
    // (lastLights) and copied into the slot's buffer once: on a discrete GPU that buffer may be
    // write-combined device memory, which the host must not read back.
    updateLightRecords();
    auto planes = frustumPlanes(fc.viewProj);
    std::vector<gpu::GpuLight>& gl = lastLights;
    std::vector<uint32_t>& visibleIds = visibleLightIds;
    gl.clear();
    visibleIds.clear();
    for (uint32_t i = 0; i < lights.size(); ++i) {
        if (!lightAlive[i]) continue;
        const LightRecord& r = lightRecords[i];
        if (r.gpu.info.x != ML_LIGHT_DIRECTIONAL && !sphereInFrustum(planes, r.sphere)) continue;
        gl.push_back(r.gpu);
        visibleIds.push_back(i);
    }
    const uint32_t visible = uint32_t(visibleIds.size());

    // Instances, and what the virtual shadow maps need of them and of the lights.
    auto* inst = slot.instances.as<GpuInstance>();
    auto* draws = slot.draws.as<VkDrawIndexedIndirectCommand>();
    updateInstanceCache();
    // The slot rewrites the instances changed since its last frame, or all of them into new buffers.
    auto write = [&](uint32_t i) {
        if (slot.instanceVersion[i] == instanceVersion[i]) return; // listed twice, or already written
        slot.instanceVersion[i] = instanceVersion[i];
        draws[i] = instanceDraws[i];
        inst[i] = instanceRecords[i];
    };
    const bool allInstances = slot.instanceVersion.empty();
    slot.instanceVersion.resize(instances.size(), ~uint64_t(0));
    if (allInstances)
        for (uint32_t i = 0; i < instances.size(); ++i) write(i);
    else
        for (uint32_t i : slot.pendingInstances) write(i);
    slot.pendingInstances.clear();
    if (vsm.enabled()) {
        auto firstMap = vsm.prepare(*device, slotIndex, frameIndex, vsmLights, visibleIds, casters,
                                    vsmChangedInstances, {toGlm(c.position), c.fovY, height});
        if (!firstMap) return fail(firstMap.error());
        vsmChangedInstances.clear();
        for (uint32_t v = 0; v < visible; ++v) gl[v].info.y = firstMap.value()[v];
    } else {
        vsmChangedInstances.clear(); // no VSM (fixed at create): nobody reads the list
    }

    fc.cluster = glm::uvec4(grid.slices, ML_TILE_SIZE, visible, uint32_t(mode));
    // Wide lights (directional ones, huge footprints) get a thread per tile in light assignment.
    slot.wideCount = slot.wideThreads = 0;
    if (mode == CullingMode::Clustered) {
        auto* wide = slot.wide.as<gpu::WideLight>();
        for (uint32_t v = 0; v < visible; ++v)
            if (auto f = wideFootprint(gl[v], fc)) {
                gl[v].params.w = 1.0f;
                const uint32_t count = (f->tiles.z - f->tiles.x + 1) * (f->tiles.w - f->tiles.y + 1);
                wide[slot.wideCount++] = {f->tiles, f->depth, v, slot.wideThreads, count, 0};
                slot.wideThreads += count;
            }
    }
    if (!gl.empty()) upload(slot.lights, gl.data(), gl.size() * sizeof(gpu::GpuLight));
    upload(slot.frame, &fc, sizeof(fc));
    std::vector<float> sliceFar = sliceBoundaries(c.nearPlane, c.farPlane, grid.slices);
    upload(slot.slices, sliceFar.data(), sliceFar.size() * 4);
    slot.lightsTotal = uint32_t(lights.size());
    slot.lightsVisible = visible;
    slot.clusters = mode == CullingMode::None ? 0 : grid.count();
    slot.poolCapacity = cull.poolCapacity;
    slot.mode = mode;
    slot.frameNumber = frameIndex;
    lastConstants = fc;
    lastSliceFar = sliceFar;
    return {};
}

void Module::Impl::collectSlot(uint32_t index) {
    Slot& s = slots[index];
    FrameReport r;
    r.frame = s.frameNumber;
    if (!profiler.read(index, r.times)) return; // not complete yet: keep pending
    const auto& c = *s.counters.as<gpu::FrameCounters>();
    FrameStats& st = r.stats;
    st.lightsTotal = s.lightsTotal;
    st.lightsVisible = s.lightsVisible;
    st.clusters = s.clusters;
    st.clustersOccupied = c.occupiedClusters;
    st.clusterLightsMean = c.occupiedClusters ? double(c.clusterLightsSum) / c.occupiedClusters : 0.0;
    st.clusterLightsMax = c.maxClusterLights;
    st.clusterOverflowCount = c.overflowClusters;
    st.poolEntries = std::min(c.poolCursor, s.poolCapacity);
    st.poolCapacity = s.poolCapacity;
    st.surfacePixels = c.surfacePixels;
    st.vsm = vsm.readStats(index);
    vsm.observe(st.vsm, s.frameNumber); // pool pressure: fallback reservations of the frames to come
    st.memory = device->memoryUsage();
    if (s.statistics && c.surfacePixels) {
        st.lightsPerPixelEvaluatedMean = double(c.evaluatedSum) / double(c.surfacePixels);
        st.lightsPerPixelReachingMean = double(c.reachingSum) / double(c.surfacePixels);
    }
    reports.push_back(r);
    s.pending = false;
}

} // namespace ml
