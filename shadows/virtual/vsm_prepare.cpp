// The CPU part of a virtual shadow map frame (VirtualShadowMaps::prepare), in named steps: the host's
// changed instances noted, which lights need maps, their map slots, the maps' matrices, coverage and
// stale bits, the active maps, the allocation order, and the slot's uploads. The GPU passes that read
// them are recorded in vsm_passes.cpp. Invariant: a frame costs the changes (moved instances, changed
// lights: stamps, not field compares) and passes over compact per-light or per-map arrays, never a pass
// over every instance, so that the CPU frame stays within its 1 ms budget at thousands of lights and
// instances (`manylights bench cpu`; figures in docs/architecture.md, "Timing and profiling").
#include "shadows/virtual/vsm.h"

#include "shadows/virtual/vsm_math.h"

#include <algorithm>
#include <chrono>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace ml {

namespace {

// Sets `count` consecutive bits from `first`: whole words where the run covers them.
void setBitRun(std::vector<uint32_t>& bits, uint32_t first, uint32_t count) {
    while (count > 0) {
        const uint32_t shift = first & 31u, n = std::min(32u - shift, count);
        bits[first >> 5] |= (n == 32u ? ~0u : ((1u << n) - 1u)) << shift;
        first += n;
        count -= n;
    }
}

// Sets the bit of every entry (all mips) of `map` whose pages overlap `rect` (mip-0 pages, inclusive),
// `offset` bits into `bits` (the stale bits' second region);
// a row's entries are consecutive (vsmEntry), so each row is one run.
void setRectBits(std::vector<uint32_t>& bits, uint32_t map, glm::uvec4 rect, uint32_t s0, uint32_t mips,
                 uint32_t entriesPerMap, uint32_t offset) {
    if (rect.x > rect.z || rect.y > rect.w) return;
    for (uint32_t m = 0; m < mips; ++m)
        for (uint32_t y = rect.y >> m; y <= (rect.w >> m); ++y)
            setBitRun(bits, offset + gpu::vsmEntry(entriesPerMap, s0, map, m, rect.x >> m, y),
                      (rect.z >> m) - (rect.x >> m) + 1u);
}

// Writes elements [0, n) of `data` into the mapped buffer where they differ from `mirror` (what the buffer
// holds), in runs of consecutive changed elements, and updates the mirror.
template <class T> void uploadChanged(Buffer& buffer, const T* data, size_t n, std::vector<T>& mirror) {
    if (mirror.size() < n) { // new or grown: all of it (n > 0 here)
        upload(buffer, data, n * sizeof(T));
        mirror.assign(data, data + n);
        return;
    }
    for (size_t i = 0; i < n;) {
        if (std::memcmp(&mirror[i], &data[i], sizeof(T)) == 0) {
            ++i;
            continue;
        }
        size_t end = i + 1;
        while (end < n && std::memcmp(&mirror[end], &data[end], sizeof(T)) != 0) ++end;
        upload(buffer, data + i, (end - i) * sizeof(T), i * sizeof(T));
        std::memcpy(mirror.data() + i, data + i, (end - i) * sizeof(T));
        i = end;
    }
}

// uploadChanged for the listed elements only (sorted, unique): the others are known to equal the mirror.
template <class T>
void uploadChangedAt(Buffer& buffer, const T* data, const std::vector<uint32_t>& at, std::vector<T>& mirror) {
    for (size_t k = 0; k < at.size();) {
        const uint32_t i = at[k];
        if (std::memcmp(&mirror[i], &data[i], sizeof(T)) == 0) {
            ++k;
            continue;
        }
        size_t end = k + 1; // a run of consecutive changed elements: one write
        while (end < at.size() && at[end] == i + (end - k) &&
               std::memcmp(&mirror[at[end]], &data[at[end]], sizeof(T)) != 0)
            ++end;
        const size_t n = end - k;
        upload(buffer, data + i, n * sizeof(T), i * sizeof(T));
        std::memcpy(mirror.data() + i, data + i, n * sizeof(T));
        k = end;
    }
}

bool boxTouchesSphere(glm::vec3 lo, glm::vec3 hi, glm::vec3 c, float r) {
    glm::vec3 d = glm::max(glm::max(lo - c, c - hi), glm::vec3(0.0f));
    return glm::dot(d, d) <= r * r;
}

} // namespace

// A light with maps as the box tests see it: centre, 1.1 x range, module light id.
struct VsmSphere {
    glm::vec3 c;
    float r;
    uint32_t light;
    bool bakedOnly; // its maps hold dynamic casters only (ML_VSM_MAP_DYNAMIC_ONLY: VsmLight::staticBake)
    VsmCone cone;   // spot lights: around the map's frustum (vsmSpotCone); none for point lights
    bool operator==(const VsmSphere&) const = default;
};

static VsmSphere lightSphere(const VsmLight& l, uint32_t id) {
    return {l.position, 1.1f * l.range, id, l.staticBake, vsmSpotCone(l)};
}

