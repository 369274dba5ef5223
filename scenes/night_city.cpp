// The procedural night city (makeNightCity).
//
// Layout (metres, +Y up, centred on the origin): blocksX x blocksZ blocks of 40 m separated by 12 m
// streets, with a street ring around the outside too, so every block can be driven around. The ground
// is one closed slab (top at y = 0); each block is a 0.15 m sidewalk slab. A block is either built up
// (a 1..3 x 1..3 grid of lots inside a 3 m sidewalk, one building per lot: a box, an L prism or a
// stepped tower, 6-45 m high, taller towards the centre) or a park (grass slab, trees, fences).
//
// Lights (exactly options.lights of them), per kind:
//   headlights  2 per car (8 cars by default; fewer cars when there are fewer than 16 lights), dynamic
//               spots attached to the moving cars;
//   moonlight   1 dim, bluish directional light (when at least one light is left after the cars);
//   the rest R: street lamps 45 % (spots down from 6 m poles at both curbs of every street), shop
//               windows 20 % (wide warm spots over shop fronts onto the sidewalk), facade floods 20 %
//               (spots from the sidewalk up onto walls), signs 15 % (narrow saturated spots by a board).
// The high street in front of the default camera (the middle east-west street, its first kFocusBlocks
// blocks: both curbs and the facades facing it) gets the first kFocusAll of the R lights and
// kFocusShare of those beyond (R = 239 at 256 lights: all; 1007 at 1024: 62 %; 4079 at 4096: 53 %),
// each kind in that proportion; the rest spread over the whole city. So the default view shows
// overlapping pools at every light count while the city does not grow: more lights fill the same
// streets and facades more densely. Within
// a set of segments (block sides for lamps, street-facing facades for the others) lights go
// round-robin over a seeded shuffle, evenly spaced along each segment. A lamp closer than 4 m to an
// existing pole on its curb hangs from that pole's line (no new pole).
//
// Determinism: everything comes from Pcg32 streams derived from the seed, one stream per subsystem,
// so the buildings of a seed are the same whatever the light count.
#include "scenes/mesh_utils.h"
#include "scenes/scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ml {
namespace {

using detail::Pcg32;

constexpr float kBlock = 40.0f;  // block side
constexpr float kStreet = 12.0f; // street width
constexpr float kPitch = kBlock + kStreet;
constexpr float kSidewalk = 3.0f; // lots start this far inside the block edge
constexpr float kCurb = 0.15f;    // sidewalk slab height
constexpr float kLane = 3.0f;     // car loop distance outside its block's edge
constexpr uint32_t kMaxLights = 4096;
constexpr uint32_t kFocusBlocks = 2; // high-street blocks (from the west end) in the default view
constexpr uint32_t kFocusAll = 240;  // up to this many lights (besides cars and moon) all on the high street
constexpr float kFocusShare = 0.5f;  // and this share of the lights beyond
const glm::vec3 kUp(0.0f, 1.0f, 0.0f);

// Shared meshes (indices into scene.meshes).
enum MeshId : uint32_t {
    kBoxMesh,
    kQuadMesh,
    kFenceMesh,
    kFoliageMesh,
    kCarMesh,
    kLMesh0,                     // 3 L variants
    kSteppedMesh0 = kLMesh0 + 3, // 3 stepped variants
    kMeshCount = kSteppedMesh0 + 3
};

// A vertical wall strip lights can be put against: base centre on the ground, outward normal.
struct Facade {
    glm::vec3 base;   // centre of the bottom edge (y = sidewalk top)
    glm::vec3 normal; // outward, horizontal, unit
    float width, height;
};

// A straight line of curb where lamps stand: start, unit direction along it, length, and the normal
// pointing into the street.
struct Curb {
    glm::vec3 start, along, street;
    float length;
};

// Object -> world for a mesh whose front is local +Z: local +Z becomes `normal` (horizontal), +Y up,
// scaled by (sx, sy, sz). Always right-handed, so winding is preserved.
glm::mat4 upright(glm::vec3 origin, glm::vec3 normal, float sx, float sy, float sz) {
    glm::vec3 x = glm::cross(kUp, normal);
    return detail::frameMatrix(origin, x * sx, kUp * sy, normal * sz);
}

glm::vec3 jitterColor(Pcg32& rng, glm::vec3 c, float amount) {
    return glm::clamp(c * rng.uniform(1.0f - amount, 1.0f + amount), glm::vec3(0.0f), glm::vec3(1.0f));
}

// Deterministic Fisher-Yates shuffle of 0..n-1.
std::vector<uint32_t> shuffled(uint32_t n, Pcg32& rng) {
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    for (uint32_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
    return order;
}

// Spreads `count` items over `segments` segments: in a shuffled order, each segment gets
// floor(count / segments) items and the first count % segments segments one more. Calls
// place(segment, t) with t in (0, 1) the item's position along its segment (evenly spaced, jittered).
template <class F> void spread(uint32_t count, uint32_t segments, Pcg32& rng, F&& place) {
    if (segments == 0) return;
    auto order = shuffled(segments, rng);
    for (uint32_t rank = 0; rank < segments; ++rank) {
        uint32_t n = count / segments + (rank < count % segments ? 1u : 0u);
        for (uint32_t j = 0; j < n; ++j) {
            float t = (float(j) + 0.5f + rng.uniform(-0.25f, 0.25f)) / float(n);
            place(order[rank], t);
        }
    }
}

// spread() over a subset of segments (their indices in `ids`).
template <class F> void spreadOver(uint32_t count, const std::vector<uint32_t>& ids, Pcg32& rng, F&& place) {
    spread(count, uint32_t(ids.size()), rng, [&](uint32_t s, float t) { place(ids[s], t); });
}

class CityBuilder {
  public:
    explicit CityBuilder(const NightCityOptions& o) : opt_(o) {
        width_ = float(o.blocksX) * kBlock + float(o.blocksX + 1) * kStreet;
        depth_ = float(o.blocksZ) * kBlock + float(o.blocksZ + 1) * kStreet;
        min_ = glm::vec3(-0.5f * width_, 0.0f, -0.5f * depth_);
    }

    Scene build() {
        scene_.name = "night-city";
        makeMeshes();
        Pcg32 layout(opt_.seed, 1);
        addInstance(kBoxMesh,
                    glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -1.0f, 0.0f)) *
                        glm::scale(glm::mat4(1.0f), glm::vec3(width_, 1.0f, depth_)),
                    glm::vec3(0.07f, 0.07f, 0.075f));
        uint32_t blocks = opt_.blocksX * opt_.blocksZ;
        for (uint32_t b = 0; b < blocks; ++b) addBlock(b, layout);

        // Light budget: see the overview.
        uint32_t cars = std::min(opt_.cars, opt_.lights / 2);
        uint32_t rest = opt_.lights - 2 * cars;
        uint32_t moon = rest > 0 ? 1u : 0u;
        rest -= moon;
        uint32_t lamps = (rest * 45 + 50) / 100;
        uint32_t shops = std::min(rest - lamps, (rest * 20 + 50) / 100);
        uint32_t floods = std::min(rest - lamps - shops, (rest * 20 + 50) / 100);
        uint32_t signs = rest - lamps - shops - floods;
        if (facades_.empty()) {
            // Only when no wall faces a street (cannot happen with the current lot layout, but the light
            // count must be exact regardless): floods and signs then stand at the curbs, facing inwards.
            for (const Curb& c : curbs_)
                facades_.push_back({c.start + c.along * (0.5f * c.length), -c.street, c.length, 10.0f});
        }
        findFocus();
        focusFraction_ = rest <= kFocusAll
                             ? 1.0f
                             : (float(kFocusAll) + kFocusShare * float(rest - kFocusAll)) / float(rest);
        addLamps(lamps);
        addFloods(floods);
        addSigns(signs);
        addShops(shops);
        if (moon) addMoon();
        addCars(cars);

        animateScene(scene_, 0.0); // places cars and headlights, computes bounds
        setCamera();
        return std::move(scene_);
    }

