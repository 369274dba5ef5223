// CPU reference rasteriser for dual depth maps (the input of SM, MH, MMH, DAG-MH; see dual_depth.h).
//
// Algorithm (a tiled scanline / bounding-box rasteriser, no GPU):
//   1. Every triangle goes to the light's view space and is clipped (Sutherland-Hodgman) against the
//      near plane, the far plane and a guard band at NDC +-2 on the four sides. The guard band keeps the
//      fixed-point coordinates below 2^26 at 64K^2, so edge functions stay exact in int64.
//   2. The clipped polygon is fanned into triangles and projected to fixed point: 8 sub-texel bits
//      (1/256 texel). Edge functions are exact integers; the texel centre (x + 0.5, y + 0.5) is a fixed
//      point too, so a centre on an edge is decided exactly.
//   3. Tie rule (top-left, in place of dual_depth.h's ">= 0"): with the triangle walked counter-
//      clockwise (NDC, y up), a centre strictly inside is covered; a centre exactly on an edge is covered
//      only when that edge points downward (dy < 0), or is horizontal and points to +x. The neighbour
//      across a shared edge walks it the other way, so exactly one of the two owns the centre. ">= 0"
//      would count the centre twice on a shared front edge and once on the back, and a closed mesh
//      would then never be "left" again. Clipping computes intersection points from the edge's end
//      points in a canonical order, so a shared edge is cut identically on both sides.
//   4. Per covered centre a hit (depth, kind) is recorded; the depth is the linear distance along the
//      light's -Z, interpolated perspective-correctly (1/z is affine in screen space) in double and
//      quantised with quantizeDepth(float(z), far). Front faces are counter-clockwise seen from the light.
//      Orthographic maps (directional lights) take the depth from the triangle's plane in fixed point
//      instead (orthoDepthPlane): quantised depth at texel (x, y) = A + ((Dx x + Dy y + 32) >> 6) in
//      int64, clamped to [0, 0xFFFFFFFE], where A (the plane at texel (0, 0)'s centre, rounded) and Dx, Dy
//      (its slopes per texel in 1/64 units, kOrthoSlopeFractionBits, rounded) come from the unclipped,
//      unsnapped triangle in double. Every texel of a triangle then lies exactly on an integer plane
//      that a decoder can evaluate (DAG-MH's value planes, dagmh.h), and parallel triangles get the same
//      slopes. The depth is within 2^-7 (x + y) + 1 units of the true plane: 1e-6 of the depth range at
//      262,144^2, where step 4's float is off by up to 6e-8 of it. A triangle steeper than 2^25 units a
//      texel (1/128 of the depth range) keeps step 4's depth, as slopes are int32 in DAG-MH's table.
//   5. Per texel the hits are sorted by depth; at equal depth a closed front face comes first, then open
//      faces, then closed back faces. enter = first hit. If the first hit is a closed front face, a
//      counter over closed faces (+1 front, -1 back, open faces ignored) is run from it and exit = depth
//      of the first hit where it drops to 0; if it never does (back faces beyond far), exit = far
//      (0xFFFFFFFE). Otherwise (open face, or a closed back face, e.g. the light inside a mesh)
//      exit = enter. No hit: enter = exit = kDepthEmpty.
// Rows are rendered in tiles (renderRows), or any block (renderRect, the tiled bakes), so that only one
// tile's hit list is held at a time.
#pragma once
#include "shadows/static/dual_depth.h"
#include "shadows/static/static_types.h"

#include <cstdint>
#include <vector>

namespace ml {

// World-space triangle soup: 3 positions per triangle, and per triangle whether its mesh is closed
// (watertight and consistently wound, counter-clockwise front faces).
struct CasterTriangles {
    std::vector<glm::vec3> positions;
    std::vector<uint8_t> closed;
    size_t triangleCount() const { return closed.size(); }
    void add(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, bool isClosed) {
        positions.push_back(a), positions.push_back(b), positions.push_back(c);
        closed.push_back(isClosed ? 1 : 0);
    }
};

// A scene's casters as CasterTriangles: castersFromScene (bake/scene_casters.h).

// A spotlight's frustum: looking along its direction, full angle 2 * outerAngle, far = range.
// The near plane is min(nearPlane, range / 100): a light of 5 cm range would otherwise get near = far
// and no bake (tests/failures Range5Centimetres). Depth is linear over [0, far], so a smaller near
// costs no depth precision; it only keeps casters closer to the light in the map.
LightFrustum spotLightFrustum(const LightShape& light, float nearPlane = 0.05f);

// A point light's cube face (0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z): 90 degrees, far = range. The face a
// direction falls in is pointLightFace (shaders/shared/light_math.h's rule: largest |component|,
// ties to the earlier axis). Near plane as for spots: min(nearPlane, range / 100).
LightFrustum pointLightFaceFrustum(const LightShape& light, uint32_t face, float nearPlane = 0.05f);
// A directional light's orthographic frustum fitted to the box [boundsMin, boundsMax]:
// looking along `direction` from beyond the box's bounding sphere, the view turned so that the box's
// longer light-space extent runs along x. Square texels; the map is res wide and mapRows(res) high
// (rows past it are outside the light): the box's light-space rectangle plus fitMargin fills it, so at
// least 1 - 1/rows - 2 margin/extent of its texels lie inside the rectangle. Depth: near/far = the box's
// slab along the light (nearest and deepest corner) -+ fitMargin, the margin 1/1024 of the box's
// diagonal (>= 0.1 mm). The rasteriser clips casters at kDirectionalClipNear from the eye, not at near:
// casters between the light and the box, up to 0.5 m beyond its bounding sphere, keep shadowing it (as
// before the fit); casters past far are clipped.
constexpr float kDirectionalClipNear = 0.5f;
LightFrustum directionalLightFrustum(glm::vec3 direction, glm::vec3 boundsMin, glm::vec3 boundsMax);
// The frustums a static light bakes: one for a spot, six for a point light, none otherwise (a
// directional light needs bounds: directionalLightFrustum).
std::vector<LightFrustum> lightFrustums(const LightShape& light);

class DualRasterizer {
  public:
    DualRasterizer(const CasterTriangles& casters, const LightFrustum& frustum, uint32_t resolution);