// Lights (spheres) binned into a uniform x/z grid for box queries (markCoverageAndStale). Cells are
// twice the median radius, at most 64 x 64 over the lights' extent (a cheap build: 4,097 offsets); a sphere
// spanning more than 64 cells goes to `wide`, which every query visits.
struct VsmLightGrid {
    glm::vec2 origin{0.0f};
    float cell = 1.0f;
    int nx = 0, nz = 0;
    std::vector<uint32_t> start; // per cell + 1: offsets into items
    std::vector<uint32_t> items; // sphere indices
    std::vector<uint32_t> wide;
    std::vector<VsmSphere> spheres; // what it was built from

    static VsmLightGrid build(const std::vector<VsmSphere>& spheres) {
        VsmLightGrid g;
        if (spheres.empty()) return g;
        std::vector<float> radii;
        glm::vec2 lo(spheres[0].c.x, spheres[0].c.z), hi = lo;
        for (const VsmSphere& s : spheres) {
            radii.push_back(s.r);
            lo = glm::min(lo, glm::vec2(s.c.x, s.c.z));
            hi = glm::max(hi, glm::vec2(s.c.x, s.c.z));
        }
        std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
        const glm::vec2 extent = hi - lo;
        g.cell = std::max({2.0f * radii[radii.size() / 2], extent.x / 64.0f, extent.y / 64.0f, 1e-3f});
        g.origin = lo;
        g.nx = std::min(int(extent.x / g.cell) + 1, 64);
        g.nz = std::min(int(extent.y / g.cell) + 1, 64);
        auto span = [&](const VsmSphere& s, int& x0, int& x1, int& z0, int& z1) {
            x0 = g.clampX((s.c.x - s.r - g.origin.x) / g.cell),
            x1 = g.clampX((s.c.x + s.r - g.origin.x) / g.cell);
            z0 = g.clampZ((s.c.z - s.r - g.origin.y) / g.cell),
            z1 = g.clampZ((s.c.z + s.r - g.origin.y) / g.cell);
        };
        g.start.assign(size_t(g.nx) * g.nz + 1, 0);
        for (int pass = 0; pass < 2; ++pass) {
            std::vector<uint32_t> cursor;
            if (pass == 1) {
                for (size_t c = 1; c < g.start.size(); ++c) g.start[c] += g.start[c - 1];
                g.items.resize(g.start.back());
                cursor.assign(g.start.begin(), g.start.end() - 1);
            }
            for (uint32_t k = 0; k < spheres.size(); ++k) {
                int x0, x1, z0, z1;
                span(spheres[k], x0, x1, z0, z1);
                if ((x1 - x0 + 1) * (z1 - z0 + 1) > 64) {
                    if (pass == 0) g.wide.push_back(k);
                    continue;
                }
                for (int z = z0; z <= z1; ++z)
                    for (int x = x0; x <= x1; ++x) {
                        const size_t c = size_t(z) * g.nx + x;
                        if (pass == 0)
                            ++g.start[c + 1];
                        else
                            g.items[cursor[c]++] = k;
                    }
            }
        }
        g.spheres = spheres;
        return g;
    }
    // In float first: a huge or infinite bound (or NaN, taken as the far edge) stays inside the grid.
    static int clampCell(float v, int n) {
        const float c = std::floor(v);
        return !(c > 0.0f) ? (c <= 0.0f ? 0 : n - 1) : c >= float(n - 1) ? n - 1 : int(c);
    }
    int clampX(float v) const { return clampCell(v, nx); }
    int clampZ(float v) const { return clampCell(v, nz); }
    // Every sphere that may touch the box [lo, hi] (some twice: callers stamp).
    template <class F> void forEach(glm::vec3 lo, glm::vec3 hi, F&& f) const {
        for (uint32_t k : wide) f(k);
        if (nx == 0) return;
        const int x0 = clampX((lo.x - origin.x) / cell), x1 = clampX((hi.x - origin.x) / cell);
        const int z0 = clampZ((lo.z - origin.y) / cell), z1 = clampZ((hi.z - origin.y) / cell);
        for (int z = z0; z <= z1; ++z)
            for (int x = x0; x <= x1; ++x) {
                const size_t c = size_t(z) * nx + x;
                for (uint32_t i = start[c]; i < start[c + 1]; ++i) f(items[i]);
            }
    }
};

Result<std::vector<uint32_t>> VirtualShadowMaps::prepare(const Device& device, uint32_t slotIndex,
                                                         uint64_t frame, std::span<const VsmLight> lights,
                                                         std::span<const uint32_t> visible,
                                                         std::span<const VsmInstance> instances,
                                                         std::span<const uint32_t> changed,
                                                         const VsmCamera& camera) {
    if (!settings_.enabled) return std::vector<uint32_t>(visible.size(), ML_VSM_NO_MAP);
    const auto start = std::chrono::steady_clock::now();
    Slot& slot = slots_[slotIndex];
    if (lightState_.size() < lights.size()) lightState_.resize(lights.size());
    slot.lightsWithPages = slot.lightsWithoutSlot = 0;
    noteChanges(instances, changed);
    const std::vector<uint8_t> needs = lightsNeedingMaps(lights, visible, instances);
    ML_TRY(assignMapSlots(device, slot, lights, needs));
    buildFrameMaps(slot, lights, camera);
    markCoverageAndStale(slot, lights, instances, changed);
    std::vector<uint32_t> firstMap = activateMaps(slot, visible, needs);
    buildAllocationOrder(slot);
    ML_TRY(uploadSlot(device, slot, frame, instances, camera));
    lastPrepareMs_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return firstMap;
}

