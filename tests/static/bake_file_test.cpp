// The bake file and the bake driver: round trips, deterministic bytes, damaged files (truncated, every
// byte of the header and record table flipped, data bytes flipped, corruption behind valid checksums)
// rejected with a one-line reason, and bake + verify on night-city lights for every method.
#include "static_test_util.h"

#include "scenes/scenes.h"
#include "bake/bake.h"
#include "shadows/static/static_method.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <cmath>

namespace ml::stest {
namespace {

const StaticMethod kMethods[] = {StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH, StaticMethod::DAGMH,
                                 StaticMethod::CPVS};

std::string tempPath(const std::string& name) {
    return (std::filesystem::path(testing::TempDir()) / ("bake_test_" + name)).string();
}

// Three records of synthetic maps at 64^2 (the smallest CPVS), no scene needed.
BakeFile syntheticBake(StaticMethod method) {
    BakeFile f;
    f.scene = {"night-city", 256, 7};
    f.method = method;
    f.resolution = 64;
    uint32_t lights[] = {0, 3, 5};
    for (uint32_t k = 0; k < 3; ++k) {
        BakeRecord r;
        r.light = lights[k];
        r.method = method;
        r.resolution = 64;
        r.frustum.view = glm::lookAt(glm::vec3(k, 10.0f, 1.0f), glm::vec3(k, 0.0f, 0.0f), glm::vec3(0, 1, 0));
        r.frustum.fov = 1.1f + 0.1f * float(k);
        r.frustum.nearPlane = 0.05f;
        r.frustum.farPlane = 12.0f + float(k);
        StaticEncodeOptions o;
        o.nearPlane = r.frustum.nearPlane, o.farPlane = r.frustum.farPlane;
        auto enc = encodeStatic(method, syntheticMap(64, 100 + k, k != 1), o);
        EXPECT_TRUE(enc.ok()) << enc.error();
        if (enc) r.data = enc.value();
        f.records.push_back(std::move(r));
    }
    return f;
}

std::vector<uint8_t> fileBytes(const std::string& path) {
    std::ifstream is(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(is), {});
}

void putBytes(const std::string& path, const uint8_t* data, size_t n) {
    std::ofstream os(path, std::ios::binary | std::ios::trunc);
    os.write(reinterpret_cast<const char*>(data), std::streamsize(n));
}

bool sameFrustum(const LightFrustum& a, const LightFrustum& b) {
    return a.view == b.view && a.fov == b.fov && a.nearPlane == b.nearPlane && a.farPlane == b.farPlane;
}

void expectSame(const BakeFile& a, const BakeFile& b) {
    EXPECT_EQ(a.scene.scene, b.scene.scene);
    EXPECT_EQ(a.scene.lights, b.scene.lights);
    EXPECT_EQ(a.scene.seed, b.scene.seed);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.resolution, b.resolution);
    ASSERT_EQ(a.records.size(), b.records.size());
    for (size_t i = 0; i < a.records.size(); ++i) {
        EXPECT_EQ(a.records[i].light, b.records[i].light);
        EXPECT_EQ(a.records[i].method, b.records[i].method);
        EXPECT_EQ(a.records[i].resolution, b.records[i].resolution);
        EXPECT_TRUE(sameFrustum(a.records[i].frustum, b.records[i].frustum));
        EXPECT_EQ(a.records[i].data, b.records[i].data);
    }
}

// A rejection must be one line naming the file.
void expectRejected(const Result<BakeFile>& r, const std::string& name, const std::string& what) {
    ASSERT_FALSE(r.ok()) << what << " was accepted";
    EXPECT_EQ(r.error().rfind(name + ": ", 0), 0u) << what << ": " << r.error();
    EXPECT_EQ(r.error().find('\n'), std::string::npos) << what << ": " << r.error();
}

TEST(BakeFile, RoundTripEveryMethod) {
    for (StaticMethod m : kMethods) {
        SCOPED_TRACE(staticMethodName(m));
        BakeFile f = syntheticBake(m);
        const std::string path = tempPath(std::string("roundtrip_") + staticMethodName(m));
        ASSERT_TRUE(writeBakeFile(path, f).ok());
        auto back = readBakeFile(path);
        ASSERT_TRUE(back.ok()) << back.error();
        expectSame(f, back.value());
        // The byte parts add up to the file size.
        std::vector<BakeRecordBytes> per;
        EXPECT_EQ(bakeFileBytes(back.value(), &per).total(), std::filesystem::file_size(path));
        EXPECT_EQ(per.size(), 3u);
    }
}

TEST(BakeFile, SameInputSameBytes) {
    BakeFile f = syntheticBake(StaticMethod::DAGMH);
    const std::string a = tempPath("same_a"), b = tempPath("same_b");
    ASSERT_TRUE(writeBakeFile(a, f).ok());
    ASSERT_TRUE(writeBakeFile(b, syntheticBake(StaticMethod::DAGMH)).ok());
    EXPECT_EQ(fileBytes(a), fileBytes(b));
    // A scene string whose length is not a multiple of 4 has zero padding, not leftovers.
    f.scene.scene = "abcde";
    auto w1 = serializeBakeFile(f);
    f.scene.scene = "abcdx";
    auto w2 = serializeBakeFile(f);
    ASSERT_TRUE(w1.ok() && w2.ok());
    EXPECT_EQ(reinterpret_cast<const uint8_t*>(&w1.value()[bakefmt::kFixedHeaderWords])[5], 0u);
    EXPECT_EQ(reinterpret_cast<const uint8_t*>(&w2.value()[bakefmt::kFixedHeaderWords])[7], 0u);
}

TEST(BakeFile, TruncatedAtEveryWordAndManyBytesRejected) {
    for (StaticMethod m : kMethods) {
        SCOPED_TRACE(staticMethodName(m));
        auto words = serializeBakeFile(syntheticBake(m));
        ASSERT_TRUE(words.ok());
        const std::vector<uint32_t>& w = words.value();
        for (size_t cut = 0; cut < w.size(); ++cut)
            expectRejected(parseBakeFile("cut", w.data(), cut), "cut", "cut at word " + std::to_string(cut));
        // Byte-level cuts through the file reader (sizes that are not whole words too), and an extension.
        const std::string path = tempPath("truncated");
        const uint8_t* bytes = reinterpret_cast<const uint8_t*>(w.data());
        const size_t n = w.size() * 4, header = w[bakefmt::kHHeaderWords] * 4,
                     table = header + w[bakefmt::kHRecordCount] * bakefmt::kRecordWords * 4;
        for (size_t cut :
             {size_t(0), size_t(1), size_t(3), size_t(5), size_t(63), size_t(64), header - 1, header,
              header + 1, table - 2, table, table + 3, n / 2, n / 2 + 1, n - 4, n - 3, n - 1}) {
            putBytes(path, bytes, cut);
            expectRejected(readBakeFile(path), path, "cut at byte " + std::to_string(cut));
        }
        std::vector<uint8_t> longer(bytes, bytes + n);
        longer.insert(longer.end(), {0, 0, 0, 0});
        putBytes(path, longer.data(), longer.size());
        expectRejected(readBakeFile(path), path, "4 extra bytes");
    }
    expectRejected(readBakeFile(tempPath("does_not_exist")), tempPath("does_not_exist"), "missing file");
}

TEST(BakeFile, EveryHeaderAndTableByteFlipRejected) {
    for (StaticMethod m : kMethods) {
        SCOPED_TRACE(staticMethodName(m));
        auto words = serializeBakeFile(syntheticBake(m));
        ASSERT_TRUE(words.ok());
        std::vector<uint32_t> w = words.value();
        const size_t table =
            (w[bakefmt::kHHeaderWords] + w[bakefmt::kHRecordCount] * bakefmt::kRecordWords) * 4;
        uint8_t* bytes = reinterpret_cast<uint8_t*>(w.data());
        for (size_t i = 0; i < table; ++i)
            for (uint8_t flip : {0x01, 0x80, 0xFF}) {
                bytes[i] ^= flip;
                expectRejected(parseBakeFile("flip", w.data(), w.size()), "flip",
                               "byte " + std::to_string(i) + " ^ " + std::to_string(flip));
                bytes[i] ^= flip;
            }
        // A sample of data bytes: the data checksum catches every one.
        const size_t n = w.size() * 4;
        for (size_t i = table, k = 0; i < n; i += 1 + (k++ * 7919) % 97) {
            bytes[i] ^= 0x10;
            expectRejected(parseBakeFile("flip", w.data(), w.size()), "flip",
                           "data byte " + std::to_string(i));
            bytes[i] ^= 0x10;
        }
        EXPECT_TRUE(parseBakeFile("flip", w.data(), w.size()).ok()); // restored
    }
}

TEST(BakeFile, RechecksummedCorruptionCaughtByValidateStatic) {
    // Damage inside a record's data, then let the writer compute fresh bake-file checksums: only
    // validateStatic (the format's own checks) stands between the file and an out-of-bounds lookup.
    BakeFile f = syntheticBake(StaticMethod::MH);
    std::vector<uint32_t>& d = f.records[1].data;
    d[mhfmt::kNodeOffset] = 0xFFFFFF00u; // the node region far outside the buffer
    auto w = serializeBakeFile(f);
    ASSERT_TRUE(w.ok());
    auto r = parseBakeFile("x", w->data(), w->size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("x: record 1: MH"), std::string::npos) << r.error();
    // The same with the format's own checksum recomputed: the structural checks must catch it.
    d[mhfmt::kChecksum] = stat::checksumWords(d.data(), d.size(), mhfmt::kChecksum);
    w = serializeBakeFile(f);
    r = parseBakeFile("x", w->data(), w->size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("x: record 1: MH"), std::string::npos) << r.error();
    EXPECT_EQ(r.error().find("checksum"), std::string::npos) << r.error();
    // The writer refuses to put such a file on disk.
    const std::string path = tempPath("refused");
    std::filesystem::remove(path);
    EXPECT_FALSE(writeBakeFile(path, f).ok());
    EXPECT_FALSE(std::filesystem::exists(path));

    // CPVS: the stored depth range must be the record's frustum's.
    BakeFile c = syntheticBake(StaticMethod::CPVS);
    c.records[2].frustum.farPlane += 1.0f;
    w = serializeBakeFile(c);
    r = parseBakeFile("c", w->data(), w->size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("c: record 2:"), std::string::npos) << r.error();
}

TEST(BakeFile, InconsistentRecordsRejected) {
    auto reject = [](BakeFile f, const char* what) {
        auto w = serializeBakeFile(f);
        if (!w) return; // refused outright: fine
        EXPECT_FALSE(parseBakeFile("i", w->data(), w->size()).ok()) << what;
    };
    BakeFile f = syntheticBake(StaticMethod::DAGMH);
    BakeFile g = f;
    g.records[1].light = 0;
    reject(g, "duplicate light");
    g = f, g.records[2].light = 256;
    reject(g, "light beyond the scene's lights");
    g = f, g.records[0].method = StaticMethod::MH;
    reject(g, "record method differs");
    g = f, g.records[0].resolution = 128;
    reject(g, "record resolution differs");
    g = f, g.resolution = 128;
    for (auto& r : g.records) r.resolution = 128;
    reject(g, "data resolution differs");
    g = f, g.records[1].frustum.fov = std::nanf("");
    reject(g, "NaN fov");
    g = f, g.records[1].frustum.view[2][1] = INFINITY;
    reject(g, "infinite matrix");
    g = f, g.records[1].frustum.view[0][0] *= 2.0f;
    reject(g, "scaled view (not a rigid motion)");
    g = f, g.records[1].frustum.view[2][3] = -1.0f;
    reject(g, "projective view");
    g = f, g.records[1].frustum.nearPlane = 20.0f;
    reject(g, "near beyond far");
    g = f, g.records[1].data.clear();
    reject(g, "empty data");
    g = f, g.scene.scene = "";
    reject(g, "empty scene");
    g = f, g.scene.lights = 0;
    reject(g, "no scene lights");
}

TEST(BakeLights, SelectionParsing) {
    auto sel = [](const char* s, uint32_t n) { return parseLightSelection(s, n); };
    EXPECT_EQ(sel("all", 4).value(), (std::vector<uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(sel("3", 8).value(), (std::vector<uint32_t>{3}));
    EXPECT_EQ(sel("0-7", 8).value(), (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7}));
    EXPECT_EQ(sel("5,0-2,1", 8).value(), (std::vector<uint32_t>{0, 1, 2, 5}));
    for (const char* bad :
         {"", "x", "8", "0-8", "3-1", "-3", "2-", "1,,2", "1,", "1 ", "+1", "99999999999", "0x3"}) {
        auto r = sel(bad, 8);
        EXPECT_FALSE(r.ok()) << "'" << bad << "'";
        if (!r.ok()) {
            EXPECT_EQ(r.error().rfind("--lights: ", 0), 0u) << r.error();
        }
    }
    EXPECT_NE(sel("9", 8).error().find("out of range"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------------
// The driver on the night city

class BakeScene : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        auto s = loadScene(spec_.scene, spec_.lights, spec_.seed);
        ASSERT_TRUE(s.ok()) << s.error();
        scene_ = new Scene(std::move(s.value()));
    }
    static void TearDownTestSuite() { delete scene_, scene_ = nullptr; }
    static std::vector<uint32_t> staticSpots(size_t count) {
        std::vector<uint32_t> out;
        for (uint32_t i = 0; i < scene_->lights.size() && out.size() < count; ++i)
            if (!scene_->lights[i].dynamic && scene_->lights[i].type == LightKind::Spot) out.push_back(i);
        return out;
    }
    static inline SceneSpec spec_{"night-city", 256, 1};
    static inline Scene* scene_ = nullptr;
};

TEST_F(BakeScene, EveryMethodVerifiesWithZeroMismatches) {
    const std::vector<uint32_t> lights = staticSpots(4);
    ASSERT_EQ(lights.size(), 4u);
    for (StaticMethod m : kMethods) {
        SCOPED_TRACE(staticMethodName(m));
        auto baked = bakeScene(*scene_, spec_, m, 512, lights);
        ASSERT_TRUE(baked.ok()) << baked.error();
        ASSERT_EQ(baked->file.records.size(), 4u);
        EXPECT_TRUE(baked->skipped.empty());
        // Through the disk, as `verify` sees it.
        const std::string path = tempPath(std::string("city_") + staticMethodName(m));
        ASSERT_TRUE(writeBakeFile(path, baked->file).ok());
        auto file = readBakeFile(path);
        ASSERT_TRUE(file.ok()) << file.error();
        auto rep = verifyBakeScene(file.value(), *scene_);
        ASSERT_TRUE(rep.ok()) << rep.error();
        EXPECT_EQ(rep->mismatches, 0u);
        for (const std::string& e : rep->examples) ADD_FAILURE() << e;
        if (m == StaticMethod::CPVS)
            EXPECT_EQ(rep->checked + rep->undefined, 4ull * 512 * 512 * 512);
        else
            EXPECT_EQ(rep->checked, 4ull * 512 * 512);
        std::printf("  [bake] %-5s 4 lights 512^2: %llu bytes, render %.2f s, encode %.2f s\n",
                    staticMethodName(m), (unsigned long long)bakeFileBytes(file.value()).total(),
                    baked->renderSeconds, baked->encodeSeconds);
    }
}

TEST_F(BakeScene, VerifyReloadsTheSceneAndSameBakeSameBytes) {
    const std::vector<uint32_t> lights = staticSpots(2);
    auto a = bakeScene(*scene_, spec_, StaticMethod::DAGMH, 256, lights);
    auto b = bakeScene(*scene_, spec_, StaticMethod::DAGMH, 256, {lights[1], lights[0], lights[1]});
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(serializeBakeFile(a->file).value(), serializeBakeFile(b->file).value());
    auto rep = verifyBake(a->file); // loads the scene from the file's spec
    ASSERT_TRUE(rep.ok()) << rep.error();
    EXPECT_EQ(rep->mismatches, 0u);
    EXPECT_EQ(rep->checked, 2ull * 256 * 256);
}

TEST_F(BakeScene, VerifyCountsWrongTexels) {
    // A texel changed to a depth outside its interval (SM, its own checksum redone) must be counted.
    auto baked = bakeScene(*scene_, spec_, StaticMethod::SM, 128, staticSpots(1));
    ASSERT_TRUE(baked.ok()) << baked.error();
    std::vector<uint32_t>& d = baked->file.records[0].data;
    const size_t texel = smfmt::kHeaderWords + 64 * 128 + 64;
    d[texel] = d[texel] == 0 ? 1u : 0u;
    d[smfmt::kChecksum] = stat::checksumWords(d.data(), d.size(), smfmt::kChecksum);
    auto rep = verifyBakeScene(baked->file, *scene_);
    ASSERT_TRUE(rep.ok()) << rep.error();
    EXPECT_EQ(rep->mismatches, 1u);
    ASSERT_EQ(rep->examples.size(), 1u);
    EXPECT_NE(rep->examples[0].find("texel (64, 64)"), std::string::npos) << rep->examples[0];
}

TEST_F(BakeScene, VerifyRejectsAChangedScene) {
    auto baked = bakeScene(*scene_, spec_, StaticMethod::MH, 64, staticSpots(1));
    ASSERT_TRUE(baked.ok()) << baked.error();
    Scene moved = *scene_;
    moved.lights[baked->file.records[0].light].position.y += 0.5f;
    auto rep = verifyBakeScene(baked->file, moved);
    ASSERT_FALSE(rep.ok());
    EXPECT_NE(rep.error().find("frustum differs"), std::string::npos) << rep.error();
}

TEST_F(BakeScene, SkippedLightsAreReported) {
    Scene s = *scene_;
    std::vector<uint32_t> dynamicLights;
    for (uint32_t i = 0; i < s.lights.size(); ++i)
        if (s.lights[i].dynamic) dynamicLights.push_back(i);
    ASSERT_FALSE(dynamicLights.empty()) << "the night city should have car headlights";
    const std::vector<uint32_t> spots = staticSpots(3);
    s.lights[spots[1]].type = LightKind::Point;
    s.lights[spots[2]].type = LightKind::Directional;
    std::vector<uint32_t> sel = {spots[0], spots[1], spots[2], dynamicLights[0]};
    auto baked = bakeScene(s, spec_, StaticMethod::MH, 64, sel);
    ASSERT_TRUE(baked.ok()) << baked.error();
    // The spot bakes one map, the point light one per cube face, the directional light one
    // orthographic map over the scene bounds; the dynamic light is skipped with its reason.
    ASSERT_EQ(baked->file.records.size(), 8u);
    EXPECT_EQ(baked->file.records[0].light, spots[0]);
    for (uint32_t f = 0; f < 6; ++f) {
        EXPECT_EQ(baked->file.records[1 + f].light, spots[1]);
        EXPECT_EQ(baked->file.records[1 + f].face, f);
    }
    EXPECT_EQ(baked->file.records[7].light, spots[2]);
    EXPECT_TRUE(baked->file.records[7].frustum.orthographic());
    ASSERT_EQ(baked->skipped.size(), 1u);
    EXPECT_NE(baked->skipped[0].reason.find("dynamic"), std::string::npos);
    // Nothing bakeable: an error naming a skipped light, not an empty file.
    auto none = bakeScene(s, spec_, StaticMethod::MH, 64, {dynamicLights[0]});
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().find("dynamic"), std::string::npos) << none.error();
    EXPECT_FALSE(bakeScene(s, spec_, StaticMethod::MH, 64, {uint32_t(s.lights.size())}).ok());
    EXPECT_FALSE(bakeScene(s, spec_, StaticMethod::CPVS, 100, {spots[0]}).ok()); // not a power of two
}

TEST_F(BakeScene, PluggableRendererIsUsedAndChecked) {
    // A renderer that returns the wrong size fails the bake with a reason (the lead's GPU path goes here).
    uint32_t calls = 0;
    DualRenderFn cpu = cpuDualRenderer(1u << 14);
    DualRenderFn counting = [&](const CasterTriangles& c, const LightFrustum& f, uint32_t res) {
        ++calls;
        return cpu(c, f, res);
    };
    auto baked = bakeScene(*scene_, spec_, StaticMethod::MMH, 128, staticSpots(2), {}, counting);
    ASSERT_TRUE(baked.ok()) << baked.error();
    EXPECT_EQ(calls, 2u);
    auto rep = verifyBakeScene(baked->file, *scene_, counting);
    ASSERT_TRUE(rep.ok());
    EXPECT_EQ(rep->mismatches, 0u);
    EXPECT_EQ(calls, 4u);
    DualRenderFn wrong = [](const CasterTriangles&, const LightFrustum&, uint32_t) -> Result<DualDepthMap> {
        return emptyMap(8);
    };
    EXPECT_FALSE(bakeScene(*scene_, spec_, StaticMethod::MMH, 128, staticSpots(1), {}, wrong).ok());
}

} // namespace
} // namespace ml::stest
