// Resolution from need (bake/need.h) and the need block of bake files (version 2): the
// estimator against a hand-computed footprint, lights near and far, a light with no caster, the cap and
// the minimum, a box region, frustum and occlusion tests; need-based files round-trip, forged need
// blocks are refused, and a need-based bake of night-city lights verifies lossless at every texel.
#include "static_test_util.h"

#include "scenes/mesh_utils.h"
#include "scenes/scenes.h"
#include "bake/bake.h"
#include "bake/need.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace ml::stest {
namespace {

// A 200 m ground quad at y = 0 and a closed 1 m box at (x, 0, 0) for each x in boxes.
Scene groundScene(const std::vector<float>& boxes) {
    Scene s;
    s.name = "need-test";
    s.meshes.push_back(detail::makeUnitQuad());
    s.meshes.push_back(detail::makeUnitBox());
    s.meshes[1].closed = true;
    Instance ground;
    ground.mesh = 0;
    ground.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -100)) *
                       glm::scale(glm::mat4(1.0f), glm::vec3(200, 1, 200));
    s.instances.push_back(ground);
    for (float x : boxes) {
        Instance b;
        b.mesh = 1;
        b.transform = glm::translate(glm::mat4(1.0f), glm::vec3(x, 0, 0));
        s.instances.push_back(b);
    }
    updateBounds(s);
    return s;
}

Light spotAt(glm::vec3 p, glm::vec3 dir = {0, -1, 0}) {
    Light l;
    l.type = LightKind::Spot;
    l.position = p;
    l.direction = glm::normalize(dir);
    l.range = 12.0f;
    l.outerAngle = 0.6f, l.innerAngle = 0.4f;
    return l;
}

NeedCamera cameraAt(glm::vec3 p) {
    NeedCamera c;
    c.position = p;
    c.anyDirection = true;
    c.fovY = 1.0f, c.aspect = 16.0f / 9.0f;
    return c;
}

const LightNeed& needOf(const std::vector<LightNeed>& v, uint32_t light) {
    for (const LightNeed& n : v)
        if (n.light == light) return n;
    static LightNeed none;
    ADD_FAILURE() << "light " << light << " missing";
    return none;
}

// A camera 2 m above the ground straight under a spot 8 m up, no box: the closest receiver is the
// ground point below the camera (depth 2 m), where the map spans 2 * 8 * tan(fov/2) and one pixel
// 2 * 2 * tan(0.5) / 720. The estimate equals their ratio within the receiver grid's spacing.
TEST(Need, FootprintMatchesHandComputedRatio) {
    Scene s = groundScene({});
    s.lights.push_back(spotAt({0, 8, 0}));
    NeedOptions o;
    o.width = 1280, o.height = 720, o.minRes = 16, o.maxRes = 65536;
    auto n = estimateNeed(s, {0}, {cameraAt({0, 2, 0})}, o);
    ASSERT_TRUE(n.ok()) << n.error();
    const float fov = bakeFrustums(s, s.lights[0])[0].fov;
    const double expected = (2.0 * 8.0 * std::tan(0.5 * fov)) / (2.0 * 2.0 * std::tan(0.5) / 720.0);
    const LightNeed& l = n->front();
    EXPECT_EQ(l.reason, NeedReason::Footprint);
    EXPECT_NEAR(l.needed, expected, 0.01 * expected);
    EXPECT_NEAR(l.distance, 2.0f, 0.02f);
    uint32_t pow2 = 1;
    while (pow2 < expected) pow2 <<= 1;
    EXPECT_EQ(l.resolution, pow2);
    EXPECT_GT(l.receivers, 100u);
    EXPECT_EQ(l.seen, l.receivers);
}