void VirtualShadowMaps::noteChanges(std::span<const VsmInstance> instances,
                                    std::span<const uint32_t> changed) {
    for (Slot& s : slots_) s.pendingCasters.insert(s.pendingCasters.end(), changed.begin(), changed.end());
    auto casts = [&](uint32_t i) { return uint8_t(instances[i].dynamic && instances[i].castsShadows); };
    bool rebuild = dynamicCaster_.size() != instances.size();
    if (rebuild) {
        dynamicCaster_.resize(instances.size());
        for (uint32_t i = 0; i < instances.size(); ++i) dynamicCaster_[i] = casts(i);
    } else {
        for (uint32_t i : changed) {
            if (dynamicCaster_[i] == casts(i)) continue;
            dynamicCaster_[i] = casts(i);
            rebuild = true;
        }
    }
    if (!rebuild) return;
    dynamicCasters_.clear(); // in index order, as a pass over the instances would list them
    for (uint32_t i = 0; i < dynamicCaster_.size(); ++i)
        if (dynamicCaster_[i]) dynamicCasters_.push_back(i);
    buildCasterOrder(instances);
}

void VirtualShadowMaps::buildCasterOrder(std::span<const VsmInstance> instances) {
    // The culling's workgroups take 64 consecutive casters of this order, and a workgroup whose casters'
    // joint box lies outside a map's frustum stops after one test (vsm_groups.comp). So neighbours in
    // space should be neighbours here: static casters in Morton order of their box centres (30 bits over
    // the scene's centres), then the dynamic ones (they move away from their neighbours: kept apart, they
    // widen only their own groups), then those casting no shadow. Built when instances are added or the
    // dynamic set changes, not per frame; any permutation is correct, only the culling rate depends on it.
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const VsmInstance& in : instances) {
        lo = glm::min(lo, (in.lo + in.hi) * 0.5f);
        hi = glm::max(hi, (in.lo + in.hi) * 0.5f);
    }
    auto spread = [](uint32_t v) { // 10 bits -> every third bit of 30
        uint64_t x = v & 0x3FFu;
        x = (x | (x << 16)) & 0x030000FFull;
        x = (x | (x << 8)) & 0x0300F00Full;
        x = (x | (x << 4)) & 0x030C30C3ull;
        x = (x | (x << 2)) & 0x09249249ull;
        return x;
    };
    std::vector<uint64_t> keys(instances.size());
    for (uint32_t i = 0; i < instances.size(); ++i) {
        const VsmInstance& in = instances[i];
        const glm::vec3 extent = glm::max(hi - lo, glm::vec3(1e-6f));
        const glm::vec3 t = glm::clamp(((in.lo + in.hi) * 0.5f - lo) / extent, 0.0f, 1.0f) * 1023.0f;
        const uint64_t morton =
            spread(uint32_t(t.x)) | spread(uint32_t(t.y)) << 1 | spread(uint32_t(t.z)) << 2;
        const uint64_t kind = !in.castsShadows ? 2u : in.dynamic ? 1u : 0u;
        keys[i] = kind << 62 | morton << 32 | i;
    }
    std::sort(keys.begin(), keys.end());
    casterOrder_.resize(instances.size());
    for (uint32_t i = 0; i < instances.size(); ++i) casterOrder_[i] = uint32_t(keys[i]);
    ++casterOrderStamp_;
}

std::vector<uint8_t> VirtualShadowMaps::lightsNeedingMaps(std::span<const VsmLight> lights,
                                                          std::span<const uint32_t> visible,
                                                          std::span<const VsmInstance> instances) const {
    // Which visible lights need maps this frame. A light with a static bake needs them only while a
    // dynamic caster is inside its range; moving lights and lights without a bake always do. Only the
    // dynamic casters are tested (kept by noteChanges, not lights x every instance).
    const std::vector<uint32_t>& dynamicCasters = dynamicCasters_;
    std::vector<uint8_t> needs(lights.size(), 0);
    for (uint32_t id : visible) {
        const VsmLight& l = lights[id];
        if (!l.castsShadows || !(settings_.kinds & (1u << l.kind))) continue;
        if (l.moving ? !settings_.movingLights : !settings_.staticLights) continue;
        bool need = !l.staticBake;
        for (size_t k = 0; k < dynamicCasters.size() && !need; ++k) {
            const VsmInstance& in = instances[dynamicCasters[k]];
            need = l.kind == ML_LIGHT_DIRECTIONAL || boxTouchesSphere(in.lo, in.hi, l.position, l.range);
        }
        needs[id] = need ? 1 : 0;
    }
    return needs;
}

