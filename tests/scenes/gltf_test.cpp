// glTF loading: the two shared real scenes, small hand-written files for the details (no normals,
// non-triangle modes, mirrored nodes, KHR_lights_punctual), and bad input that must give a one-line
// error naming the file: missing, malformed JSON, truncated .glb/.gltf, accessors past their buffer,
// out-of-range indices, NaN positions, unknown extensions.
#include "scene_test_util.h"

#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

namespace ml {
namespace {

size_t triangles(const Scene& s) {
    size_t n = 0;
    for (const Mesh& m : s.meshes) n += m.indices.size() / 3;
    return n;
}

size_t instancedTriangles(const Scene& s) {
    size_t n = 0;
    for (const Instance& i : s.instances) n += s.meshes[i.mesh].indices.size() / 3;
    return n;
}

void expectFramed(const Scene& s) {
    const Camera& c = s.camera;
    glm::vec3 view = glm::normalize(c.target - c.position);
    for (int k = 0; k < 8; ++k) {
        glm::vec3 corner((k & 1) ? s.boundsMax.x : s.boundsMin.x, (k & 2) ? s.boundsMax.y : s.boundsMin.y,
                         (k & 4) ? s.boundsMax.z : s.boundsMin.z);
        glm::vec3 to = corner - c.position;
        float angle = std::acos(std::clamp(glm::dot(glm::normalize(to), view), -1.0f, 1.0f));
        EXPECT_LE(angle, 0.5f * c.fovY + 1e-3f) << "bounds corner " << k << " outside the view cone";
        EXPECT_GT(glm::length(to), c.nearPlane);
        EXPECT_LT(glm::length(to), c.farPlane);
    }
}

// Procedural lights sit near the scene and aim at it.
void expectLightsOnScene(const Scene& s) {
    glm::vec3 margin = 0.25f * (s.boundsMax - s.boundsMin) + 0.1f;
    for (const Light& l : s.lights) {
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(l.position, s.boundsMin - margin)));
        EXPECT_TRUE(glm::all(glm::lessThanEqual(l.position, s.boundsMax + margin)));
        EXPECT_FALSE(l.dynamic);
        EXPECT_EQ(l.attachedInstance, -1);
    }
}

TEST(ScenesGltf, LoadsSampleBuilding) {
    ML_SKIP_WITHOUT_SHARED();
    std::string path = test::sharedScene("sample-building.gltf");
    auto r = loadGltf(path, 100, 1);
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = *r;
    EXPECT_EQ(triangles(s), 11132u);          // every primitive once (SOURCES.md)
    EXPECT_EQ(instancedTriangles(s), 23388u); // 70 mesh nodes
    EXPECT_EQ(s.instances.size(), 87u);       // (node, primitive) pairs
    EXPECT_EQ(s.lights.size(), 100u);
    test::expectValidLights(s);
    expectLightsOnScene(s);
    expectFramed(s);
    for (const Mesh& m : s.meshes) EXPECT_EQ(m.closed, isClosedMesh(m)) << m.name;
    // Authored for a y-down clip space (every node mirrored): loaded upright, a 22 x 22 m floor with the
    // dome rising ~10 m above it, and every transform proper.
    bool warned = false;
    for (const std::string& w : s.warnings) warned = warned || w.find("mirrored") != std::string::npos;
    EXPECT_TRUE(warned);
    EXPECT_NEAR(s.boundsMax.x - s.boundsMin.x, 22.0f, 0.1f);
    EXPECT_GT(s.boundsMax.y, 9.0f);
    EXPECT_GT(s.boundsMin.y, -1.0f);
    for (const Instance& i : s.instances) EXPECT_GT(glm::determinant(glm::mat3(i.transform)), 0.0f);
}

TEST(ScenesGltf, LoadsFzkHaus) {
    ML_SKIP_WITHOUT_SHARED();
    std::string path = test::sharedScene("fzk-haus.glb");
    auto r = loadGltf(path, 64, 2);
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = *r;
    EXPECT_EQ(triangles(s), 32588u);
    EXPECT_EQ(instancedTriangles(s), 35906u);
    EXPECT_EQ(s.lights.size(), 64u);
    test::expectValidLights(s);
    expectLightsOnScene(s);
    expectFramed(s);
    // A two-storey house in metres: ~18 x 16 m site, ~6 m roof ridge above the ground.
    glm::vec3 size = s.boundsMax - s.boundsMin;
    EXPECT_NEAR(size.x, 18.0f, 0.5f);
    EXPECT_NEAR(size.z, 16.0f, 0.5f);
    EXPECT_GT(size.y, 5.0f);
    EXPECT_LT(size.y, 10.0f);
    size_t closed = 0;
    for (const Mesh& m : s.meshes) {
        EXPECT_EQ(m.closed, isClosedMesh(m)) << m.name;
        closed += m.closed;
        for (const Vertex& v : m.vertices)
            ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-3f); // computed normals
    }
    EXPECT_GT(closed, 0u);
    EXPECT_LT(closed, s.meshes.size()) << "IFC walls are closed, some other parts are not";
}