// Two equal lamps, the camera beside one: the far one (40 m away) needs far less.
TEST(Need, FarLightGetsLowerResolutionThanNearOne) {
    Scene s = groundScene({0.0f, 40.0f});
    s.lights.push_back(spotAt({0, 6, 1}));
    s.lights.push_back(spotAt({40, 6, 1}));
    NeedOptions o;
    o.minRes = 16, o.maxRes = 16384;
    auto n = estimateNeed(s, {0, 1}, {cameraAt({0, 1.7f, 4})}, o);
    ASSERT_TRUE(n.ok()) << n.error();
    const LightNeed &a = needOf(*n, 0), &b = needOf(*n, 1);
    EXPECT_EQ(a.reason, NeedReason::Footprint);
    EXPECT_EQ(b.reason, NeedReason::Footprint);
    EXPECT_GE(a.resolution, 4 * b.resolution) << a.needed << " vs " << b.needed;
    EXPECT_GT(b.distance, 30.0f);
}

// A lamp shining up into an empty sky has nothing in its volume: no structure.
TEST(Need, NoCasterInVolumeGetsNone) {
    Scene s = groundScene({});
    s.lights.push_back(spotAt({0, 3, 0}, {0, 1, 0}));
    s.lights.push_back(spotAt({0, 3, 0}, {0, -1, 0}));
    auto n = estimateNeed(s, {0, 1}, {cameraAt({0, 1.7f, 3})}, {});
    ASSERT_TRUE(n.ok()) << n.error();
    EXPECT_EQ(needOf(*n, 0).reason, NeedReason::NoCaster);
    EXPECT_EQ(needOf(*n, 0).resolution, 0u);
    EXPECT_EQ(needOf(*n, 0).receivers, 0u);
    EXPECT_NE(needOf(*n, 1).reason, NeedReason::NoCaster);
    EXPECT_GT(needOf(*n, 1).resolution, 0u);
    EXPECT_EQ(needReasonText(needOf(*n, 0), 1), "no caster in its volume: not baked");
    // The same lamp shining up at a box 3 m above it (the box's underside faces the lamp) has a caster.
    Scene t = groundScene({});
    Instance box;
    box.mesh = 1;
    box.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0, 6, 0));
    t.instances.push_back(box);
    updateBounds(t);
    t.lights.push_back(spotAt({0, 3, 0}, {0, 1, 0}));
    n = estimateNeed(t, {0}, {cameraAt({0, 1.7f, 3})}, {});
    ASSERT_TRUE(n.ok()) << n.error();
    EXPECT_NE(n->front().reason, NeedReason::NoCaster);
    EXPECT_GT(n->front().resolution, 0u);
    EXPECT_GT(n->front().receivers, 0u);
}

TEST(Need, CapAndMinimumRespected) {
    Scene s = groundScene({});
    s.lights.push_back(spotAt({0, 8, 0}));
    NeedOptions o;
    o.minRes = 64, o.maxRes = 512;
    auto close = estimateNeed(s, {0}, {cameraAt({0, 0.5f, 0})}, o); // needs thousands
    ASSERT_TRUE(close.ok());
    EXPECT_EQ(close->front().reason, NeedReason::Capped);
    EXPECT_EQ(close->front().resolution, 512u);
    EXPECT_GT(close->front().needed, 512.0f);
    EXPECT_NE(needReasonText(close->front(), 1).find("capped at 512"), std::string::npos);
    o.minRes = 4096, o.maxRes = 8192;
    auto low = estimateNeed(s, {0}, {cameraAt({0, 60.0f, 0})}, o); // 60 m up: a few hundred
    ASSERT_TRUE(low.ok());
    EXPECT_EQ(low->front().reason, NeedReason::Floor);
    EXPECT_EQ(low->front().resolution, 4096u);
    o.minRes = 0;
    EXPECT_FALSE(estimateNeed(s, {0}, {cameraAt({0, 1, 0})}, o).ok());
    EXPECT_FALSE(estimateNeed(s, {0}, {}, NeedOptions{}).ok());                    // no camera sample
    EXPECT_FALSE(estimateNeed(s, {5}, {cameraAt({0, 1, 0})}, NeedOptions{}).ok()); // no such light
}