    // Renders rows [y0, y1) into enter/exit (and enterPlane, optional: renderRect's), each (y1 - y0) *
    // resolution words, row-major.
    void renderRows(uint32_t y0, uint32_t y1, uint32_t* enter, uint32_t* exit,
                    uint32_t* enterPlane = nullptr) const;
    // Renders the w x h block at texel (x0, y0) (inside the map, w * h < 2^30) into enter/exit, w words a
    // row: the same texels renderRows gives. Safe to call from several threads at once.
    // Hits go to 8 slots a texel (an overflow list past that) and each row walks only its covered span;
    // the thread's scratch (68 B a texel of the largest block rendered) is kept for its next call.
    // enterPlane (optional, w words a row): the id of the depth plane (planes()) the texel's enter depth
    // lies on exactly, 0 when none (empty texel, perspective map, a triangle too steep for a plane, or a
    // depth clamped to [0, 0xFFFFFFFE]); of the planes through the enter depth, the smallest id.
    void renderRect(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter, uint32_t* exit,
                    uint32_t* enterPlane = nullptr) const;
    // Bytes of the calling thread's renderRect scratch now (0 once render() has finished a map).
    static size_t threadScratchBytes();
    // renderRect as one hit list sorted by texel, every column of a triangle's box tested: the plain
    // statement of the rules above, which the tests hold renderRect to texel for texel.
    void renderRectReference(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter,
                             uint32_t* exit) const;
    // True when no triangle's covered rows and columns (renderRect's own bounds) reach the block, so
    // renderRect would fill it with kDepthEmpty only. Conservative: false may still render empty.
    bool blockEmpty(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) const;
    // The whole map, in tiles of at most `tileTexels` texels; frees the thread's scratch at the end. An
    // orthographic map carries its enter planes (DualDepthMap::enterPlane, planes).
    DualDepthMap render(uint64_t tileTexels = 1u << 20) const;

    size_t projectedTriangles() const { return tris_.size(); }
    // An orthographic map's distinct depth planes (step 4), plane id i + 1 at index i. Triangles on one
    // plane (a ground of many quads, a wall's two halves) share it. 16 B a plane; ids stay below 2^30.
    static constexpr uint32_t kMaxDepthPlanes = (1u << 30) - 1u;
    const std::vector<DepthPlane>& planes() const { return planes_; }
    // An all-empty map of this rasteriser's size, rows and projection (renderRows fills its words).
    DualDepthMap blankMap() const;

  private:
    struct Tri {
        int64_t x[3], y[3]; // fixed point, 1/256 texel, counter-clockwise
        double invDepth[3]; // 1 / depth (perspective) or depth (orthographic): linear in screen space
        // Orthographic maps: the triangle's depth plane in fixed point (step 4), in quantised depth units
        // at texel (x, y): planeA + ((planeDx x + planeDy y + 32) >> 6). `plane` false: too steep for it.
        int64_t planeA = 0, planeDx = 0, planeDy = 0;
        bool plane = false;
        uint32_t planeId = 0; // planes() index + 1, 0 when `plane` is false
        // The hit's quantised depth at texel (x, y), e the edge functions at its centre (step 4);
        // *onPlane (optional) gets planeId when the depth is the plane's unclamped value.
        uint32_t depth(int64_t x, int64_t y, const int64_t e[3], double invArea, bool ortho, float far,
                       uint32_t* onPlane = nullptr) const;
        int32_t yMin, yMax; // covered texel rows (inclusive), before tiling
        uint8_t kind;       // 0 closed front, 1 open, 2 closed back
    };
    std::vector<Tri> tris_; // sorted by yMin
    std::vector<DepthPlane> planes_;
    uint32_t res_;
    uint32_t rows_; // rows in the light's volume (LightFrustum::mapRows)
    float far_;
    bool ortho_ = false;
};

// Convenience: rasterise the whole map.
DualDepthMap rasterizeDual(const CasterTriangles& casters, const LightFrustum& frustum, uint32_t resolution);

} // namespace ml
