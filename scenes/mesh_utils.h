// Internal helpers shared by the scene sources (not part of the module API):
//  - Pcg32: a small portable PRNG. Scenes must be identical for a seed on every standard library, so
//    nothing here uses std::uniform_*_distribution (its algorithm is implementation-defined).
//  - Mesh builders for the night city. Closed builders (box, L prism, stepped box) emit watertight,
//    consistently counter-clockwise-outward triangle lists with flat normals (vertices are split per
//    face; isClosedMesh welds them back by position). Open builders (quad, fence, foliage cards) emit
//    single-sided sheets whose edges have no opposite edge; given a thickness > 0 they emit closed
//    boxes of that thickness instead (the "-closed" night city variants).
//  - Small geometry helpers: affine frames, mesh bounds, flat normals.
#pragma once
#include "scenes/scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace ml::detail {

// PCG32 (O'Neill, XSH-RR output): 64-bit LCG state, 32-bit output. Integer-only, so every platform
// produces the same sequence; floats are derived from the top 24 bits, which are exact in a float.
class Pcg32 {
  public:
    explicit Pcg32(uint64_t seed, uint64_t stream = 0x5851f42d4c957f2dull) {
        inc_ = (stream << 1u) | 1u;
        next();
        state_ += seed;
        next();
    }
    uint32_t next() {
        uint64_t old = state_;
        state_ = old * 6364136223846793005ull + inc_;
        uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    // [0, 1) with 24-bit resolution.
    float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    // [0, n) for n >= 1; the modulo bias (< n / 2^32) is irrelevant for scene layout.
    uint32_t below(uint32_t n) { return n == 0 ? 0 : next() % n; }
    bool chance(float p) { return uniform() < p; }

  private:
    uint64_t state_ = 0;
    uint64_t inc_ = 0;
};

// ---- closed meshes (all have their base on y = 0) ----

// Unit box [-0.5, 0.5] x [0, 1] x [-0.5, 0.5]: 24 vertices, 12 triangles.
Mesh makeUnitBox();

// L-shaped prism in the unit footprint [-0.5, 0.5]^2, height [0, 1]: the +x/+z quadrant of size
// notchX x notchZ (fractions of the footprint, in (0, 1)) is cut away.
Mesh makeLPrism(float notchX, float notchZ, const char* name);

// A podium (footprint `base`, height baseHeight) carrying a tower (footprint `top`, strictly inside
// `base`, from baseHeight to topHeight). Footprints are (minX, minZ, maxX, maxZ). One closed mesh: the
// podium roof is a ring around the tower. Used for stepped buildings (unit coordinates) and the car
// (metres).
Mesh makeSteppedBox(glm::vec4 base, float baseHeight, glm::vec4 top, float topHeight, const char* name);

// ---- open meshes (closed slabs when thickness > 0, in object units) ----

// Unit quad in the XZ plane (y = 0), x in [-0.5, 0.5], z in [0, 1], front face +Y. 2 triangles.
// thickness > 0: the box y in [-thickness, 0] under it, 12 triangles.
Mesh makeUnitQuad(float thickness = 0.0f);

// Fence panel in the XY plane (z = 0, front +Z), x in [-0.5, 0.5], y in [0, 1]: `pickets` vertical
// strips plus two rails slightly in front (z = 0.02) so they never coincide with the pickets.
// thickness > 0: pickets are boxes z in [-thickness, 0], rails z in [0.02, 0.02 + thickness].
Mesh makeFence(int pickets, float thickness = 0.0f);

// Two crossed unit quads (XY plane and ZY plane), x/z in [-0.5, 0.5], y in [0, 1]: a foliage card.
// thickness > 0: two crossed boxes that thick, centred on those planes (overlapping, each closed).
Mesh makeFoliageCards(float thickness = 0.0f);

// ---- helpers ----

// Object -> world matrix whose columns are the given axes (already scaled) and origin.
glm::mat4 frameMatrix(const glm::vec3& origin, const glm::vec3& xAxis, const glm::vec3& yAxis,
                      const glm::vec3& zAxis);

// Object-space AABB of a mesh; returns false for a mesh without vertices.
bool meshBounds(const Mesh& mesh, glm::vec3& lo, glm::vec3& hi);

// Replaces the mesh by one with three vertices per triangle and face normals (for meshes whose file
// has no normals; architectural models are flat-faced, so flat shading is the faithful choice).
void makeFlatNormals(Mesh& mesh);

} // namespace ml::detail