// A box region: a grid of positions; the need follows the box's corner closest to the light.
TEST(Need, BoxRegion) {
    auto cams = boxCameras({-1, 1, -1}, {1, 3, 1}, 3, 1.0f, 0.1f, 500.0f);
    ASSERT_EQ(cams.size(), 27u);
    EXPECT_EQ(cams[0].position, glm::vec3(-1, 1, -1));
    EXPECT_EQ(cams[26].position, glm::vec3(1, 3, 1));
    EXPECT_EQ(cams[13].position, glm::vec3(0, 2, 0));
    ASSERT_EQ(boxCameras({0, 0, 0}, {2, 2, 2}, 1, 1.0f, 0.1f, 500.0f)[0].position, glm::vec3(1, 1, 1));
    Scene s = groundScene({});
    s.lights.push_back(spotAt({0, 8, 0}));
    NeedOptions o;
    o.minRes = 16, o.maxRes = 65536;
    auto inBox = estimateNeed(s, {0}, cams, o);
    auto centreOnly = estimateNeed(s, {0}, {cams[13]}, o);
    ASSERT_TRUE(inBox.ok() && centreOnly.ok());
    // The lowest layer (1 m above the ground) decides: twice the need of the centre (2 m).
    EXPECT_NEAR(inBox->front().needed, 2.0f * centreOnly->front().needed, 0.03f * centreOnly->front().needed);
    EXPECT_NEAR(inBox->front().distance, 1.0f, 0.02f);
}

// A path camera looking away from the light sees none of its receivers; an occluder between camera and
// receivers (the visibility callback) pushes the need to receivers farther away or to none.
TEST(Need, FrustumAndOcclusion) {
    Scene s = groundScene({});
    s.lights.push_back(spotAt({0, 8, 0}));
    NeedCamera away;
    away.position = {0, 2, 30};
    away.forward = {0, 0, 1}; // looking away from the lamp at z = 0
    NeedOptions o;
    o.minRes = 64, o.maxRes = 65536;
    auto n = estimateNeed(s, {0}, {away}, o);
    ASSERT_TRUE(n.ok());
    EXPECT_EQ(n->front().reason, NeedReason::NotSeen);
    EXPECT_EQ(n->front().resolution, 64u);
    EXPECT_EQ(n->front().seen, 0u);
    NeedCamera towards = away;
    towards.forward = glm::normalize(glm::vec3(0, -2, -30));
    n = estimateNeed(s, {0}, {towards}, o);
    ASSERT_TRUE(n.ok());
    EXPECT_EQ(n->front().reason, NeedReason::Footprint);
    const float open = n->front().needed;
    // A wall hiding the near half of the cone (only receivers with z < 0 visible): the need drops.
    o.visible = [](const glm::vec3&, const glm::vec3& p) { return p.z < 0.0f; };
    n = estimateNeed(s, {0}, {towards}, o);
    ASSERT_TRUE(n.ok());
    EXPECT_EQ(n->front().reason, NeedReason::Footprint);
    EXPECT_LT(n->front().needed, open);
    EXPECT_GT(n->front().rays, 0u);
    o.visible = [](const glm::vec3&, const glm::vec3&) { return false; };
    n = estimateNeed(s, {0}, {towards}, o);
    ASSERT_TRUE(n.ok());
    EXPECT_EQ(n->front().reason, NeedReason::NotSeen);
    EXPECT_GT(n->front().seen, 0u);
    // A ray budget of 1: the second candidate is taken unoccluded, and flagged.
    o.maxRaysPerLight = 1;
    n = estimateNeed(s, {0}, {towards}, o);
    ASSERT_TRUE(n.ok());
    EXPECT_TRUE(n->front().raysCapped);
    EXPECT_EQ(n->front().reason, NeedReason::Footprint);
}