Result<void> VirtualShadowMaps::assignMapSlots(const Device& device, Slot& slot,
                                               std::span<const VsmLight> lights,
                                               const std::vector<uint8_t>& needs) {
    // Slots: assigned on first need, kept while the light keeps its kind (its cached pages stay useful
    // when it comes back into view); a kind change frees them.
    for (uint32_t id = 0; id < lights.size(); ++id) {
        LightState& st = lightState_[id];
        const uint32_t count = lights[id].kind == ML_LIGHT_POINT         ? 6u
                               : lights[id].kind == ML_LIGHT_DIRECTIONAL ? settings_.clipLevels
                                                                         : 1u;
        if (st.firstMap != ML_VSM_NO_MAP && (st.kind != lights[id].kind || st.mapCount != count)) {
            for (uint32_t m = 0; m < st.mapCount; ++m) {
                maps_[st.firstMap + m].inUse = false;
                touchMap(st.firstMap + m);
                freeSlots_.push_back(st.firstMap + m);
            }
            std::sort(freeSlots_.rbegin(), freeSlots_.rend());
            st.firstMap = ML_VSM_NO_MAP;
            st.builtVersion = 0;
            spheresDirty_ = true;
        }
        if (needs[id] && st.firstMap == ML_VSM_NO_MAP) {
            auto first = allocateSlots(device, count);
            if (!first) return fail(first.error());
            st.firstMap = first.value();
            if (st.firstMap == ML_VSM_NO_MAP) {
                ++slot.lightsWithoutSlot;
                continue;
            }
            st.mapCount = count;
            st.kind = lights[id].kind;
            st.builtVersion = 0;
            spheresDirty_ = true;
            for (uint32_t m = 0; m < count; ++m) {
                maps_[st.firstMap + m] = VsmMapInfo{};
                maps_[st.firstMap + m].light = id;
                touchMap(st.firstMap + m);
            }
        }
    }
    return {};
}

void VirtualShadowMaps::buildFrameMaps(Slot& slot, std::span<const VsmLight> lights,
                                       const VsmCamera& camera) {
    // Matrices of every map in use; a map whose projection or caster set changed is stale as a whole.
    // The host copy equals the slot's buffers: only the maps with bits set are cleared.
    for (uint32_t m : slot.bitMaps) {
        const auto [first, last] = mapBitWords(m);
        std::fill(slot.host.coverage.begin() + first, slot.host.coverage.begin() + last, 0u);
        std::fill(slot.host.stale.begin() + first, slot.host.stale.begin() + last, 0u);
        std::fill(slot.host.stale.begin() + markWords_ + first, slot.host.stale.begin() + markWords_ + last,
                  0u);
    }
    // Then one pass over the maps: a map in use takes its built record (with INVALIDATE when it moved),
    // a free one zeros.
    movedMaps_.assign(mapsInUse_, 0);
    for (uint32_t id = 0; id < lights.size(); ++id) {
        LightState& st = lightState_[id];
        if (st.firstMap == ML_VSM_NO_MAP) continue;
        const VsmLight& l = lights[id];
        const bool local = l.kind != ML_LIGHT_DIRECTIONAL;
        if (local && l.version != 0 && st.builtVersion == l.version) continue; // its maps are as built
        for (uint32_t f = 0; f < st.mapCount; ++f) {
            bool moved = false;
            const VsmMapInfo& info = maps_[st.firstMap + f];
            // Clip levels follow the camera; spot and point maps only their light: an equal stamp is
            // the same light, else the fields are compared (a light set to what it was is the same).
            const bool kept =
                info.inUse && info.light == id && info.face == f && l.kind != ML_LIGHT_DIRECTIONAL;
            const bool same =
                kept && ((l.version != 0 && info.builtVersion == l.version) || info.builtFrom == l);
            if (same) {
                maps_[st.firstMap + f].builtVersion = l.version;
                continue;
            }
            buildMap(st.firstMap + f, l, f, camera, moved);
            maps_[st.firstMap + f].builtVersion = l.version;
            if (l.kind != ML_LIGHT_DIRECTIONAL) spheresDirty_ = true; // position, range or bake may differ
            if (moved) movedMaps_[st.firstMap + f] = 1;
        }
        if (local) st.builtVersion = l.version;
    }
    // The slot's copy is rewritten only where maps_ changed since (mapStamp_) or a per-frame INVALIDATE
    // flag of its last frame must go: not every map in use each frame.
    if (mapStamp_.size() < mapsInUse_) mapStamp_.resize(mapsInUse_, 0);
    slot.mapStamp.resize(mapsInUse_, ~uint64_t(0));
    for (uint32_t m : slot.flaggedMaps)
        if (m < mapsInUse_) slot.mapStamp[m] = ~uint64_t(0);
    slot.flaggedMaps.clear();
    slot.mapsWritten.clear();
    for (uint32_t m = 0; m < mapsInUse_; ++m) {
        if (slot.mapStamp[m] == mapStamp_[m] && !movedMaps_[m]) continue;
        slot.mapStamp[m] = mapStamp_[m];
        slot.mapsWritten.push_back(m);
        const gpu::GpuVsmMap& g = slot.host.maps[m] = maps_[m].inUse ? maps_[m].gpu : gpu::GpuVsmMap{};
        const uint32_t flags = ((g.info.y & ML_VSM_MAP_DYNAMIC_ONLY) ? 1u : 0u) | (maps_[m].inUse ? 2u : 0u);
        const glm::uvec4 key(g.info.x, g.light.y, g.light.z, flags);
        if (slot.mapKey.size() <= m) slot.mapKey.resize(size_t(m) + 1, glm::uvec4(0));
        if (slot.mapKey[m] != key) slot.mapKeysChanged = true;
        slot.mapKey[m] = key;
        if (movedMaps_[m]) {
            slot.host.maps[m].info.y |= ML_VSM_MAP_INVALIDATE;
            slot.flaggedMaps.push_back(m);
        }
    }
}

