// Settings and per-frame statistics of the virtual shadow maps (ModuleOptions::vsm, FrameStats::vsm):
// plain API types of manylights/module.h.
#pragma once
#include <cstdint>
#include <string_view>

namespace ml {

// How pages are drawn: meshlets with task and mesh shaders (culling per meshlet and triangle), or the
// indexed vertex path (instance culling only; the reference and the fallback without mesh shaders).
// Auto: the vertex path on CPU devices (measured faster there: docs/vsm-page-draws.md, "Meshlets: page
// draws with task and mesh shaders") and on devices without mesh shaders, the mesh path otherwise. The
// choice is logged once at creation.
enum class VsmRaster : uint32_t { Auto, Mesh, Vertex };
// `--vsm-raster auto|mesh|vertex` of the commands: false for any other word.
inline bool parseVsmRaster(std::string_view word, VsmRaster& out) {
    if (word == "auto")
        out = VsmRaster::Auto;
    else if (word == "mesh")
        out = VsmRaster::Mesh;
    else if (word == "vertex")
        out = VsmRaster::Vertex;
    else
        return false;
    return true;
}

// VsmSettings::texelsPerPixel's accepted values: 1/4, 1/2, 1, 2, 4, 8 (exact powers of two; NaN fails).
inline bool validTexelsPerPixel(float t) {
    for (float p = 0.25f; p <= 8.0f; p *= 2.0f)
        if (t == p) return true;
    return false;
}

struct VsmSettings {
    bool enabled = true;
    // Virtual resolution of every map (spot, cube face, clip level): a power of two, 256..16384.
    uint32_t resolution = 4096;
    // Page side in texels: 32, 64 or 128 (measured on the night city, `bench vsm`:
    // docs/virtual-shadow-maps.md).
    uint32_t pageSize = 64;
    // Physical pages in the shared pool (4 B per texel: 4096 pages of 64^2 = 64 MiB).
    uint32_t poolPages = 4096;
    // Map slots at most (a spot light takes 1, a point light 6, a directional light clipLevels). The slot
    // pool starts at initialMaps and doubles when a light needs slots and none are free (page table 4 B per
    // entry: 21.8 KiB per map at 4096^2 / 64^2). 32768 holds 4096 point lights (24,576 cube faces).
    uint32_t maxMaps = 32768;
    uint32_t initialMaps = 512; // the slot pool's first size (tests start it small to exercise growth)
    // Directional lights: clip levels, and the half extent (metres) of level 0; level l covers 2^l that.
    uint32_t clipLevels = 10;
    float clipHalfExtent = 8.0f;
    float clipDepth = 600.0f; // metres of depth each clip level's box spans along the light
    // Shadow texels per pixel footprint, per axis, in the mip (and clip level) a lookup picks: 1 matches a
    // texel to the pixel (the seed's resolution matching); 2 picks one mip finer (4x the pages where it
    // applies), 0.5 one coarser. Finer texels flicker less under a moving camera (docs/accuracy.md
    // section 7). A power of two in 1/4..8; LightDesc::shadowTexelScale multiplies it per light.
    float texelsPerPixel = 1.0f;
    // Page marking per cluster-light pair against the cluster's bounds (a superset of the per-pixel marks)
    // in the clustered culling modes; false, or `none` / `tiled` culling: per receiver pixel. Off by
    // default: the pass is a fraction of the per-pixel one, but it marks and draws more pages, and their
    // draws can cost more than the marking saves (figures: docs/virtual-shadow-maps.md, "Bookkeeping
    // against the evaluation pass").
    bool clusterMarking = false;
    bool caching = true; // false: every marked page is redrawn every frame (the bench baseline)
    // Fallback reservations (a coarser page per lookup, drawn under pool pressure) cost marking time in
    // every frame: a third of vsm_mark on the night city. On demand, receivers reserve them only near
    // pressure: until a frame with active maps has completed, then for fallbackHoldFrames frames after a
    // completed frame that marked at least half the pool, had fallbacks or overflowed the request list. A
    // jump from under half the pool to past all of it within the frames in flight then loses shadows for
    // those frames (counted in fallbacks). false: every frame (GpuVsm.FallbacksReservedOnlyNearPressure
    // runs both).
    bool fallbacksOnDemand = true;
    uint32_t fallbackHoldFrames = 30;
    // Page draws clipped to one dirty page each (both raster paths). false: one draw per (caster, map, mip)
    // over the mip's whole virtual resolution, fragments outside dirty pages discarded (`bench vsm
    // --vsm-page-clip off`'s baseline; the pages come out the same).
    bool pageClip = true;
    // The static layer: every physical page gets a twin holding the static casters' depths alone (the
    // pool's memory doubles: 128 MiB at the defaults). A page invalidated only by a moving dynamic caster
    // (a cart) then redraws only the dynamic casters and takes the minimum with its twin,
    // not every caster again; static casters go to the twins only (one atomic per fragment either way).
    // Exact: the static casters' depths are unchanged, and the atomic minimum is order-independent.
    bool staticLayer = true;
    uint32_t maxDrawsPerMip = 16384;
    // The caster culling (timed as vsm_cull / vsm_expand) runs one workgroup per (caster group, map) pair
    // left by the pair test, in rows of this many workgroups: 1..65535 (Vulkan's guaranteed
    // maxComputeWorkGroupCount); tests set it small so that a frame's pairs span several rows.
    uint32_t cullRowWorkgroups = 65535;
    // Entries the request list holds (pages wanted in one frame: marked or reserved as fallbacks), rounded
    // up to a power of two >= 256; 4 B each, twice (the sort's ping-pong). Wanted pages past it get no
    // page that frame and are counted (VsmStats::requestOverflow). 2^18: 64x the default pool.
    uint32_t requestCapacity = 1u << 18;
    uint32_t kinds = 7;         // bit per light kind (1 spot, 2 point, 4 directional) that gets maps
    bool staticLights = true;   // lights that do not move get maps
    bool movingLights = true;   // moving lights (headlights) get maps
    uint32_t probeCapacity = 0; // lookup records the probe pass writes per frame (0: the pass is off)
    VsmRaster raster = VsmRaster::Auto;
    uint32_t maxMeshletsPerMip = 1u << 18; // meshlet-instance list entries per mip (12 B each)
    // Meshlet size limits used at Module::addMesh (meshoptimizer): at most the shaders' capacity, 64
    // vertices and 124 triangles; triangles a multiple of 4. Smaller values are
    // for `bench vsm --meshlet`.
    uint32_t meshletVertices = 64, meshletTriangles = 124;
};

// What the VSM passes did in one frame (FrameReport::stats.vsm; stats.json's "vsm" object).
struct VsmStats {
    uint32_t pagesMarked = 0, pagesAllocated = 0, pagesCached = 0, pagesRendered = 0, pagesInvalidated = 0,
             pagesEvicted = 0, fallbacks = 0, requests = 0, poolPages = 0, lightsWithPages = 0,
             mapsActive = 0, instancesDrawn = 0, instancesCulledHpb = 0, drawOverflow = 0,
             lightsWithoutSlot = 0, requestOverflow = 0;
    uint64_t poolBytes = 0, usedBytes = 0, virtualBytes = 0, atlasBytes = 0;
    // Mesh path only (zero on the vertex path, except trianglesRasterized: the indexed draws' triangles):
    // meshlets of (instance, map, mip) at each culling stage.
    bool meshPath = false;
    uint32_t meshletsTotal = 0, meshletsCulledFrustum = 0, meshletsCulledHpb = 0, meshletsAfterExpansion = 0,
             meshletOverflow = 0, taskCulledFrustum = 0, taskCulledCone = 0, taskCulledHpb = 0,
             meshletsAfterTask = 0, trianglesAfterTask = 0, trianglesRasterized = 0;
    // Page draws, both paths: fragment-shader invocations, and the texels of the pages rendered
    // (pagesRendered x pageSize^2): draws clipped to their page keep the first near the second (times
    // the casters' depth complexity); pageClipOverflow counts mesh-path meshlets drawn unclipped.
    uint64_t fragmentsDrawn = 0, dirtyPageTexels = 0;
    uint32_t pageClipOverflow = 0;
    // Why pages were rendered: pagesNew took a physical page this frame (new to the view, or evicted
    // before); the other pagesRendered - pagesNew had one that lost VALID. pagesInvalidatedCaster: of
    // pagesInvalidated, by moved casters' bounds only (not a moved light, a map made active, or caching
    // off). pagesRenderedDynamic: rendered from their static twin, dynamic casters only (staticLayer).
    uint32_t pagesNew = 0, pagesInvalidatedCaster = 0, pagesRenderedDynamic = 0;
    // The culling's caster groups (64 casters in the culling order): (group, map with a
    // dirty page) frustum tests, and those refused (the group's casters not read at all).
    // pairOverflow: pairs past the pair list's capacity (0 unless the device's storage-buffer
    // range cut it: their casters are not drawn, so shadows can be missing there).
    uint32_t groupTests = 0, groupsRefused = 0, pairOverflow = 0;
};

} // namespace ml
