// Scene changes reaching the GPU without a device-wide wait: new meshes' bytes appended to the mesh
// buffers (a buffer that outgrows its capacity is replaced, the old one retired until the frames in
// flight are done), static shadow words appended to one shared arena (both GPU-only: written by copies from
// staging buffers at the next frame's start), shadow records per frame slot, rewritten in place only for the
// lights that changed. A slot's buffers are written only in beginFrame of that slot, when the host has waited
// for the slot's previous frame (the framesInFlight contract, manylights/module.h), so no frame in flight
// reads what is written.
#include "engine/module_impl.h"
#include "shadows/static/static_method.h"
#include "shadows/static/static_visibility.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <tuple>

namespace ml {

Result<void> Module::Impl::stage(const std::vector<uint8_t>& bytes, std::vector<StagedCopy> copies,
                                 const char* name) {
    if (bytes.empty() || copies.empty()) return {};
    Buffer source;
    ML_TRY(createBuffer(*device, source, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, name,
                        MemoryRole::Staging));
    upload(source, bytes.data(), bytes.size());
    for (StagedCopy& c : copies) {
        c.source = source.buffer;
        stagedCopies.push_back(std::move(c));
    }
    staging.push_back(source);
    return {};
}

void Module::Impl::retireStaged() {
    for (Buffer& b : staging) retire(b);
    staging.clear();
    stagedCopies.clear();
    setup.fills.clear();
    setup.copies.clear();
    for (Buffer& b : setup.released) retire(b);
    setup.released.clear();
}

Result<void> Module::Impl::uploadMeshes() {
    // Meshes only grow (addMesh appends, removeMesh keeps the data), so only the bytes past what each
    // buffer holds are staged and copied at the frame's start, into the range past the old end that no
    // frame in flight reads (no instance of a new mesh was recorded before). A part past its buffer's
    // capacity gets a new GPU-only buffer of twice the capacity (or what it needs) holding the whole
    // array; frames in flight keep reading the old one, retired. So adding n meshes one frame at a time
    // stages each byte once, plus the whole array at each doubling. A failure destroys what was made
    // here and leaves meshesDirty set, so the next record() tries again.
    const Device& d = *device;
    struct Part {
        Buffer* buffer;
        const void* data;
        size_t size;
        VkBufferUsageFlags usage;
        const char* name;
    };
    const Part parts[] = {
        {&vertexBuffer, vertices.data(), vertices.size() * sizeof(MeshVertex), kStorageBufferUsage,
         "vertices"},
        {&indexBuffer, indices.data(), indices.size() * 4,
         VkBufferUsageFlags(VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT), "indices"},
        {&meshletBuffer, meshlets.meshlets.data(), meshlets.meshlets.size() * sizeof(gpu::GpuMeshlet),
         kStorageBufferUsage, "meshlets"},
        {&meshletVertexBuffer, meshlets.vertices.data(), meshlets.vertices.size() * 4, kStorageBufferUsage,
         "meshlet_vertices"},
        {&meshletTriangleBuffer, meshlets.triangles.data(), meshlets.triangles.size() * 4,
         kStorageBufferUsage, "meshlet_triangles"}};
    constexpr size_t kParts = std::size(parts);
    static_assert(kParts == std::tuple_size_v<decltype(meshBytesUploaded)>);
    Buffer made[kParts];                 // the parts that grow
    bool grows[kParts];                  // no buffer yet, or past its capacity
    size_t from[kParts], offset[kParts]; // first byte to send; its place in the staging bytes
    std::vector<uint8_t> bytes;          // every part's new bytes at a 16-byte aligned offset
    for (size_t i = 0; i < kParts; ++i) {
        grows[i] = !parts[i].buffer->buffer || parts[i].size > parts[i].buffer->size;
        from[i] = grows[i] ? 0 : std::min(meshBytesUploaded[i], parts[i].size);
        offset[i] = bytes.size();
        const size_t n = parts[i].size - from[i];
        bytes.resize(offset[i] + ((n + 15) & ~size_t(15)));
        if (n) std::memcpy(bytes.data() + offset[i], static_cast<const uint8_t*>(parts[i].data) + from[i], n);
    }
    auto staged = [&]() -> Result<void> {
        std::vector<StagedCopy> copies;
        for (size_t i = 0; i < kParts; ++i) {
            VkBuffer target = parts[i].buffer->buffer;
            if (grows[i]) {
                const size_t capacity =
                    std::max({parts[i].size, size_t(2 * parts[i].buffer->size), size_t(16)});
                ML_TRY(
                    createBuffer(d, made[i], capacity, parts[i].usage, parts[i].name, MemoryRole::GpuOnly));
                target = made[i].buffer;
            }
            if (parts[i].size > from[i])
                copies.push_back({VK_NULL_HANDLE, target, {{offset[i], from[i], parts[i].size - from[i]}}});
        }
        return stage(bytes, std::move(copies), "mesh_staging");
    }();
    if (!staged) {
        for (Buffer& b : made) destroyBuffer(d, b);
        return staged;
    }
    for (size_t i = 0; i < kParts; ++i) {
        if (made[i].buffer) {
            retire(*parts[i].buffer);
            *parts[i].buffer = made[i];
        }
        meshBytesStaged += parts[i].size - from[i];
        meshBytesUploaded[i] = parts[i].size;
    }
    meshesDirty = false;
    return {};
}

void Module::Impl::touchShadow(uint32_t light) {
    if (lightVersion.size() <= light) lightVersion.resize(light + 1, 0);
    lightVersion[light] = ++lightStamp; // the light's cached records (updateLightRecords) are remade
}

uint32_t Module::Impl::shadowRecordOf(uint32_t light) const {
    if (!lightAlive[light] || !lights[light].castsShadows) return ML_NO_SHADOW;
    for (const StaticShadow& s : shadows[light])
        if (s.method != StaticMethod::None) return light * 6; // point lights: + cube face in the shader
    return ML_NO_SHADOW;
}

// Appends the faces whose words are not resident. When they do not fit, the arena is rebuilt compactly
// into a new buffer of twice the live words (capped at the storage buffer range, which setStaticShadow
// keeps the live words under) and every slot rewrites all its records.
Result<void> Module::Impl::uploadShadowWords() {
    if (!wordsPending && staticWords.buffer) return {};
    const Device& d = *device;
    uint64_t pending = 0, live = 0;
    for (const auto& faces : shadows)
        for (const StaticShadow& s : faces) {
            if (s.method == StaticMethod::None) continue;
            live += s.words.size();
            if (!s.resident) pending += s.words.size();
        }
    const uint64_t capacity = staticWords.buffer ? staticWords.size / 4 : 0;
    if (!staticWords.buffer || wordsUsed + pending > capacity) {
        retire(staticWords);
        const uint64_t range = d.properties.limits.maxStorageBufferRange / 4;
        const uint64_t words = std::min<uint64_t>(std::max<uint64_t>(2 * live, 4096), range);
        wordsUsed = 0;
        for (auto& faces : shadows)
            for (StaticShadow& s : faces) s.resident = false;
        pending =
            live; // every face is uploaded again into the new arena, not only the ones that were pending
        recordsEpoch++;
        // State first: out of memory leaves no arena and every face pending, so the next frame retries.
        ML_TRY(createBuffer(d, staticWords, words * 4, kStorageBufferUsage, "static_shadow_words",
                            MemoryRole::GpuOnly));
    }
    // The pending faces' words, packed, staged and copied past the cursor at the frame's start (no frame
    // in flight reads there). Faces become resident only once the copy is queued.
    std::vector<uint8_t> bytes(size_t(pending) * 4);
    StagedCopy copy{VK_NULL_HANDLE, staticWords.buffer, {}};
    uint64_t at = 0;
    for (const auto& faces : shadows)
        for (const StaticShadow& s : faces) {
            if (s.method == StaticMethod::None || s.resident || s.words.empty()) continue;
            std::memcpy(bytes.data() + at * 4, s.words.data(), s.words.size() * 4);
            copy.regions.push_back({at * 4, (wordsUsed + at) * 4, s.words.size() * 4});
            at += s.words.size();
        }
    ML_TRY(stage(bytes, {copy}, "static_shadow_staging"));
    for (auto& faces : shadows)
        for (StaticShadow& s : faces) {
            if (s.method == StaticMethod::None || s.resident) continue;
            s.base = uint32_t(wordsUsed);
            s.resident = true;
            wordsUsed += s.words.size();
        }
    wordsPending = false;
    return {};
}

// The slot's records: light i's six (spots: face 0 only) at 6 i, a face without a bake (or a light
// removed or not casting) a zero record. Only the lights whose version moved are rewritten, so a change
// of one light costs six records per slot.
Result<void> Module::Impl::writeShadowRecords(Slot& slot) {
    const Device& d = *device;
    const size_t n = lights.size();
    bool all = slot.recordsEpoch != recordsEpoch;
    auto grown =
        ensureBuffer(d, slot.shadowRecords, std::max<size_t>(n, 1) * 6 * sizeof(gpu::GpuShadowRecord),
                     kStorageBufferUsage, "shadow_records");
    if (!grown) return fail(grown.error());
    all |= grown.value();
    if (lightVersion.size() < n) lightVersion.resize(n, 0);
    slot.shadowVersion.resize(n, ~uint64_t(0)); // lights new to the slot differ from any version
    auto* records = slot.shadowRecords.as<gpu::GpuShadowRecord>();
    for (uint32_t i = 0; i < n; ++i) {
        if (!all && slot.shadowVersion[i] == lightVersion[i]) continue;
        const bool casts = lightAlive[i] && lights[i].castsShadows;
        for (uint32_t f = 0; f < 6; ++f) {
            const StaticShadow& s = shadows[i][f];
            records[i * 6 + f] = casts && s.method != StaticMethod::None
                                     ? makeShadowRecord(s.method, s.frustum, s.base,
                                                        staticResolution(s.method, s.words.data()), pcfRadius)
                                     : gpu::GpuShadowRecord{};
            records[i * 6 + f].bias.x = lights[i].shadowDepthBias; // setLight touches the light's version
            records[i * 6 + f].bias.y = lights[i].shadowNormalBias;
            records[i * 6 + f].info.z = s.method != StaticMethod::None && filterByLevel ? 1u : 0u;
        }
        slot.shadowVersion[i] = lightVersion[i];
        recordsWritten++;
    }
    slot.recordsEpoch = recordsEpoch;
    return {};
}

} // namespace ml
