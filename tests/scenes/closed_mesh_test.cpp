// isClosedMesh on small meshes whose answer is known, and updateBounds.
#include "scenes/scenes.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

// A unit cube as 8 shared corners and 12 CCW-outward triangles.
Mesh sharedCube() {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back(
            {glm::vec3(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)), glm::vec3(0, 1, 0)});
    // Faces as quads (a, b, c, d) counter-clockwise seen from outside.
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return m;
}

// The same cube with every triangle owning its own 3 vertices (as flat-shaded meshes are stored).
Mesh splitCube() {
    Mesh s = sharedCube(), m;
    for (uint32_t i : s.indices) {
        m.indices.push_back(uint32_t(m.vertices.size()));
        m.vertices.push_back(s.vertices[i]);
    }
    return m;
}

TEST(ScenesClosedMesh, CubeIsClosed) {
    EXPECT_TRUE(isClosedMesh(sharedCube()));
    EXPECT_TRUE(isClosedMesh(splitCube())) << "vertices are welded by position";
}

TEST(ScenesClosedMesh, MissingFaceIsOpen) {
    Mesh m = sharedCube();
    m.indices.resize(m.indices.size() - 6);
    EXPECT_FALSE(isClosedMesh(m));
}

TEST(ScenesClosedMesh, FlippedTriangleIsNotClosed) {
    Mesh m = sharedCube();
    std::swap(m.indices[1], m.indices[2]);
    EXPECT_FALSE(isClosedMesh(m)) << "inconsistent winding";
}

TEST(ScenesClosedMesh, DuplicateTriangleIsNotClosed) {
    Mesh m = sharedCube();
    m.indices.insert(m.indices.end(), {m.indices[0], m.indices[1], m.indices[2]});
    EXPECT_FALSE(isClosedMesh(m));
    // Two coincident cubes in one mesh: every directed edge twice (non-manifold).
    Mesh two = sharedCube();
    std::vector<uint32_t> again = two.indices;
    two.indices.insert(two.indices.end(), again.begin(), again.end());
    EXPECT_FALSE(isClosedMesh(two));
}

TEST(ScenesClosedMesh, DegenerateTrianglesAreIgnored) {
    Mesh m = sharedCube();
    m.indices.insert(m.indices.end(), {0, 0, 1, 3, 3, 3});
    EXPECT_TRUE(isClosedMesh(m));
}

TEST(ScenesClosedMesh, SingleQuadAndEmptyAreOpen) {
    Mesh quad = sharedCube();
    quad.indices.resize(6);
    EXPECT_FALSE(isClosedMesh(quad));
    EXPECT_FALSE(isClosedMesh(Mesh{}));
    Mesh bad = sharedCube();
    bad.indices[0] = 100; // out of range: never closed, never a crash
    EXPECT_FALSE(isClosedMesh(bad));
}

TEST(ScenesClosedMesh, UpdateBoundsTransformsCorners) {
    Scene s;
    s.meshes.push_back(sharedCube());
    Instance a;
    a.transform = glm::mat4(1.0f);
    a.transform[3] = glm::vec4(10, 0, 0, 1);
    Instance b;
    b.transform = glm::mat4(2.0f);
    b.transform[3] = glm::vec4(-5, -1, 0, 1);
    s.instances = {a, b};
    updateBounds(s);
    EXPECT_EQ(s.boundsMin, glm::vec3(-5, -1, 0));
    EXPECT_EQ(s.boundsMax, glm::vec3(11, 1, 2));
}

} // namespace
} // namespace ml