void VirtualShadowMaps::markCoverageAndStale(Slot& slot, std::span<const VsmLight> lights,
                                             std::span<const VsmInstance> instances,
                                             std::span<const uint32_t> changed) {
    // Coverage (maps of baked lights: pages under dynamic casters) and stale bits (pages under a moved,
    // added or removed caster's old or new bounds): a dynamic caster's in the first region, a static
    // one's in the second (from word markWords_), which also invalidates the pages' static twins. Only a few
    // boxes can set a bit: the dynamic casters' (coverage) and the old and new bounds of the instances that
    // changed (stale; 1 % of 10,000 moving: 200 boxes). Each is tested against the lights with maps in the
    // grid cells it overlaps (VsmLightGrid) and projected only into the maps of the lights it touches: the
    // cost is the changed boxes times the lights near them, plus the projections, not maps x instances.
    const bool firstFrame = lastInstances_.size() != instances.size();
    struct Box {
        glm::vec3 lo, hi;
        uint32_t instance;
        bool coverage;     // else stale
        bool staticCaster; // stale: the box is (or was) a static caster's, so the static twins change
    };
    // The lights with map slots, as spheres, in a uniform grid over x and z (cells twice the median
    // radius: a typical light touches at most 4 cells); a box tests only the lights listed in the cells
    // its x/z extent overlaps, each light once (a stamp per light). Lights past 64 cells, and directional
    // lights, take every box. A box entirely past 1.1 x a local light's range cannot shadow a point the
    // light reaches: along a texel's ray (and its PCF neighbours, a few texels wide) depth grows with
    // distance, and lookups happen only within the range (lightReachesPoint) plus a normal offset of
    // about a texel; 10 % covers both. Its bits would never be read.
    // The spheres are remade only when a slot or a light with maps changed (spheresDirty_).
    if (spheresDirty_ || !grid_) {
        std::vector<VsmSphere> local;
        directionalWithMaps_.clear();
        anyBakedMaps_ = false;
        for (uint32_t id = 0; id < lightState_.size() && id < lights.size(); ++id) {
            if (lightState_[id].firstMap == ML_VSM_NO_MAP) continue;
            const VsmLight& l = lights[id];
            anyBakedMaps_ = anyBakedMaps_ || l.staticBake;
            if (l.kind == ML_LIGHT_DIRECTIONAL) {
                directionalWithMaps_.push_back(id);
                continue;
            }
            local.push_back(lightSphere(l, id));
        }
        if (!grid_ || grid_->spheres != local)
            grid_ = std::make_shared<VsmLightGrid>(VsmLightGrid::build(local));
        spheresDirty_ = false;
    }
    const VsmLightGrid& grid = *grid_;
    const std::vector<VsmSphere>& local = grid.spheres;

    // Queries of the grid: a coverage box alone (only when some light with maps is baked: no other map
    // takes coverage), a changed instance's old and new bounds together (one walk over the union's
    // cells, each box tested on its own).
    std::vector<Box> boxes;
    std::vector<std::pair<uint32_t, uint32_t>> queries; // (first box, boxes)
    if (anyBakedMaps_)
        for (uint32_t i : dynamicCasters_) {
            queries.emplace_back(uint32_t(boxes.size()), 1u);
            boxes.push_back({instances[i].lo, instances[i].hi, i, true, false});
        }
    // Stale: the listed instances whose bounds or casting differ from what the maps saw (a repeat in the
    // list finds lastInstances_ already equal). A new instance count is a first frame: all stale.
    if (!firstFrame)
        for (uint32_t i : changed) {
            const VsmInstance& in = instances[i];
            VsmInstance& old = lastInstances_[i];
            if (old.lo == in.lo && old.hi == in.hi && old.castsShadows == in.castsShadows &&
                old.dynamic == in.dynamic)
                continue;
            // A caster that is static in either frame was (or will be) drawn into the static twins.
            const bool wasStatic = !old.dynamic || !in.dynamic;
            queries.emplace_back(uint32_t(boxes.size()), 2u);
            boxes.push_back({old.lo, old.hi, i, false, wasStatic});
            boxes.push_back({in.lo, in.hi, i, false, wasStatic});
            old = in;
        }
    std::vector<std::pair<uint32_t, uint32_t>> hits; // (light, box)
    std::vector<uint32_t> touched;                   // maps given a bit (uploadSlot)
    std::vector<uint32_t> stamp(local.size(), 0);
    slot.host.sphereTests = slot.host.projections = 0;
    // A box can set bits only in maps of its kind (the per-map test below): coverage boxes in the maps of
    // baked lights (dynamic casters only), stale boxes of static casters in the others. Lights of the
    // other kind are skipped before the sphere test.
    auto wanted = [&](const Box& box, bool bakedOnly) {
        return box.coverage ? bakedOnly : !(bakedOnly && box.staticCaster);
    };
    for (uint32_t q = 0; q < queries.size(); ++q) {
        const auto [first, count] = queries[q];
        glm::vec3 lo = boxes[first].lo, hi = boxes[first].hi;
        for (uint32_t b = first + 1; b < first + count; ++b) {
            lo = glm::min(lo, boxes[b].lo);
            hi = glm::max(hi, boxes[b].hi);
        }
        for (uint32_t id : directionalWithMaps_)
            for (uint32_t b = first; b < first + count; ++b)
                if (wanted(boxes[b], lights[id].staticBake)) hits.emplace_back(id, b);
        grid.forEach(lo, hi, [&](uint32_t k) {
            if (stamp[k] == q + 1) return;
            stamp[k] = q + 1;
            const VsmSphere& sp = local[k];
            for (uint32_t b = first; b < first + count; ++b) {
                if (!wanted(boxes[b], sp.bakedOnly)) continue;
                ++slot.host.sphereTests;
                const glm::vec3 d =
                    glm::max(glm::max(boxes[b].lo - sp.c, sp.c - boxes[b].hi), glm::vec3(0.0f));
                if (glm::dot(d, d) <= sp.r * sp.r &&
                    vsmBoxMayTouchCone(sp.cone, sp.c, boxes[b].lo, boxes[b].hi))
                    hits.emplace_back(sp.light, b);
            }
        });
    }
    std::sort(hits.begin(), hits.end());
    for (size_t h = 0; h < hits.size();) {
        const uint32_t k = hits[h].first;
        const LightState& st = lightState_[k];
        size_t end = h;
        while (end < hits.size() && hits[end].first == k) ++end;
        for (uint32_t m = st.firstMap; m < st.firstMap + st.mapCount; ++m) {
            if (!maps_[m].inUse) continue;
            const bool dynamicOnly = (slot.mapKey[m].w & 1u) != 0;
            for (size_t j = h; j < end; ++j) {
                const Box& box = boxes[hits[j].second];
                // Coverage: dynamic-only maps; stale: every map, dynamic-only ones for dynamic casters.
                if (box.coverage ? !dynamicOnly : (dynamicOnly && box.staticCaster)) continue;
                glm::uvec4 rect;
                ++slot.host.projections;
                if (!vsmProjectBox(slot.host.maps[m], box.lo, box.hi, s0_, rect)) continue;
                // Stale bits of static casters go to the second region (entries offset by its start).
                const uint32_t offset = !box.coverage && box.staticCaster ? uint32_t(markWords_) * 32u : 0u;
                setRectBits(box.coverage ? slot.host.coverage : slot.host.stale, m, rect, s0_, mips_,
                            entriesPerMap_, offset);
                touched.push_back(m);
            }
        }
        h = end;
    }
    if (firstFrame)
        for (uint32_t m = 0; m < mapsInUse_; ++m) {
            slot.host.maps[m].info.y |= ML_VSM_MAP_INVALIDATE;
            slot.flaggedMaps.push_back(m);
        }
    // Only the bounds and the casting flag of lastInstances_ are read: the changed entries (set above)
    // are enough.
    if (firstFrame) lastInstances_.assign(instances.begin(), instances.end());
    // The words to upload: this frame's maps and the slot's previous ones (now cleared).
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    std::swap(slot.bitMaps, touched);
    slot.bitUploads = std::move(touched);
    slot.bitUploads.insert(slot.bitUploads.end(), slot.bitMaps.begin(), slot.bitMaps.end());
}