  private:
    void makeMeshes() {
        scene_.meshes.resize(kMeshCount);
        scene_.meshes[kBoxMesh] = detail::makeUnitBox();
        // Closed variant: the awning's frame is in metres (2 cm canvas), the fence's depth axis is
        // 1 m (2 cm boards), foliage is scaled 2.5-3.8x (1 cm -> 2.5-3.8 cm slabs).
        bool closed = opt_.closedCasters;
        scene_.meshes[kQuadMesh] = detail::makeUnitQuad(closed ? 0.02f : 0.0f);
        scene_.meshes[kFenceMesh] = detail::makeFence(10, closed ? 0.02f : 0.0f);
        scene_.meshes[kFoliageMesh] = detail::makeFoliageCards(closed ? 0.01f : 0.0f);
        // Car in metres (1.9 wide, 1.5 high, 4.5 long), front towards -Z: a body with a cabin set back.
        // Its transform stays rigid so attached headlights keep metric offsets.
        scene_.meshes[kCarMesh] = detail::makeSteppedBox({-0.95f, -2.25f, 0.95f, 2.25f}, 0.85f,
                                                         {-0.82f, -0.9f, 0.82f, 1.4f}, 1.5f, "car");
        const float notches[3][2] = {{0.5f, 0.5f}, {0.6f, 0.4f}, {0.4f, 0.6f}};
        const char* lNames[3] = {"building-l0", "building-l1", "building-l2"};
        for (int i = 0; i < 3; ++i)
            scene_.meshes[kLMesh0 + i] = detail::makeLPrism(notches[i][0], notches[i][1], lNames[i]);
        const glm::vec4 towers[3] = {
            {-0.3f, -0.3f, 0.3f, 0.3f}, {-0.35f, -0.2f, 0.25f, 0.38f}, {-0.25f, -0.4f, 0.42f, 0.2f}};
        const float podium[3] = {0.3f, 0.45f, 0.22f};
        const char* sNames[3] = {"building-stepped0", "building-stepped1", "building-stepped2"};
        for (int i = 0; i < 3; ++i)
            scene_.meshes[kSteppedMesh0 + i] =
                detail::makeSteppedBox({-0.5f, -0.5f, 0.5f, 0.5f}, podium[i], towers[i], 1.0f, sNames[i]);
    }

