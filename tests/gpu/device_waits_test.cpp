// No hidden device-wide stalls: adding meshes, adding, changing and removing lights and instances, the
// shadow filter and the targets' size reach the GPU through per-slot and appended uploads, with no
// vkDeviceWaitIdle (they used to make the next record() wait for the whole borrowed device). The frames
// drawn after each change must equal a module that made the same calls and drew once at the end.
#include "gpu_test_util.h"

#include "engine/manylights_diagnostics.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <numeric>
#include <string>

namespace ml::test {
namespace {

// A closed box of half extents `half` around the origin: one face per axis and sign, CCW seen from outside.
MeshDesc boxMesh(glm::vec3 half, std::string name, std::vector<MeshVertex>& v, std::vector<uint32_t>& idx) {
    v.clear();
    idx.clear();
    for (int axis = 0; axis < 3; ++axis)
        for (float s : {-1.0f, 1.0f}) {
            glm::vec3 n(0.0f), u(0.0f), w(0.0f);
            n[axis] = s;
            u[(axis + 1) % 3] = 1.0f;
            w[(axis + 2) % 3] = 1.0f;
            if (s < 0) std::swap(u, w);
            const uint32_t b = uint32_t(v.size());
            for (glm::vec3 c : {n - u - w, n + u - w, n + u + w, n - u + w}) {
                const glm::vec3 p = c * half;
                v.push_back({{p.x, p.y, p.z}, {n.x, n.y, n.z}});
            }
            for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) idx.push_back(b + k);
        }
    return {v, idx, true, std::move(name)};
}

void addScene(Module& m, MeshId& quad, MeshId& box) {
    static const std::vector<MeshVertex> qv = {
        {{-8, 0, -8}, {0, 1, 0}}, {{8, 0, -8}, {0, 1, 0}}, {{8, 0, 8}, {0, 1, 0}}, {{-8, 0, 8}, {0, 1, 0}}};
    static const std::vector<uint32_t> qi = {0, 2, 1, 0, 3, 2};
    quad = m.addMesh({qv, qi, false, "ground"}).value();
    std::vector<MeshVertex> bv;
    std::vector<uint32_t> bi;
    box = m.addMesh(boxMesh(glm::vec3(1.0f), "box", bv, bi)).value();
    ASSERT_TRUE(m.addInstance(quad, glm::mat4(1.0f), glm::vec3(0.6f), false).ok());
    ASSERT_TRUE(m.addInstance(box, glm::translate(glm::mat4(1.0f), {0, 1, 0}), glm::vec3(0.5f), false).ok());
}

LightDesc spot(float x, float z) {
    LightDesc l;
    l.kind = LightKind::Spot;
    l.position = {x, 5.0f, z};
    l.direction = {0.0f, -1.0f, 0.0f};
    l.range = 9.0f;
    l.intensity = 8.0f;
    return l;
}

// The same calls on both modules; `frame` runs between them on the one under test.
void script(Module& m, const std::function<void()>& frame) {
    MeshId quad = 0, box = 0;
    addScene(m, quad, box);
    std::vector<LightId> ids;
    for (int i = 0; i < 6; ++i) ids.push_back(m.addLight(spot(-5.0f + 2.0f * i, 1.5f)).value());
    LightDesc point;
    point.kind = LightKind::Point;
    point.position = {2.0f, 3.0f, -2.0f};
    point.range = 8.0f;
    point.intensity = 6.0f;
    ids.push_back(m.addLight(point).value());
    ASSERT_TRUE(m.createTargets(64, 36).ok());
    ASSERT_TRUE(m.setCamera({{0, 9, 11}, {0, 0, 0}}).ok());
    ASSERT_TRUE(m.bakeStaticShadows(StaticMethod::SM, 64).ok()); // a load-time call: it may wait
    frame();
    frame();
    const uint64_t waits = diag::deviceWaitCount(m);
    ids.push_back(m.addLight(spot(0.0f, -3.0f)).value());
    frame();
    ASSERT_TRUE(m.removeLight(ids[2]).ok()); // a baked light
    frame();
    LightId reused = m.addLight(spot(1.0f, 3.0f)).value(); // reuses the removed light's slot
    frame();
    LightDesc dim = spot(-5.0f, 1.5f);
    dim.intensity = 3.0f;
    dim.castsShadows = false;
    ASSERT_TRUE(m.setLight(ids[0], dim).ok());
    frame();
    ASSERT_TRUE(m.setShadowFilter(1).ok());
    frame();
    InstanceId mover =
        m.addInstance(box, glm::translate(glm::mat4(1.0f), {3, 1, 2}), glm::vec3(0.8f), true).value();
    frame();
    InstanceId gone =
        m.addInstance(box, glm::translate(glm::mat4(1.0f), {-3, 1, -2}), glm::vec3(0.8f), true).value();
    frame();
    ASSERT_TRUE(m.removeInstance(gone).ok());
    ASSERT_TRUE(m.setInstanceTransform(mover, glm::translate(glm::mat4(1.0f), {3, 1, 3})).ok());
    frame();
    ASSERT_TRUE(m.removeLight(reused).ok());
    ASSERT_TRUE(m.createTargets(80, 45).ok()); // a new size: the cluster buffers are replaced, not waited on
    frame();
    EXPECT_EQ(diag::deviceWaitCount(m), waits) << "a scene change made the module wait for the device";
}

TEST(DeviceWaits, LightAndInstanceChangesWaitForNothingAndMatchAFreshFrame) {
    auto tested = makeModule();
    ASSERT_TRUE(tested);
    script(*tested, [&] { renderFrame(*tested); });
    renderFrame(*tested);
    std::vector<uint8_t> incremental, fresh;
    ASSERT_TRUE(tested->readOutput(incremental).ok());
    EXPECT_EQ(validationErrors(), 0u);
    tested.reset();

    auto once = makeModule();
    ASSERT_TRUE(once);
    script(*once, [] {});
    renderFrame(*once);
    ASSERT_TRUE(once->readOutput(fresh).ok());
    ASSERT_EQ(incremental.size(), fresh.size());
    size_t differ = 0;
    for (size_t i = 0; i < fresh.size(); ++i) differ += incremental[i] != fresh[i];
    EXPECT_EQ(differ, 0u) << "bytes differing between the incrementally updated module and a fresh one";
    EXPECT_EQ(validationErrors(), 0u);
}

// One light more costs that light's records in each slot, not every light's.
TEST(DeviceWaits, AddingOneLightRewritesOneLightsRecords) {
    auto m = makeModule();
    ASSERT_TRUE(m);
    MeshId quad = 0, box = 0;
    addScene(*m, quad, box);
    for (int i = 0; i < 64; ++i) ASSERT_TRUE(m->addLight(spot(-6.0f + 0.2f * i, 0.0f)).ok());
    ASSERT_TRUE(m->createTargets(32, 18).ok());
    ASSERT_TRUE(m->setCamera({{0, 9, 11}, {0, 0, 0}}).ok());
    ASSERT_TRUE(m->bakeStaticShadows(StaticMethod::SM, 32).ok());
    renderFrame(*m);
    renderFrame(*m); // both slots hold every record
    const uint64_t before = internals(*m).recordsWritten, waits = diag::deviceWaitCount(*m);
    ASSERT_TRUE(m->addLight(spot(0.0f, 2.0f)).ok());
    renderFrame(*m);
    renderFrame(*m);
    EXPECT_EQ(internals(*m).recordsWritten - before, 2u) << "one light's records, once per slot";
    EXPECT_EQ(diag::deviceWaitCount(*m), waits);
    EXPECT_EQ(validationErrors(), 0u);
}

// Meshes added a frame at a time: each frame stages only the new mesh's bytes (plus the whole arrays
// at each doubling of a buffer), never every mesh again, waits for nothing, and the last frame equals
// a module that added everything before its only frame. Virtual shadow maps on, so the new boxes are
// drawn into pages (and their meshlets uploaded) as well as into the G-buffer.
void meshScript(Module& m, const std::function<void()>& frame) {
    MeshId quad = 0, box = 0;
    addScene(m, quad, box);
    for (int i = 0; i < 4; ++i) ASSERT_TRUE(m.addLight(spot(-4.0f + 2.5f * i, 0.5f)).ok());
    ASSERT_TRUE(m.createTargets(64, 36).ok());
    ASSERT_TRUE(m.setCamera({{0, 9, 11}, {0, 0, 0}}).ok());
    frame();
    const uint64_t waits = diag::deviceWaitCount(m);
    for (int k = 0; k < 12; ++k) { // boxes of new sizes: a new mesh each
        const float h = 0.3f + 0.1f * float(k);
        std::vector<MeshVertex> v;
        std::vector<uint32_t> idx;
        const MeshId mesh = m.addMesh(boxMesh({0.3f, h, 0.3f}, "box_" + std::to_string(k), v, idx)).value();
        const glm::vec3 at(-5.0f + float(k % 6) * 2.0f, h, k < 6 ? -3.0f : 3.0f);
        ASSERT_TRUE(
            m.addInstance(mesh, glm::translate(glm::mat4(1.0f), at), glm::vec3(0.7f), k % 2 == 0).ok());
        frame();
    }
    EXPECT_EQ(diag::deviceWaitCount(m), waits) << "adding a mesh made the module wait for the device";
}

TEST(DeviceWaits, MeshesAddedFrameByFrameStageOnlyTheirBytes) {
    auto tested = makeModule(CullingMode::Clustered, true);
    ASSERT_TRUE(tested);
    uint32_t frames = 0;
    meshScript(*tested, [&] { renderFrame(*tested), ++frames; });
    renderFrame(*tested);
    const auto& t = internals(*tested);
    // Every byte once, plus the whole array at each doubling: at most 3x the final arrays. Re-staging
    // every mesh each frame (the upload before appending) sends about frames / 2 times them.
    const uint64_t total =
        std::accumulate(t.meshBytesUploaded.begin(), t.meshBytesUploaded.end(), uint64_t(0));
    EXPECT_GT(frames, 10u);
    EXPECT_GE(t.meshBytesStaged, total);
    EXPECT_LE(t.meshBytesStaged, 3 * total) << "mesh bytes staged again frame after frame";
    std::printf("mesh bytes: %llu in the buffers, %llu staged over %u frames\n", (unsigned long long)total,
                (unsigned long long)t.meshBytesStaged, frames);
    std::vector<uint8_t> incremental, fresh;
    ASSERT_TRUE(tested->readOutput(incremental).ok());
    EXPECT_EQ(validationErrors(), 0u);
    tested.reset();

    auto once = makeModule(CullingMode::Clustered, true);
    ASSERT_TRUE(once);
    meshScript(*once, [] {});
    renderFrame(*once);
    ASSERT_TRUE(once->readOutput(fresh).ok());
    ASSERT_EQ(incremental.size(), fresh.size());
    size_t differ = 0;
    for (size_t i = 0; i < fresh.size(); ++i) differ += incremental[i] != fresh[i];
    EXPECT_EQ(differ, 0u)
        << "bytes differing between the module that added meshes frame by frame and a fresh one";
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
