// What the API-sequence fuzzer (tests/api_fuzz/api_fuzz.cpp) found, kept as plain regression tests.
//
// The static shadow arena (engine/module_uploads.cpp) rebuilt when full while some faces were resident
// and others pending: the upload sized its staging bytes for the pending faces only, then copied every
// face (all pending again after the rebuild) into them, a heap overflow (free(): invalid next size) and
// copy regions past the staging buffer. Reached by re-baking some lights while others keep an older
// bake, e.g. a light made dynamic in between (bakeStaticShadows skips it, its faces stay resident).
#include "../../gpu/gpu_test_util.h"

#include <glm/gtc/matrix_transform.hpp>

namespace ml::test {
namespace {

TEST(FuzzFound, StaticArenaRebuildWithResidentFaces) {
    auto m = makeModule();
    ASSERT_TRUE(m);
    static const std::vector<MeshVertex> v = {
        {{-8, 0, -8}, {0, 1, 0}}, {{8, 0, -8}, {0, 1, 0}}, {{8, 0, 8}, {0, 1, 0}}, {{-8, 0, 8}, {0, 1, 0}}};
    static const std::vector<uint32_t> idx = {0, 2, 1, 0, 3, 2};
    auto ground = m->addMesh({v, idx, false, "ground"});
    ASSERT_TRUE(ground.ok());
    ASSERT_TRUE(m->addInstance(ground.value(), glm::mat4(1.0f), glm::vec3(0.5f), false).ok());
    ASSERT_TRUE(m->addInstance(ground.value(),
                               glm::scale(glm::translate(glm::mat4(1.0f), {0, 1.5f, 0}), glm::vec3(0.1f)),
                               glm::vec3(0.5f), false)
                    .ok());
    LightDesc l;
    l.kind = LightKind::Point; // six faces: a large share of the arena stays resident
    l.position = {1, 4, 0};
    const LightId kept = m->addLight(l).value();
    l.kind = LightKind::Spot;
    l.position = {-1, 4, 0};
    ASSERT_TRUE(m->addLight(l).ok());
    ASSERT_TRUE(m->createTargets(32, 18).ok());
    ASSERT_TRUE(m->setCamera({{0, 6, 8}, {0, 0, 0}}).ok());
    ASSERT_TRUE(m->bakeStaticShadows(StaticMethod::SM, 64).ok());
    renderFrame(*m); // every face resident
    // The point light turns dynamic: later bakes skip it and its six faces stay resident, while the
    // spot's face is re-baked and appended until the arena is full and rebuilt.
    l.kind = LightKind::Point;
    l.position = {1, 4, 0};
    l.dynamic = true;
    ASSERT_TRUE(m->setLight(kept, l).ok());
    auto& impl = internals(*m);
    const uint64_t epoch = impl.recordsEpoch;
    for (int i = 0; i < 64 && impl.recordsEpoch == epoch; ++i) {
        auto baked = m->bakeStaticShadows(StaticMethod::SM, 64);
        ASSERT_TRUE(baked.ok()) << baked.error();
        ASSERT_EQ(baked.value(), 1u);
        renderFrame(*m);
    }
    ASSERT_NE(impl.recordsEpoch, epoch) << "the arena was never rebuilt: the case is not reached";
    EXPECT_EQ(validationErrors(), 0u);
    // Every face's words where its record says they are.
    const std::vector<uint32_t> arena = readBufferAs<uint32_t>(deviceOf(*m), impl.staticWords);
    uint32_t faces = 0;
    for (size_t light = 0; light < impl.shadows.size(); ++light)
        for (const auto& face : impl.shadows[light]) {
            if (face.method == StaticMethod::None) continue;
            ++faces;
            ASSERT_TRUE(face.resident);
            ASSERT_LE(face.base + face.words.size(), arena.size());
            EXPECT_TRUE(std::equal(face.words.begin(), face.words.end(), arena.begin() + face.base))
                << "light slot " << light;
        }
    EXPECT_EQ(faces, 7u) << "the point light's six faces and the spot's one";
}

} // namespace
} // namespace ml::test