std::vector<uint32_t> VirtualShadowMaps::activateMaps(Slot& slot, std::span<const uint32_t> visible,
                                                      const std::vector<uint8_t>& needs) {
    std::vector<uint32_t> firstMap(visible.size(), ML_VSM_NO_MAP);
    // Active maps: those of visible lights with maps (only they get marks, allocation, HPB and draws).
    // A map that was not active last frame missed the invalidations in between: stale as a whole.
    slot.host.active.clear();
    std::vector<uint8_t> active(maps_.size(), 0);
    for (size_t v = 0; v < visible.size(); ++v) {
        const LightState& st = lightState_[visible[v]];
        if (!needs[visible[v]] || st.firstMap == ML_VSM_NO_MAP) continue;
        firstMap[v] = st.firstMap;
        ++slot.lightsWithPages;
        for (uint32_t f = 0; f < st.mapCount; ++f) {
            const uint32_t m = st.firstMap + f;
            slot.host.active.push_back(m);
            active[m] = 1;
            if (!wasActive_[m]) {
                slot.host.maps[m].info.y |= ML_VSM_MAP_INVALIDATE;
                slot.flaggedMaps.push_back(m);
            }
        }
    }
    wasActive_ = active;
    slot.activeCount = uint32_t(slot.host.active.size());
    return firstMap;
}