    uint32_t addInstance(uint32_t mesh, const glm::mat4& transform, glm::vec3 albedo, bool dynamic = false) {
        Instance inst;
        inst.mesh = mesh;
        inst.transform = transform;
        inst.albedo = albedo;
        inst.dynamic = dynamic;
        scene_.instances.push_back(inst);
        return uint32_t(scene_.instances.size() - 1);
    }

    glm::mat4 boxAt(glm::vec3 base, glm::vec3 size) const {
        return glm::translate(glm::mat4(1.0f), base) * glm::scale(glm::mat4(1.0f), size);
    }

    glm::vec3 blockMin(uint32_t b) const {
        uint32_t bx = b % opt_.blocksX, bz = b / opt_.blocksX;
        return min_ + glm::vec3(kStreet + float(bx) * kPitch, 0.0f, kStreet + float(bz) * kPitch);
    }

    void addTree(glm::vec3 ground, Pcg32& rng) {
        float h = rng.uniform(1.8f, 2.6f);
        addInstance(kBoxMesh, boxAt(ground, {0.3f, h, 0.3f}), jitterColor(rng, {0.25f, 0.16f, 0.09f}, 0.1f));
        float s = rng.uniform(2.5f, 3.8f);
        glm::mat4 m = glm::translate(glm::mat4(1.0f), ground + glm::vec3(0.0f, h - 0.4f, 0.0f)) *
                      glm::rotate(glm::mat4(1.0f), rng.uniform(0.0f, 1.57f), kUp) *
                      glm::scale(glm::mat4(1.0f), {s, s * 1.2f, s});
        addInstance(kFoliageMesh, m, jitterColor(rng, {0.1f, 0.26f, 0.08f}, 0.2f));
    }