BakeFile needFile() {
    BakeFile f;
    f.scene = {"night-city", 256, 7};
    f.method = StaticMethod::DAGMH;
    f.resolution = 128;
    f.hasNeed = true;
    f.need.region = "box:0,0,0,1,1,1, 2^3 positions";
    f.need.width = 320, f.need.height = 180, f.need.minRes = 64, f.need.maxRes = 128, f.need.samples = 8;
    const uint32_t res[] = {128, 64, 0};
    const NeedReason why[] = {NeedReason::Capped, NeedReason::Footprint, NeedReason::NoCaster};
    for (uint32_t k = 0; k < 3; ++k) {
        LightNeed n;
        n.light = 2 * k, n.resolution = res[k], n.reason = why[k], n.distance = 3.0f + k, n.sample = k;
        n.needed = 100.0f * float(k + 1), n.receivers = 50, n.seen = 40;
        if (k == 2) n = LightNeed{4, 0, NeedReason::NoCaster};
        f.need.lights.push_back(n);
        if (!res[k]) continue;
        BakeRecord r;
        r.light = 2 * k, r.method = f.method, r.resolution = res[k];
        r.frustum.view = glm::lookAt(glm::vec3(k, 10.0f, 1.0f), glm::vec3(k, 0.0f, 0.0f), glm::vec3(0, 1, 0));
        r.frustum.fov = 1.1f, r.frustum.nearPlane = 0.05f, r.frustum.farPlane = 12.0f;
        auto enc = encodeStatic(f.method, syntheticMap(res[k], 100 + k, true), {0.05f, 12.0f, {}, nullptr});
        EXPECT_TRUE(enc.ok());
        if (enc) r.data = enc.value();
        f.records.push_back(std::move(r));
    }
    return f;
}

TEST(Need, FileRoundTripAndVersions) {
    BakeFile f = needFile();
    auto w = serializeBakeFile(f);
    ASSERT_TRUE(w.ok()) << w.error();
    EXPECT_EQ(w.value()[bakefmt::kHVersion], 2u);
    auto back = parseBakeFile("need", w->data(), w->size());
    ASSERT_TRUE(back.ok()) << back.error();
    ASSERT_TRUE(back->hasNeed);
    EXPECT_EQ(back->need.region, f.need.region);
    EXPECT_EQ(back->need.samples, 8u);
    ASSERT_EQ(back->need.lights.size(), 3u);
    EXPECT_EQ(back->need.lights[1].resolution, 64u);
    EXPECT_EQ(back->need.lights[1].needed, 200.0f);
    EXPECT_EQ(back->need.lights[2].reason, NeedReason::NoCaster);
    EXPECT_EQ(back->records[1].resolution, 64u);
    EXPECT_EQ(bakeFileBytes(back.value()).total(), w->size() * 4);
    // Without a need block the file is version 1, as before version 2 existed.
    f.hasNeed = false;
    f.records.pop_back();
    auto v1 = serializeBakeFile(f);
    ASSERT_TRUE(v1.ok());
    EXPECT_EQ(v1.value()[bakefmt::kHVersion], 1u);
    EXPECT_TRUE(parseBakeFile("v1", v1->data(), v1->size()).ok());
}

// Forged need blocks with valid checksums are refused with one line.
TEST(Need, ForgedNeedBlocksRefused) {
    auto refused = [](BakeFile f, const char* what, const char* expect) {
        auto w = serializeBakeFile(f);
        if (!w.ok()) return; // refused before writing: fine too
        auto r = parseBakeFile("forged", w->data(), w->size());
        ASSERT_FALSE(r.ok()) << what;
        EXPECT_NE(r.error().find(expect), std::string::npos) << what << ": " << r.error();
        EXPECT_EQ(r.error().find('\n'), std::string::npos);
    };
    BakeFile f = needFile();
    BakeFile g = f;
    g.need.lights[1].resolution = 128; // record says 64
    refused(g, "entry resolution differs from record", "differs from its need entry");
    g = f, g.need.lights[0].resolution = 0; // record present but 'not baked'
    refused(g, "resolution 0 with a record", "resolution 0");
    g = f, g.need.lights[2] = LightNeed{4, 64, NeedReason::Footprint}; // a resolution, no record
    refused(g, "entry without record", "has a resolution but no record");
    g = f, std::swap(g.need.lights[0], g.need.lights[1]);
    refused(g, "entries out of order", "increasing order");
    g = f, g.need.maxRes = 256;
    refused(g, "cap differs from header", "maximum must be");
    g = f, g.need.lights[1].reason = NeedReason(9);
    refused(g, "unknown reason", "unknown reason");
    g = f, g.need.lights[1].resolution = 32; // below the minimum (and the record's)
    refused(g, "below minimum", "outside the range");
    // A version 1 header with need words: refused.
    auto w = serializeBakeFile(f);
    ASSERT_TRUE(w.ok());
    std::vector<uint32_t> v = w.value();
    v[bakefmt::kHVersion] = 1;
    v[bakefmt::kHChecksum] = stat::checksumWords(v.data(), v[bakefmt::kHHeaderWords], bakefmt::kHChecksum);
    auto r = parseBakeFile("v1need", v.data(), v.size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("reserved word is not 0"), std::string::npos) << r.error();
    v[bakefmt::kHVersion] = 4; // past the newest (3: directional records fitted to their box)
    v[bakefmt::kHChecksum] = stat::checksumWords(v.data(), v[bakefmt::kHHeaderWords], bakefmt::kHChecksum);
    r = parseBakeFile("v4", v.data(), v.size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("unsupported version 4"), std::string::npos) << r.error();
}