void VirtualShadowMaps::buildAllocationOrder(Slot& slot) {
    // Allocation order (vsm_alloc_common.glsl): every light's coarsest level first (the coarsest mip of a
    // perspective map, the coarsest clip level of a directional light), then one level finer, and so on;
    // within a level, the maps in use in slot order, active or not. An inactive map has no marks, so its
    // ranks are only a gap; keeping them makes the order independent of which lights are in view, so a
    // moving camera does not rebuild and re-upload it (one run per map and mip) every frame. It depends
    // on the maps in use, their kind and their levels (slot.mapKey) and is kept while those stay.
    slot.orderChanged = !slot.orderBuilt || slot.mapKeysChanged || slot.orderMaps != mapsInUse_;
    if (!slot.orderChanged) return;
    slot.orderMaps = mapsInUse_;
    slot.orderBuilt = true;
    slot.mapKeysChanged = false;
    slot.host.runs.clear();
    uint32_t rank = 0;
    const uint32_t steps = std::max(mips_, settings_.clipLevels);
    for (uint32_t r = 0; r < steps; ++r)
        for (uint32_t m = 0; m < mapsInUse_; ++m) {
            const glm::uvec4& k = slot.mapKey[m];
            if (!(k.w & 2u)) continue; // a free slot
            const bool ortho = k.x == ML_VSM_ORTHOGRAPHIC;
            const uint32_t count = ortho ? k.z : mips_; // clip levels, or mips
            if (r >= count) continue;
            const uint32_t level = count - 1 - r;
            if (ortho && k.y != level) continue;
            const uint32_t mip = ortho ? 0u : level;
            const uint32_t n = (s0_ >> mip) * (s0_ >> mip);
            slot.host.runs.push_back(glm::uvec4(rank, m, mip, n));
            slot.host.rankBase[size_t(m) * mips_ + mip] = rank;
            rank += n;
        }
    slot.orderEntries = rank;
}