    void addBlock(uint32_t b, Pcg32& rng) {
        glm::vec3 lo = blockMin(b);
        glm::vec3 centre = lo + glm::vec3(0.5f * kBlock, 0.0f, 0.5f * kBlock);
        addInstance(kBoxMesh, boxAt(centre, {kBlock, kCurb, kBlock}),
                    jitterColor(rng, {0.3f, 0.3f, 0.29f}, 0.05f));
        for (int side = 0; side < 4; ++side) {
            // Curb lines run counter-clockwise seen from above; `street` points out of the block.
            static const glm::vec3 starts[4] = {
                {0, 0, 0}, {kBlock, 0, 0}, {kBlock, 0, kBlock}, {0, 0, kBlock}};
            static const glm::vec3 alongs[4] = {{1, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
            static const glm::vec3 streets[4] = {{0, 0, -1}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}};
            glm::vec3 start = lo + starts[side] + alongs[side] * 2.0f - streets[side] * 0.6f;
            curbs_.push_back(
                {start + glm::vec3(0.0f, kCurb, 0.0f), alongs[side], streets[side], kBlock - 4.0f});
            // Street trees, 2.2 m in from the edge, at a third and two thirds of each side.
            for (float t : {0.3f, 0.7f})
                addTree(lo + starts[side] + alongs[side] * (kBlock * t) - streets[side] * 2.2f +
                            glm::vec3(0.0f, kCurb, 0.0f),
                        rng);
        }
        uint32_t blocks = opt_.blocksX * opt_.blocksZ;
        bool park = blocks >= 4 && b != 0 && rng.chance(0.12f);
        if (park)
            addPark(lo, rng);
        else
            addBuildings(lo, centre, rng);
    }

    void addPark(glm::vec3 lo, Pcg32& rng) {
        float inner = kBlock - 2.0f * kSidewalk;
        glm::vec3 centre = lo + glm::vec3(0.5f * kBlock, kCurb, 0.5f * kBlock);
        addInstance(kBoxMesh, boxAt(centre, {inner, 0.05f, inner}),
                    jitterColor(rng, {0.1f, 0.22f, 0.08f}, 0.1f));
        int trees = 10 + int(rng.below(8));
        for (int i = 0; i < trees; ++i)
            addTree(centre + glm::vec3(rng.uniform(-14.0f, 14.0f), 0.05f, rng.uniform(-14.0f, 14.0f)), rng);
        // Fence panels (4.25 m each) around the lawn, one left out in the middle of each side as a gate.
        const int panels = 8;
        float panel = inner / float(panels);
        for (int side = 0; side < 4; ++side) {
            static const glm::vec3 outward[4] = {{0, 0, -1}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}};
            glm::vec3 n = outward[side];
            glm::vec3 along = glm::cross(kUp, n);
            for (int p = 0; p < panels; ++p) {
                if (p == panels / 2) continue;
                glm::vec3 at =
                    centre + n * (0.5f * inner) + along * ((float(p) + 0.5f) * panel - 0.5f * inner);
                addInstance(kFenceMesh, upright(at, n, panel, 1.2f, 1.0f), glm::vec3(0.2f, 0.2f, 0.22f));
            }
        }
    }

    void addBuildings(glm::vec3 lo, glm::vec3 blockCentre, Pcg32& rng) {
        auto lotsAlong = [&] {
            float u = rng.uniform();
            return u < 0.15f ? 1 : (u < 0.7f ? 2 : 3);
        };
        int nx = lotsAlong(), nz = lotsAlong();
        const float gap = 2.0f, inner = kBlock - 2.0f * kSidewalk;
        float lotX = (inner - gap * float(nx - 1)) / float(nx),
              lotZ = (inner - gap * float(nz - 1)) / float(nz);
        // 1 at the city centre, 0 at the far corner: downtown is taller.
        float maxDist = 0.5f * glm::length(glm::vec2(width_, depth_));
        float central = 1.0f - glm::length(glm::vec2(blockCentre.x, blockCentre.z)) / maxDist;
        static const glm::vec3 palette[6] = {{0.45f, 0.45f, 0.43f}, {0.6f, 0.52f, 0.4f},
                                             {0.45f, 0.2f, 0.14f},  {0.15f, 0.2f, 0.25f},
                                             {0.7f, 0.7f, 0.68f},   {0.55f, 0.45f, 0.3f}};
        for (int iz = 0; iz < nz; ++iz)
            for (int ix = 0; ix < nx; ++ix) {
                float fx = lotX * rng.uniform(0.7f, 0.98f), fz = lotZ * rng.uniform(0.7f, 0.98f);
                float cx =
                    lo.x + kSidewalk + float(ix) * (lotX + gap) + 0.5f * fx + rng.uniform() * (lotX - fx);
                float cz =
                    lo.z + kSidewalk + float(iz) * (lotZ + gap) + 0.5f * fz + rng.uniform() * (lotZ - fz);
                float h = 6.0f + 39.0f * std::pow(rng.uniform(), 2.2f - 1.4f * central);
                glm::vec3 albedo = jitterColor(rng, palette[rng.below(6)], 0.08f);
                addBuilding({cx, kCurb, cz}, fx, fz, h, albedo, blockCentre, rng);
            }
    }