TEST(ScenesGltf, DeterministicLights) {
    ML_SKIP_WITHOUT_SHARED();
    std::string path = test::sharedScene("fzk-haus.glb");
    auto a = loadGltf(path, 300, 5), b = loadGltf(path, 300, 5), c = loadGltf(path, 300, 6);
    ASSERT_TRUE(a.ok() && b.ok() && c.ok());
    EXPECT_EQ(test::sceneBytes(*a), test::sceneBytes(*b));
    EXPECT_NE(test::sceneBytes(*a), test::sceneBytes(*c));
    for (uint32_t n : {0u, 4097u}) {
        auto r = loadGltf(path, n, 1);
        EXPECT_FALSE(r.ok());
        EXPECT_NE(r.error().find(path), std::string::npos);
    }
}

// ---- small hand-written files ----

std::string base64(const std::string& in) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        uint32_t v =
            (uint32_t(uint8_t(in[i])) << 16) | (uint32_t(uint8_t(in[i + 1])) << 8) | uint8_t(in[i + 2]);
        for (int k = 3; k >= 0; --k) out += table[(v >> (6 * k)) & 63];
    }
    if (i + 1 == in.size()) {
        uint32_t v = uint32_t(uint8_t(in[i])) << 16;
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += "==";
    } else if (i + 2 == in.size()) {
        uint32_t v = (uint32_t(uint8_t(in[i])) << 16) | (uint32_t(uint8_t(in[i + 1])) << 8);
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += table[(v >> 6) & 63];
        out += '=';
    }
    return out;
}

// A tetrahedron (4 positions, 12 u16 indices, CCW outward) in one embedded buffer, with knobs to break
// it. Layout: positions at 0 (48 bytes), indices at 48 (24 bytes).
struct Tetra {
    std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::vector<uint16_t> indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    int positionCount = 4;
    int positionBufferViewLength = 48;
    int bufferByteLength = 72;
    std::string nodes = R"([{"mesh": 0}])";
    std::string extraPrimitive;     // appended to the primitives array
    std::string extensionsRequired; // e.g. R"("extensionsRequired": ["KHR_draco_mesh_compression"],)"
    std::string extraTop;           // more top-level members, each followed by a comma
    std::string primitiveMember;    // more members of the first primitive, each preceded by a comma

    std::string json() const {
        std::string bin(reinterpret_cast<const char*>(positions.data()), positions.size() * 4);
        bin.append(reinterpret_cast<const char*>(indices.data()), indices.size() * 2);
        return R"({"asset": {"version": "2.0"}, )" + extensionsRequired + extraTop +
               R"("scene": 0, "scenes": [{"nodes": [0]}], "nodes": )" + nodes +
               R"(, "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1)" +
               primitiveMember + "}" + extraPrimitive +
               R"(]}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
               std::to_string(positionCount) +
               R"(, "type": "VEC3"}, {"bufferView": 1, "componentType": 5123, "count": )" +
               std::to_string(indices.size()) +
               R"(, "type": "SCALAR"}], "bufferViews": [{"buffer": 0, "byteLength": )" +
               std::to_string(positionBufferViewLength) +
               R"(}, {"buffer": 0, "byteOffset": 48, "byteLength": )" + std::to_string(indices.size() * 2) +
               R"(}], "buffers": [{"byteLength": )" + std::to_string(bufferByteLength) +
               R"(, "uri": "data:application/octet-stream;base64,)" + base64(bin) + R"("}]})";
    }
};