// Need-based bake of night-city lights at small resolutions (a box region, CPU rasteriser), then
// verify: every texel of every record lossless, for a depth method and CPVS (every voxel).
TEST(Need, BakeAndVerifyLossless) {
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    // A box around the ground under light 0: it needs the cap, lights far from it the minimum.
    const glm::vec3 c = scene->lights[0].position * glm::vec3(1, 0, 1);
    auto cams =
        boxCameras(c + glm::vec3(-1, 1.5f, -1), c + glm::vec3(1, 2, 1), 2, scene->camera.fovY, 0.1f, 500.0f);
    NeedOptions o;
    o.width = 160, o.height = 90, o.minRes = 64, o.maxRes = 128;
    auto need = estimateNeed(scene.value(), {0, 1, 2, 100, 200}, cams, o);
    ASSERT_TRUE(need.ok()) << need.error();
    BakeNeed bn;
    bn.region = "box test", bn.width = 160, bn.height = 90, bn.minRes = 64, bn.maxRes = 128;
    bn.samples = uint32_t(cams.size());
    bn.lights = need.value();
    bool differ = false;
    for (const LightNeed& l : bn.lights) {
        differ |= l.resolution != bn.lights[0].resolution;
        std::printf("  light %u: %s\n", l.light, needReasonText(l, bn.samples).c_str());
    }
    EXPECT_TRUE(differ) << "every light got the same resolution: the test would not see per-light sizes";
    for (StaticMethod m : {StaticMethod::DAGMH, StaticMethod::CPVS}) {
        SCOPED_TRACE(staticMethodName(m));
        auto baked = bakeSceneNeed(scene.value(), {"night-city", 256, 1}, m, bn, {0, 1, 2, 100, 200, 255});
        ASSERT_TRUE(baked.ok()) << baked.error();
        // Light 255 is a car's headlight (dynamic): listed as skipped, not dropped.
        ASSERT_EQ(baked->skipped.size(), 1u);
        EXPECT_EQ(baked->skipped[0].light, 255u);
        // A selected bakeable light without a need entry is an error, not a silent omission.
        EXPECT_FALSE(bakeSceneNeed(scene.value(), {"night-city", 256, 1}, m, bn, {0, 3}).ok());
        auto w = serializeBakeFile(baked->file);
        ASSERT_TRUE(w.ok()) << w.error();
        auto back = parseBakeFile("need", w->data(), w->size());
        ASSERT_TRUE(back.ok()) << back.error();
        for (const BakeRecord& r : back->records)
            for (const LightNeed& l : bn.lights)
                if (l.light == r.light) {
                    EXPECT_EQ(r.resolution, l.resolution);
                }
        auto rep = verifyBakeScene(back.value(), scene.value());
        ASSERT_TRUE(rep.ok()) << rep.error();
        EXPECT_EQ(rep->mismatches, 0u);
        uint64_t texels = 0;
        for (const BakeRecord& r : back->records) texels += uint64_t(r.resolution) * r.resolution;
        if (m != StaticMethod::CPVS) {
            EXPECT_EQ(rep->checked, texels);
        }
        EXPECT_GT(rep->checked, 0u);
    }
}

} // namespace
} // namespace ml::stest