Result<void> VirtualShadowMaps::uploadSlot(const Device& device, Slot& slot, uint64_t frame,
                                           std::span<const VsmInstance> instances, const VsmCamera& camera) {
    slot.casterCount = uint32_t(instances.size());

    gpu::VsmConstants c{};
    c.page = glm::uvec4(settings_.pageSize, uint32_t(std::countr_zero(settings_.pageSize)), s0_, mips_);
    c.sizes = glm::uvec4(entriesPerMap_, slot.activeCount, settings_.poolPages, uint32_t(frame + 1));
    c.options = glm::uvec4(pcf_, settings_.caching ? 1u : 0u, settings_.resolution, uint32_t(markWords_));
    // The pixel footprint per metre, divided by the texels wanted per pixel: the mip (or clip level) a
    // lookup picks then has texels that much smaller than the pixel (VsmSettings::texelsPerPixel).
    c.camera = glm::vec4(
        2.0f * std::tan(camera.fovY * 0.5f) / float(std::max(camera.height, 1u)) / settings_.texelsPerPixel,
        settings_.pageClip ? 1.0f : 0.0f, reservesFallbacks(frame) ? 1.0f : 0.0f,
        // Without caching every page is redrawn whole each frame: no twin is kept or written.
        settings_.staticLayer && settings_.caching ? 1.0f : 0.0f);
    c.order =
        glm::uvec4(uint32_t(slot.host.runs.size()), slot.orderEntries, settings_.requestCapacity, hpbWords_);
    lastConstants_ = c;

    // Upload (this slot's previous frame has completed: the module waited for its fence).
    upload(slot.constants, &c, sizeof(c));
    // Maps: the others equal what this slot's buffer holds (neither was written since its last upload).
    if (slot.uploadedMaps.size() < mapsInUse_) {
        uploadChanged(slot.maps, slot.host.maps.data(), mapsInUse_, slot.uploadedMaps);
    } else {
        std::vector<uint32_t>& at = slot.mapsWritten;
        at.insert(at.end(), slot.flaggedMaps.begin(), slot.flaggedMaps.end());
        std::sort(at.begin(), at.end());
        at.erase(std::unique(at.begin(), at.end()), at.end());
        uploadChangedAt(slot.maps, slot.host.maps.data(), at, slot.uploadedMaps);
    }
    if (slot.bitsFull) { // new buffers: every word once
        upload(slot.coverage, slot.host.coverage.data(), slot.host.coverage.size() * 4);
        upload(slot.stale, slot.host.stale.data(), slot.host.stale.size() * 4); // both regions
        slot.bitsFull = false;
    } else {
        for (uint32_t m : slot.bitUploads) {
            const auto [first, last] = mapBitWords(m);
            upload(slot.coverage, slot.host.coverage.data() + first, (last - first) * 4, first * 4);
            upload(slot.stale, slot.host.stale.data() + first, (last - first) * 4, first * 4);
            const size_t second = markWords_ + first; // static casters' region
            upload(slot.stale, slot.host.stale.data() + second, (last - first) * 4, second * 4);
        }
    }
    // The active set and the allocation order change only when lights come into or out of view.
    uploadChanged(slot.active, slot.host.active.data(), slot.host.active.size(), slot.uploadedActive);
    // The order's arrays change only when buildAllocationOrder rebuilt them (or the slots grew).
    if (slot.orderChanged || slot.uploadedRankBase.size() != size_t(mapsInUse_) * mips_) {
        uploadChanged(slot.runs, slot.host.runs.data(), slot.host.runs.size(), slot.uploadedRuns);
        uploadChanged(slot.rankBase, slot.host.rankBase.data(), size_t(mapsInUse_) * mips_,
                      slot.uploadedRankBase);
    }
    // Casters, written where they differ from what this slot's buffer holds (its mirror): one pass, no
    // frame-sized temporary.
    auto grown = ensureBuffer(device, slot.casters, instances.size() * sizeof(gpu::GpuCaster),
                              kStorageBufferUsage, "vsm_casters");
    if (!grown) return fail(grown.error());
    const size_t groups = (instances.size() + ML_VSM_CULL_GROUP - 1) / ML_VSM_CULL_GROUP;
    if (auto g =
            ensureBuffer(device, slot.casterGroups, std::max<size_t>(groups, 1) * sizeof(gpu::GpuCasterGroup),
                         kStorageBufferUsage, "vsm_caster_groups", MemoryRole::GpuOnly);
        !g)
        return fail(g.error());
    // Pairs: at most every group with every active map (only active maps get marks, so only they get dirty
    // pages), within the storage-buffer range the shaders bind (past it: counted, VsmStats::pairOverflow).
    const size_t pairRange = device.properties.limits.maxStorageBufferRange / 8;
    slot.pairCapacity =
        uint32_t(std::clamp<size_t>(groups * slot.activeCount, 1, std::min<size_t>(pairRange, 1u << 31)));
    if (auto g = ensureBuffer(device, slot.cullPairs, size_t(slot.pairCapacity) * 8, kStorageBufferUsage,
                              "vsm_cull_pairs", MemoryRole::GpuOnly);
        !g)
        return fail(g.error());
    // The casters in culling order (buildCasterOrder): uploaded when it was rebuilt or the buffer is new.
    auto ordered = ensureBuffer(device, slot.casterOrder, std::max<size_t>(casterOrder_.size(), 1) * 4,
                                kStorageBufferUsage, "vsm_caster_order");
    if (!ordered) return fail(ordered.error());
    if (ordered.value() || slot.casterOrderStamp != casterOrderStamp_) {
        if (!casterOrder_.empty()) upload(slot.casterOrder, casterOrder_.data(), casterOrder_.size() * 4);
        slot.casterOrderStamp = casterOrderStamp_;
    }
    const bool whole = grown.value() || slot.uploadedCasters.size() < instances.size();
    if (whole) slot.uploadedCasters.assign(instances.size(), gpu::GpuCaster{});
    if (whole || slot.casterVersion.size() < instances.size()) slot.casterVersion.assign(instances.size(), 0);
    auto* mapped = slot.casters.as<gpu::GpuCaster>();
    slot.host.castersVisited = 0;
    auto writeCaster = [&](uint32_t i) {
        ++slot.host.castersVisited;
        const VsmInstance& in = instances[i];
        // Same stamp, same inputs: the mirror (and so the buffer) already holds this record.
        if (in.version != 0 && slot.casterVersion[i] == in.version) return;
        slot.casterVersion[i] = in.version;
        gpu::GpuCaster c;
        c.lo = glm::vec4(in.lo, 0.0f);
        c.hi = glm::vec4(in.hi, 0.0f);
        c.draw = glm::uvec4(in.castsShadows ? in.indexCount : 0u, in.firstIndex, in.vertexOffset,
                            in.dynamic ? 1u : 0u);
        c.meshlets = glm::uvec4(in.firstMeshlet, in.meshletCount, in.closed ? 1u : 0u, 0u);
        if (!whole && std::memcmp(&slot.uploadedCasters[i], &c, sizeof(c)) == 0) return;
        slot.uploadedCasters[i] = c;
        mapped[i] = c;
    };
    if (whole)
        for (uint32_t i = 0; i < instances.size(); ++i) writeCaster(i);
    else
        for (uint32_t i : slot.pendingCasters) writeCaster(i);
    slot.pendingCasters.clear();
    // This slot's previous frame completed (the module waited for its fence): its list's length picks
    // the allocation's recorded sequence (VsmPasses::oneWorkgroupOnly).
    slot.listBefore = slot.countersWritten ? slot.counters.as<gpu::VsmCounters>()->listCount : ~0u;
    slot.countersWritten = true;
    gpu::VsmCounters zero{};
    zero.dispatchY = zero.dispatchZ = 1;
    zero.listGroupsY = zero.listGroupsZ = 1;
    zero.cullGroupsX =
        (uint32_t(groups) + ML_VSM_CULL_GROUP - 1) / ML_VSM_CULL_GROUP; // vsm_pairs; y: vsm_assign
    zero.cullGroupsZ = 1;
    upload(slot.counters, &zero, sizeof(zero));
    if (settings_.probeCapacity) {
        uint32_t header[4] = {0, settings_.probeCapacity, 0, 0};
        upload(slot.probes, header, sizeof(header));
    }
    return {};
}

} // namespace ml
