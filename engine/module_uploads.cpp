// Scene changes reaching the GPU without a device-wide wait (issue 19): meshes into new buffers (the old
// ones retired until the frames in flight are done), static shadow words appended to one shared arena,
// shadow records per frame slot, rewritten in place only for the lights that changed. A slot's buffers
// are written only in beginFrame of that slot, when the host has waited for the slot's previous frame
// (the framesInFlight contract, engine/manylights.h), so no frame in flight reads what is written.
#include "engine/module_impl.h"
#include "shadows/static/static_method.h"
#include "shadows/static/static_visibility.h"

#include <algorithm>
#include <tuple>

namespace ml {

void Module::Impl::uploadMeshes() {
    const Device& d = *device;
    for (auto [b, data, bytes, usage, name] :
         {std::tuple{&vertexBuffer, (const void*)vertices.data(), vertices.size() * sizeof(MeshVertex),
                     kStorageBufferUsage, "vertices"},
          std::tuple{&indexBuffer, (const void*)indices.data(), indices.size() * 4,
                     VkBufferUsageFlags(VK_BUFFER_USAGE_INDEX_BUFFER_BIT), "indices"},
          std::tuple{&meshletBuffer, (const void*)meshlets.meshlets.data(),
                     meshlets.meshlets.size() * sizeof(gpu::GpuMeshlet), kStorageBufferUsage, "meshlets"},
          std::tuple{&meshletVertexBuffer, (const void*)meshlets.vertices.data(),
                     meshlets.vertices.size() * 4, kStorageBufferUsage, "meshlet_vertices"},
          std::tuple{&meshletTriangleBuffer, (const void*)meshlets.triangles.data(),
                     meshlets.triangles.size() * 4, kStorageBufferUsage, "meshlet_triangles"}}) {
        // Frames in flight may read the old buffer: a new one, the old one released later. Meshes are
        // load-time data, so the whole set is re-uploaded (once per frame with any addMesh).
        retire(*b);
        *b = createBuffer(d, std::max<size_t>(bytes, 16), usage, name);
        if (bytes) upload(*b, data, bytes);
    }
    meshesDirty = false;
}

void Module::Impl::touchShadow(uint32_t light) {
    if (shadowVersion.size() <= light) shadowVersion.resize(light + 1, 0);
    shadowVersion[light]++;
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
void Module::Impl::uploadShadowWords() {
    if (!wordsPending && staticWords.buffer) return;
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
        staticWords = createBuffer(d, words * 4, kStorageBufferUsage, "static_shadow_words");
        wordsUsed = 0;
        for (auto& faces : shadows)
            for (StaticShadow& s : faces) s.resident = false;
        recordsEpoch++;
    }
    for (auto& faces : shadows)
        for (StaticShadow& s : faces) {
            if (s.method == StaticMethod::None || s.resident) continue;
            // Words past the cursor: no frame in flight reads them.
            upload(staticWords, s.words.data(), s.words.size() * 4, size_t(wordsUsed) * 4);
            s.base = uint32_t(wordsUsed);
            s.resident = true;
            wordsUsed += s.words.size();
        }
    wordsPending = false;
}

// The slot's records: light i's six (spots: face 0 only) at 6 i, a face without a bake (or a light
// removed or not casting) a zero record. Only the lights whose version moved are rewritten, so a change
// of one light costs six records per slot.
void Module::Impl::writeShadowRecords(Slot& slot) {
    const Device& d = *device;
    const size_t n = lights.size();
    bool all = slot.recordsEpoch != recordsEpoch;
    all |= ensureBuffer(d, slot.shadowRecords, std::max<size_t>(n, 1) * 6 * sizeof(gpu::GpuShadowRecord),
                        kStorageBufferUsage, "shadow_records");
    if (shadowVersion.size() < n) shadowVersion.resize(n, 0);
    slot.shadowVersion.resize(n, ~0u); // lights new to the slot differ from any version
    auto* records = slot.shadowRecords.as<gpu::GpuShadowRecord>();
    for (uint32_t i = 0; i < n; ++i) {
        if (!all && slot.shadowVersion[i] == shadowVersion[i]) continue;
        const bool casts = lightAlive[i] && lights[i].castsShadows;
        for (uint32_t f = 0; f < 6; ++f) {
            const StaticShadow& s = shadows[i][f];
            records[i * 6 + f] = casts && s.method != StaticMethod::None
                                     ? makeShadowRecord(s.method, s.frustum, s.base,
                                                        staticResolution(s.method, s.words.data()), pcfRadius)
                                     : gpu::GpuShadowRecord{};
            records[i * 6 + f].bias.x = lights[i].shadowDepthBias; // setLight touches the light's version
            records[i * 6 + f].bias.y = lights[i].shadowNormalBias;
        }
        slot.shadowVersion[i] = shadowVersion[i];
        recordsWritten++;
    }
    slot.recordsEpoch = recordsEpoch;
}

} // namespace ml