TEST(ScenesGltf, HandWrittenTetrahedron) {
    Tetra t;
    t.extraPrimitive = R"(, {"attributes": {"POSITION": 0}, "mode": 1})"; // LINES: skipped with a warning
    std::string path = test::writeFile("tetra.gltf", t.json());
    auto r = loadGltf(path, 3, 1);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_EQ(r->meshes.size(), 1u);
    const Mesh& m = r->meshes[0];
    EXPECT_EQ(m.indices.size(), 12u);
    EXPECT_TRUE(m.closed);
    EXPECT_EQ(m.vertices.size(), 12u) << "no normals in the file: flat normals, one vertex per corner";
    for (size_t k = 0; k < m.vertices.size(); k += 3) {
        glm::vec3 a = m.vertices[k].position, b = m.vertices[k + 1].position, c = m.vertices[k + 2].position;
        EXPECT_GT(glm::dot(glm::cross(b - a, c - a), m.vertices[k].normal), 0.0f);
    }
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_NE(r->warnings[0].find("LINES"), std::string::npos) << r->warnings[0];
    EXPECT_EQ(r->lights.size(), 3u);
    test::expectValidLights(*r);
    EXPECT_NEAR(r->instances[0].albedo.x, 0.8f, 1e-6f); // no material: a rough dielectric
    EXPECT_EQ(r->instances[0].roughness, 1.0f);
    EXPECT_EQ(r->instances[0].metalness, 0.0f);
}

// metallicRoughness factors reach the instance (Module::setInstanceMaterial through bindScene); absent
// factors take glTF's defaults (1, 1).
TEST(ScenesGltf, MaterialFactorsReachTheInstance) {
    Tetra t;
    t.primitiveMember = R"(, "material": 0)";
    t.extraTop = R"("materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.5, 0.75, 1],)"
                 R"( "metallicFactor": 0.75, "roughnessFactor": 0.375}}],)";
    auto r = loadGltf(test::writeFile("tetra_material.gltf", t.json()), 1, 1);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_EQ(r->instances.size(), 1u);
    EXPECT_EQ(r->instances[0].albedo, glm::vec3(0.25f, 0.5f, 0.75f));
    EXPECT_EQ(r->instances[0].metalness, 0.75f);
    EXPECT_EQ(r->instances[0].roughness, 0.375f);
    t.extraTop = R"("materials": [{"pbrMetallicRoughness": {}}],)";
    r = loadGltf(test::writeFile("tetra_default_material.gltf", t.json()), 1, 1);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->instances[0].metalness, 1.0f);
    EXPECT_EQ(r->instances[0].roughness, 1.0f);
}

// A mirrored node among proper ones gets a mesh copy with reversed triangles, so it stays closed and
// outward-wound in world space.
TEST(ScenesGltf, MirroredNodeKeepsOutwardWinding) {
    Tetra t;
    t.nodes =
        R"([{"children": [1, 2]}, {"mesh": 0}, {"mesh": 0, "scale": [-1, 1, 1], "translation": [3, 0, 0]}])";
    std::string path = test::writeFile("mirrored.gltf", t.json());
    auto r = loadGltf(path, 1, 1);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_EQ(r->instances.size(), 2u);
    EXPECT_EQ(r->meshes.size(), 2u);
    for (const Instance& inst : r->instances) {
        const Mesh& m = r->meshes[inst.mesh];
        EXPECT_TRUE(m.closed);
        double volume = 0.0; // world-space signed volume: positive when outward-wound
        for (size_t k = 0; k < m.indices.size(); k += 3) {
            glm::dvec3 p[3];
            for (int j = 0; j < 3; ++j)
                p[j] = glm::dvec3(inst.transform *
                                  glm::vec4(m.vertices[m.indices[k + size_t(j)]].position, 1.0f));
            volume += glm::dot(p[0], glm::cross(p[1], p[2])) / 6.0;
        }
        EXPECT_GT(volume, 0.0);
    }
}

TEST(ScenesGltf, PunctualLightsAreUsedFirst) {
    Tetra t;
    t.nodes =
        R"([{"children": [1, 2]}, {"mesh": 0}, {"translation": [0, 5, 0], "rotation": [-0.7071068, 0, 0, 0.7071068],
                  "extensions": {"KHR_lights_punctual": {"light": 0}}}])";
    t.extraTop =
        R"("extensionsUsed": ["KHR_lights_punctual"], "extensions": {"KHR_lights_punctual": {"lights": [
                  {"type": "spot", "color": [1, 0, 0], "intensity": 7, "range": 9, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}},)";
    std::string path = test::writeFile("punctual.gltf", t.json());
    auto r = loadGltf(path, 4, 1);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_EQ(r->lights.size(), 4u);
    const Light& l = r->lights[0];
    EXPECT_EQ(l.type, LightKind::Spot);
    EXPECT_NEAR(l.position.y, 5.0f, 1e-5f);
    EXPECT_NEAR(l.direction.y, -1.0f, 1e-5f) << "-Z rotated -90 degrees about X points down";
    EXPECT_EQ(l.color, glm::vec3(1, 0, 0));
    EXPECT_FLOAT_EQ(l.range, 9.0f);
    EXPECT_FLOAT_EQ(l.outerAngle, 0.5f);
    EXPECT_FLOAT_EQ(l.innerAngle, 0.2f);
    test::expectValidLights(*r);
}

