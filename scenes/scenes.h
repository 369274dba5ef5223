// Scene sources: the procedural night city and glTF files. Every loader is deterministic for a seed and
// returns a Result whose error is one line naming the file and the reason; none of them throws or
// crashes on malformed input.
#pragma once
#include "scenes/scene.h"

namespace ml {

struct NightCityOptions {
    uint32_t seed = 1;
    uint32_t lights = 256; // total lights, headlights included; 1..4096
    uint32_t blocksX = 6, blocksZ = 6;
    uint32_t cars = 8; // each carries two headlight spotlights
    // Awnings, fences and foliage as thin closed boxes (2-3 cm) instead of open sheets: the seeds'
    // CLOSED CITY. Open sheets have a point depth interval, so a static tree keeps a node per texel
    // on them and grows with the texel count (docs/static-shadows.md, "Open and closed casters").
    bool closedCasters = false;
};

// A grid of streets and blocks: closed buildings of varied height and footprint, open geometry
// (awnings, fences, foliage cards), street lamps with downward spotlights, facade floodlights, coloured
// signs, and cars driving along the streets (dynamic instances with headlights).
Result<Scene> makeNightCity(const NightCityOptions& options);

struct IndoorOptions {
    uint32_t seed = 1;
    uint32_t lights = 600; // total, 1..4096: a tenth point lights, one headlight per cart, the rest spots
    uint32_t roomsX = 0, roomsZ = 0; // 0 x 0: about 12 spot fixtures per room, a near-square grid
    uint32_t carts = 4;              // dynamic casters driving loops through the doorways
};

// Rooms (12 m, 6 m high) joined by doorways: ceiling and wall spot fixtures, point lights, crates and
// pillars, carts with headlights (scenes/indoor.cpp). The virtual shadow maps' many-light level.
Result<Scene> makeIndoor(const IndoorOptions& options);

// How far a scene file is trusted (docs/reliability.md, "Untrusted files").
struct LoadOptions {
    // false: buffer and image URIs must resolve (realpath) to regular files inside the scene file's
    // folder. true: any readable file (a trusted scene that shares buffers with a sibling folder).
    bool allowOutsideSceneDir = false;
};

// Loads a .gltf or .glb file (tinygltf). Places `lights` spotlights procedurally (deterministic from
// `seed`) when the file has none. Marks each mesh closed or open.
Result<Scene> loadGltf(const std::string& path, uint32_t lights, uint32_t seed,
                       const LoadOptions& options = {});

// The blocks per side of "night-city-large" (6 for "night-city"): 40^2 blocks hold over 500,000
// triangles (ScenesNightCity.LargeCityHasTheSeedsScale), for benchmarks at the seeds' scale.
constexpr uint32_t kLargeCityBlocks = 40;

// "night-city", "night-city-large", their "-closed" variants, "indoor" or a path ending in .gltf / .glb.
Result<Scene> loadScene(const std::string& nameOrPath, uint32_t lights, uint32_t seed,
                        const LoadOptions& options = {});

// Every edge shared by exactly two triangles with opposite directions (after welding equal positions).
bool isClosedMesh(const Mesh& mesh);

// Moves cars along their paths to time `seconds` and carries attached lights with their instances.
void animateScene(Scene& scene, double seconds);

// Recomputes scene.boundsMin/boundsMax from the instances.
void updateBounds(Scene& scene);

} // namespace ml