    // One building with footprint fx x fz centred at `base`, height h. Records its street-facing walls.
    void addBuilding(glm::vec3 base, float fx, float fz, float h, glm::vec3 albedo, glm::vec3 blockCentre,
                     Pcg32& rng) {
        float kind = rng.uniform();
        // Rotation by k quarter turns about +Y, written with exact 0/1 entries (no cos/sin rounding).
        static const glm::vec3 xAxes[4] = {{1, 0, 0}, {0, 0, -1}, {-1, 0, 0}, {0, 0, 1}};
        static const glm::vec3 zAxes[4] = {{0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {-1, 0, 0}};
        uint32_t k = rng.below(4);
        float sx = (k & 1) ? fz : fx, sz = (k & 1) ? fx : fz; // local extents that give world fx x fz
        glm::mat4 m = detail::frameMatrix(base, xAxes[k] * sx, kUp * h, zAxes[k] * sz);
        std::vector<glm::vec3> fullWalls = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
        float wallHeight = h;
        if (kind < 0.15f && fx >= 10.0f && fz >= 10.0f) {
            addInstance(kLMesh0 + rng.below(3), m, albedo);
            fullWalls = {-xAxes[k], -zAxes[k]}; // the walls away from the notch run the full length
        } else if (kind < 0.3f && h >= 15.0f) {
            uint32_t variant = rng.below(3);
            addInstance(kSteppedMesh0 + variant, m, albedo);
            static const float podium[3] = {0.3f, 0.45f, 0.22f};
            wallHeight = h * podium[variant];
        } else {
            addInstance(kBoxMesh, m, albedo);
        }
        bool awning = rng.chance(0.35f);
        for (const glm::vec3& n : fullWalls) {
            float half = std::abs(n.x) > 0.5f ? 0.5f * fx : 0.5f * fz;
            float width = std::abs(n.x) > 0.5f ? fz : fx;
            glm::vec3 c = base + n * half;
            // Street-facing: the wall is within 12 m of its block's edge (excludes inner lots).
            float toEdge = 0.5f * kBlock - glm::dot(c - blockCentre, n);
            if (toEdge > 12.0f) continue;
            facades_.push_back({c, n, width, wallHeight});
            if (awning) {
                awning = false;
                addAwning(c, n, std::min(8.0f, 0.6f * width), rng);
            }
        }
    }

    // A canvas awning: a single quad hinged on the wall 3.2 m up, sloping down 0.25 rad into the street.
    void addAwning(glm::vec3 wallBase, glm::vec3 n, float width, Pcg32& rng) {
        const float tilt = 0.25f, depth = 1.6f;
        glm::vec3 x = glm::cross(kUp, n);
        glm::vec3 z = n * std::cos(tilt) - kUp * std::sin(tilt);
        glm::vec3 y = glm::cross(z, x);
        glm::vec3 origin = wallBase + kUp * 3.2f + n * 0.01f;
        static const glm::vec3 canvas[4] = {
            {0.5f, 0.08f, 0.06f}, {0.1f, 0.3f, 0.12f}, {0.1f, 0.15f, 0.4f}, {0.55f, 0.4f, 0.1f}};
        addInstance(kQuadMesh, detail::frameMatrix(origin, x * width, y, z * depth),
                    jitterColor(rng, canvas[rng.below(4)], 0.1f));
    }

    // The high street: the middle east-west street (the default camera's), its first kFocusBlocks
    // blocks from the west: the curbs of the blocks on both sides and the facades facing it.
    float highStreetZ() const { return min_.z + float(opt_.blocksZ / 2) * kPitch + 0.5f * kStreet; }
    void findFocus() {
        const uint32_t row = opt_.blocksZ / 2, focusX = std::min(kFocusBlocks, opt_.blocksX);
        for (uint32_t bx = 0; bx < focusX; ++bx) {
            if (row > 0)
                focusCurbs_.push_back(((row - 1) * opt_.blocksX + bx) * 4 + 2); // south side of the street
            if (row < opt_.blocksZ) focusCurbs_.push_back((row * opt_.blocksX + bx) * 4 + 0);
        }
        const float z = highStreetZ(), xEnd = min_.x + float(focusX) * kPitch + kStreet;
        for (uint32_t i = 0; i < facades_.size(); ++i) {
            const Facade& f = facades_[i];
            bool faces = std::abs(f.normal.z) > 0.5f && (z - f.base.z) * f.normal.z > 0.0f;
            if (faces && std::abs(f.base.z - z) < 0.5f * kStreet + 15.0f && f.base.x < xEnd)
                focusFacades_.push_back(i);
        }
        allCurbs_.resize(curbs_.size());
        std::iota(allCurbs_.begin(), allCurbs_.end(), 0u);
        allFacades_.resize(facades_.size());
        std::iota(allFacades_.begin(), allFacades_.end(), 0u);
        if (focusCurbs_.empty()) focusCurbs_ = allCurbs_;
        if (focusFacades_.empty()) focusFacades_ = allFacades_;
    }

    // focusFraction_ of `count` over the high street's segments, the rest over all of them.
    template <class F>
    void spreadFocused(uint32_t count, const std::vector<uint32_t>& focus, const std::vector<uint32_t>& all,
                       Pcg32& rng, F&& place) {
        uint32_t focused = std::min(count, uint32_t(float(count) * focusFraction_ + 0.5f));
        spreadOver(focused, focus, rng, place);
        spreadOver(count - focused, all, rng, place);
    }

    // Shop windows: a lit pane on the ground floor and a wide warm spot above it, aimed out and down
    // onto the sidewalk in front.
    void addShops(uint32_t count) {
        Pcg32 rng(opt_.seed, 6);
        static const glm::vec3 warm[3] = {{1.0f, 0.85f, 0.65f}, {1.0f, 0.95f, 0.85f}, {1.0f, 0.75f, 0.5f}};
        spreadFocused(count, focusFacades_, allFacades_, rng, [&](uint32_t s, float t) {
            const Facade& f = facades_[s];
            glm::vec3 along = glm::cross(kUp, f.normal);
            glm::vec3 wall = f.base + along * ((t - 0.5f) * f.width);
            glm::vec3 color = warm[rng.below(3)];
            addInstance(kBoxMesh, upright(wall + f.normal * 0.03f + kUp * 0.4f, f.normal, 2.4f, 2.0f, 0.06f),
                        color * 0.9f);
            scene_.lights.push_back(spot(wall + f.normal * 0.5f + kUp * 3.0f, f.normal * 0.9f - kUp, color,
                                         rng.uniform(14.0f, 22.0f), rng.uniform(9.0f, 11.0f),
                                         rng.uniform(0.85f, 1.0f), 0.5f));
        });
    }

    // One dim moonlight from high in the south-west.
    void addMoon() {
        Light l;
        l.type = LightKind::Directional;
        l.direction = glm::normalize(glm::vec3(0.35f, -1.0f, 0.45f));
        l.color = glm::vec3(0.55f, 0.65f, 1.0f);
        l.intensity = 0.12f;
        scene_.lights.push_back(l);
    }

    Light spot(glm::vec3 position, glm::vec3 direction, glm::vec3 color, float intensity, float range,
               float outer, float innerFraction) {
        Light l;
        l.type = LightKind::Spot;
        l.position = position;
        l.direction = glm::normalize(direction);
        l.color = color;
        l.intensity = intensity;
        l.range = range;
        l.outerAngle = outer;
        l.innerAngle = outer * innerFraction;
        return l;
    }

    // Street lamps at the curb: a 6 m pole, an arm over the street and a spotlight under its end.
    void addLamps(uint32_t count) {
        Pcg32 rng(opt_.seed, 2);
        std::vector<std::vector<float>> poles(curbs_.size()); // pole positions along each curb
        spreadFocused(count, focusCurbs_, allCurbs_, rng, [&](uint32_t s, float t) {
            const Curb& c = curbs_[s];
            glm::vec3 foot = c.start + c.along * (t * c.length);
            bool near = std::any_of(poles[s].begin(), poles[s].end(),
                                    [&](float p) { return std::abs(p - t * c.length) < 4.0f; });
            if (!near) {
                poles[s].push_back(t * c.length);
                addInstance(kBoxMesh, boxAt(foot, {0.16f, 6.0f, 0.16f}), glm::vec3(0.2f, 0.21f, 0.22f));
                addInstance(kBoxMesh,
                            upright(foot + c.street * 0.65f + kUp * 5.9f, c.street, 0.1f, 0.1f, 1.3f),
                            glm::vec3(0.2f, 0.21f, 0.22f));
                // Street furniture in the pool: a bench along the curb and a bollard towards the street,
                // so each lamp's pool holds casters (closed boxes) whose shadows the static methods keep.
                addInstance(kBoxMesh, boxAt(foot + c.along * 1.6f - c.street * 0.6f, {1.8f, 0.5f, 0.5f}),
                            glm::vec3(0.35f, 0.25f, 0.18f));
                addInstance(kBoxMesh, boxAt(foot - c.along * 1.4f + c.street * 0.3f, {0.3f, 1.0f, 0.3f}),
                            glm::vec3(0.3f, 0.3f, 0.32f));
            }
            bool sodium = rng.chance(0.65f);
            glm::vec3 color = sodium ? glm::vec3(1.0f, 0.6f, 0.25f) : glm::vec3(1.0f, 0.92f, 0.8f);
            // Aimed a little into the street, so the pools of both curbs meet in the middle.
            scene_.lights.push_back(spot(foot + c.street * 1.2f + kUp * 5.85f, -kUp + c.street * 0.3f, color,
                                         rng.uniform(35.0f, 45.0f), rng.uniform(13.5f, 16.0f),
                                         rng.uniform(0.66f, 0.8f), 0.6f));
        });
    }

    // Floodlights on the sidewalk 1.5 m in front of a wall, aimed up and onto it.
    void addFloods(uint32_t count) {
        Pcg32 rng(opt_.seed, 3);
        static const glm::vec3 tints[4] = {
            {1.0f, 0.85f, 0.6f}, {0.75f, 0.85f, 1.0f}, {1.0f, 0.7f, 0.35f}, {0.5f, 0.95f, 0.9f}};
        spreadFocused(count, focusFacades_, allFacades_, rng, [&](uint32_t s, float t) {
            const Facade& f = facades_[s];
            glm::vec3 along = glm::cross(kUp, f.normal);
            glm::vec3 p = f.base + along * ((t - 0.5f) * f.width) + f.normal * 1.5f + kUp * 0.3f;
            float range = std::clamp(f.height * 0.9f, 12.0f, 30.0f);
            scene_.lights.push_back(spot(p, kUp - f.normal * 0.4f, tints[rng.below(4)],
                                         rng.uniform(50.0f, 70.0f), range, rng.uniform(0.45f, 0.65f), 0.65f));
        });
    }

    // Shop signs: a saturated board on the wall 3-6 m up and a narrow coloured spot, either washing the
    // wall from 2.5 m out or pointing down onto the sidewalk.
    void addSigns(uint32_t count) {
        Pcg32 rng(opt_.seed, 4);
        static const glm::vec3 colors[7] = {{1.0f, 0.05f, 0.1f}, {1.0f, 0.1f, 0.8f}, {0.1f, 0.9f, 1.0f},
                                            {0.2f, 1.0f, 0.2f},  {0.2f, 0.3f, 1.0f}, {1.0f, 0.9f, 0.1f},
                                            {1.0f, 0.45f, 0.05f}};
        spreadFocused(count, focusFacades_, allFacades_, rng, [&](uint32_t s, float t) {
            const Facade& f = facades_[s];
            glm::vec3 along = glm::cross(kUp, f.normal);
            float y = std::min(rng.uniform(3.0f, 6.0f), std::max(f.height - 1.0f, 2.0f));
            glm::vec3 wall = f.base + along * ((t - 0.5f) * f.width) + kUp * y;
            glm::vec3 color = colors[rng.below(7)];
            addInstance(kBoxMesh, upright(wall + f.normal * 0.06f, f.normal, 1.6f, 0.9f, 0.12f),
                        color * 0.8f);
            float outer = rng.uniform(0.3f, 0.45f);
            if (rng.chance(0.5f)) {
                glm::vec3 p = wall + f.normal * 2.5f + kUp * 0.5f;
                scene_.lights.push_back(
                    spot(p, wall - p, color, rng.uniform(18.0f, 25.0f), 9.0f, outer, 0.6f));
            } else {
                glm::vec3 p = wall + f.normal * 0.8f;
                scene_.lights.push_back(
                    spot(p, f.normal * 0.5f - kUp, color, rng.uniform(18.0f, 25.0f), 8.0f, outer, 0.6f));
            }
        });
    }

    // Cars loop around blocks on the lane 3 m outside the block edge, with rounded corners (radius 3 m,
    // 4 segments). All loops turn the same way, so neighbouring blocks' cars pass in opposite
    // directions on a shared street. Cars on one loop share its speed and are evenly spaced.
    void addCars(uint32_t count) {
        Pcg32 rng(opt_.seed, 5);
        uint32_t blocks = opt_.blocksX * opt_.blocksZ;
        auto order = shuffled(blocks, rng);
        // Blocks along the high street first, so its traffic passes in front of the default camera.
        std::stable_partition(order.begin(), order.end(), [&](uint32_t b) {
            return std::find(focusCurbs_.begin(), focusCurbs_.end(), b * 4 + 0) != focusCurbs_.end() ||
                   std::find(focusCurbs_.begin(), focusCurbs_.end(), b * 4 + 2) != focusCurbs_.end();
        });
        std::vector<uint32_t> perBlock(blocks, 0);
        for (uint32_t i = 0; i < count; ++i) ++perBlock[order[i % blocks]];
        static const glm::vec3 paints[6] = {{0.6f, 0.05f, 0.05f},  {0.05f, 0.1f, 0.4f}, {0.8f, 0.8f, 0.8f},
                                            {0.05f, 0.05f, 0.05f}, {0.3f, 0.3f, 0.32f}, {0.7f, 0.55f, 0.1f}};
        const float pi = 3.14159265358979f;
        for (uint32_t r = 0; r < std::min(count, blocks); ++r) {
            uint32_t b = order[r];
            glm::vec3 lo = blockMin(b);
            const glm::vec3 corners[4] = {lo, lo + glm::vec3(kBlock, 0, 0), lo + glm::vec3(kBlock, 0, kBlock),
                                          lo + glm::vec3(0, 0, kBlock)};
            const float startAngle[4] = {pi, 1.5f * pi, 0.0f, 0.5f * pi};
            std::vector<glm::vec3> loop;
            for (int c = 0; c < 4; ++c)
                for (int j = 0; j <= 4; ++j) {
                    float a = startAngle[c] + 0.5f * pi * float(j) / 4.0f;
                    loop.push_back(corners[c] + kLane * glm::vec3(std::cos(a), 0.0f, std::sin(a)));
                }
            float length = 0.0f;
            for (size_t i = 0; i < loop.size(); ++i)
                length += glm::length(loop[(i + 1) % loop.size()] - loop[i]);
            float speed = rng.uniform(7.0f, 12.0f), phase0 = rng.uniform(0.0f, length);
            for (uint32_t k = 0; k < perBlock[b]; ++k) {
                CarPath car;
                car.instance = addInstance(kCarMesh, glm::mat4(1.0f),
                                           jitterColor(rng, paints[rng.below(6)], 0.1f), true);
                car.waypoints = loop;
                car.speed = speed;
                car.phase = std::fmod(phase0 + length * float(k) / float(perBlock[b]), length);
                scene_.cars.push_back(std::move(car));
                for (float side : {-0.65f, 0.65f}) {
                    Light l = spot({}, {0, -1, 0}, {1.0f, 0.95f, 0.85f}, 50.0f, 20.0f, 0.5f, 0.6f);
                    l.dynamic = true;
                    l.attachedInstance = int32_t(scene_.cars.back().instance);
                    l.localPosition = glm::vec3(side, 0.65f, -2.3f);
                    l.localDirection = glm::normalize(glm::vec3(0.0f, -0.1f, -1.0f));
                    scene_.lights.push_back(l);
                }
            }
        }
    }

    // Looking down the high street (the middle east-west street) from its west end, 12 m up, pitched
    // ~17 degrees down: the overlapping lamp and shop pools on the street and sidewalks, the flood-lit
    // facades and signs on both sides fill the frame; the far end of the street and the sky the top.
    void setCamera() {
        float streetZ = highStreetZ();
        Camera& cam = scene_.camera;
        cam.position = glm::vec3(min_.x + 3.0f, 12.0f, streetZ);
        cam.target = glm::vec3(min_.x + 43.0f, 0.0f, streetZ);
        cam.fovY = 1.0f;
        cam.nearPlane = 0.1f;
        cam.farPlane = std::max(100.0f, 1.05f * glm::length(scene_.boundsMax - scene_.boundsMin));
    }

    NightCityOptions opt_;
    Scene scene_;
    float width_ = 0.0f, depth_ = 0.0f;
    glm::vec3 min_{0.0f};
    std::vector<Facade> facades_;
    std::vector<Curb> curbs_;
    std::vector<uint32_t> focusCurbs_, focusFacades_, allCurbs_, allFacades_;
    float focusFraction_ = 1.0f;
};

} // namespace

Result<Scene> makeNightCity(const NightCityOptions& options) {
    if (options.lights == 0 || options.lights > kMaxLights)
        return fail("night-city: lights must be in 1.." + std::to_string(kMaxLights) + ", got " +
                    std::to_string(options.lights));
    if (options.blocksX == 0 || options.blocksZ == 0 || options.blocksX > 64 || options.blocksZ > 64)
        return fail("night-city: blocksX and blocksZ must be in 1..64, got " +
                    std::to_string(options.blocksX) + " x " + std::to_string(options.blocksZ));
    return CityBuilder(options).build();
}

} // namespace ml