// ---- bad input ----

TEST(ScenesGltf, MissingFile) {
    std::string path = (test::tempDir() / "does-not-exist.glb").string();
    test::expectOneLineError(loadGltf(path, 8, 1), path);
    test::expectOneLineError(loadScene(path, 8, 1), path);
}

TEST(ScenesGltf, MalformedJson) {
    for (const char* text :
         {"{ this is not json", "", "{}", "[1, 2, 3]", R"({"asset": {"version": "2.0"}, "nodes": 5})"}) {
        std::string path = test::writeFile("malformed.gltf", text);
        test::expectOneLineError(loadGltf(path, 8, 1), path);
    }
}

TEST(ScenesGltf, AccessorPastBuffer) {
    {
        Tetra t;
        t.positionCount = 100; // 1200 bytes from a 48-byte bufferView
        std::string path = test::writeFile("past-view.gltf", t.json());
        test::expectOneLineError(loadGltf(path, 8, 1), path);
    }
    {
        Tetra t;
        t.positionCount = 100;
        t.positionBufferViewLength = 1200; // the view itself runs past the 72-byte buffer
        std::string path = test::writeFile("past-buffer.gltf", t.json());
        test::expectOneLineError(loadGltf(path, 8, 1), path);
    }
}

TEST(ScenesGltf, IndexOutOfRange) {
    Tetra t;
    t.indices[7] = 4; // only 4 vertices
    std::string path = test::writeFile("bad-index.gltf", t.json());
    auto r = loadGltf(path, 8, 1);
    test::expectOneLineError(r, path);
    EXPECT_NE(r.error().find("index"), std::string::npos) << r.error();
}

TEST(ScenesGltf, NanPosition) {
    Tetra t;
    t.positions[4] = std::nanf("");
    std::string path = test::writeFile("nan.gltf", t.json());
    test::expectOneLineError(loadGltf(path, 8, 1), path);
}

TEST(ScenesGltf, BadReferences) {
    const char* nodeSets[] = {
        R"([{"mesh": 3}])",                      // mesh out of range
        R"([{"children": [0], "mesh": 0}])",     // cycle
        R"([{"children": [7]}])",                // child out of range
        R"([{"mesh": 0, "matrix": [1, 0, 0]}])", // short matrix
    };
    for (const char* nodes : nodeSets) {
        Tetra t;
        t.nodes = nodes;
        std::string path = test::writeFile("bad-ref.gltf", t.json());
        SCOPED_TRACE(nodes);
        test::expectOneLineError(loadGltf(path, 8, 1), path);
    }
    Tetra t;
    t.extensionsRequired = R"("extensionsRequired": ["KHR_draco_mesh_compression"], )";
    std::string path = test::writeFile("draco.gltf", t.json());
    test::expectOneLineError(loadGltf(path, 8, 1), path);
}

// Cuts of the real .glb at every 1/16th (and a few header-sized cuts) must fail cleanly. Each cut is
// tried three ways: as is; with the header's total length patched to the cut size (so the GLB header
// check passes); and additionally with the BIN chunk length patched to what is left (so tinygltf sees
// a self-consistent container whose buffer is too short for the accessors).
TEST(ScenesGltf, TruncatedGlb) {
    ML_SKIP_WITHOUT_SHARED();
    std::string full = test::readFile(test::sharedScene("fzk-haus.glb"));
    ASSERT_GT(full.size(), 1000u);
    uint32_t jsonLength;
    std::memcpy(&jsonLength, full.data() + 12, 4);
    std::vector<size_t> cuts = {0, 4, 12, 19, 20, 27};
    for (int k = 1; k < 16; ++k) cuts.push_back(full.size() * size_t(k) / 16);
    cuts.push_back(20 + jsonLength + 8);
    cuts.push_back(full.size() - 4);
    for (size_t cut : cuts) {
        for (int variant = 0; variant < 3; ++variant) {
            std::string bytes = full.substr(0, cut);
            if (variant >= 1 && cut >= 12) {
                uint32_t length = uint32_t(cut);
                std::memcpy(&bytes[8], &length, 4);
            }
            size_t binHeader = 20 + jsonLength;
            if (variant == 2 && cut >= binHeader + 8) {
                uint32_t bin = uint32_t((cut - binHeader - 8) & ~size_t(3));
                std::memcpy(&bytes[binHeader], &bin, 4);
                bytes.resize(binHeader + 8 + bin);
                uint32_t length = uint32_t(bytes.size());
                std::memcpy(&bytes[8], &length, 4);
            }
            std::string path = test::writeFile("cut.glb", bytes);
            SCOPED_TRACE("cut " + std::to_string(cut) + " variant " + std::to_string(variant));
            test::expectOneLineError(loadGltf(path, 8, 1), path);
        }
    }
}

TEST(ScenesGltf, TruncatedGltf) {
    ML_SKIP_WITHOUT_SHARED();
    std::string full = test::readFile(test::sharedScene("sample-building.gltf"));
    ASSERT_GT(full.size(), 1000u);
    for (int k = 0; k < 16; ++k) {
        std::string path = test::writeFile("cut.gltf", full.substr(0, full.size() * size_t(k) / 16));
        SCOPED_TRACE(k);
        test::expectOneLineError(loadGltf(path, 8, 1), path);
    }
}

// Whatever a loader accepts must be safe to use: indices in range, finite positions, unit normals.
void expectUsable(const Scene& s) {
    for (const Mesh& m : s.meshes) {
        ASSERT_EQ(m.indices.size() % 3, 0u);
        for (uint32_t i : m.indices) ASSERT_LT(i, m.vertices.size());
        for (const Vertex& v : m.vertices) ASSERT_TRUE(test::finite(v.position) && test::finite(v.normal));
    }
    for (const Instance& i : s.instances) ASSERT_LT(i.mesh, s.meshes.size());
}

// Seeded random byte corruption (small files: anywhere; the .glb: header and JSON chunk, where the
// structure lives). Each variant either loads into a usable scene or fails with a one-line error.
TEST(ScenesGltf, RandomCorruptionNeverCrashes) {
    uint64_t state = 0x9E3779B97F4A7C15ull;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return uint32_t(state >> 33);
    };
    struct Source {
        std::string bytes, name;
        size_t span;
    };
    std::string tetra = Tetra().json();
    std::vector<Source> sources{{tetra, "fuzz.gltf", tetra.size()}};
    // The shared .glb when the checkout has ../shared (a clone without it corrupts the tetrahedron only;
    // reading its JSON length from a missing file overran an empty string).
    std::string glb = test::readFile(test::sharedScene("fzk-haus.glb"));
    if (glb.size() >= 20) {
        uint32_t jsonLength;
        std::memcpy(&jsonLength, glb.data() + 12, 4);
        ASSERT_LE(20 + size_t(jsonLength), glb.size());
        sources.push_back({glb, "fuzz.glb", 20 + size_t(jsonLength)});
    }
    int loaded = 0, failed = 0;
    for (const Source& src : sources) {
        for (int trial = 0; trial < 40; ++trial) {
            std::string bytes = src.bytes;
            int flips = 1 + int(next() % 4);
            for (int f = 0; f < flips; ++f) {
                const char noise[] = {'0', '9', '-', '"', '{', ']', ',', 'e', '\0', '\x7f'};
                bytes[next() % src.span] = noise[next() % sizeof noise];
            }
            std::string path = test::writeFile(src.name, bytes);
            auto r = loadGltf(path, 4, 1);
            if (r.ok()) {
                ++loaded;
                expectUsable(*r);
            } else {
                ++failed;
                test::expectOneLineError(r, path);
            }
        }
    }
    EXPECT_GT(failed, 0);
    std::printf("corruption: %d loaded, %d rejected\n", loaded, failed);
}

TEST(ScenesGltf, NotAGlb) {
    std::string path = test::writeFile("text.glb", "{\"asset\": {\"version\": \"2.0\"}}");
    test::expectOneLineError(loadGltf(path, 8, 1), path);
}

TEST(ScenesLoadScene, Dispatch) {
    ML_SKIP_WITHOUT_SHARED();
    auto city = loadScene("night-city", 32, 1);
    ASSERT_TRUE(city.ok()) << city.error();
    EXPECT_EQ(city->name, "night-city");
    EXPECT_EQ(city->lights.size(), 32u);
    auto glb = loadScene(test::sharedScene("fzk-haus.glb"), 16, 1);
    ASSERT_TRUE(glb.ok()) << glb.error();
    EXPECT_EQ(glb->lights.size(), 16u);
    std::string obj = (test::tempDir() / "house.obj").string();
    auto r = loadScene(obj, 16, 1);
    test::expectOneLineError(r, obj);
    EXPECT_NE(r.error().find("night-city"), std::string::npos) << "lists the choices: " << r.error();
    EXPECT_NE(r.error().find(".glb"), std::string::npos) << r.error();
    EXPECT_FALSE(loadScene("night-city", 0, 1).ok());
}

} // namespace
} // namespace ml
