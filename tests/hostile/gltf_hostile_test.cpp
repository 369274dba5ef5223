// Hostile glTF files: deep JSON nesting, buffer URIs that leave the scene's
// folder ('..', absolute paths, symlinks), messages that would echo file bytes or whole data URIs, and
// KHR_lights_punctual parameters out of range.
#include "hostile_test_util.h"

#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <fstream>

#include <cstring>

namespace ml {
namespace {

namespace fs = std::filesystem;
using hostile::tempDir;

// A scene folder with `scene/` inside and a "secret" file beside it (outside the scene's folder).
struct Layout {
    fs::path root, scene, secret;
    Layout() {
        root = tempDir() / "uri";
        fs::remove_all(root);
        scene = root / "scene";
        fs::create_directories(scene / "sub");
        secret = root / "secret.bin";
        hostile::writeBytes(secret.string(), hostile::tetraBin()); // a valid buffer: only the folder is wrong
        hostile::writeBytes((scene / "sub" / "tetra.bin").string(), hostile::tetraBin());
    }
    std::string write(const std::string& name, const std::string& bytes) const {
        const std::string p = (scene / name).string();
        hostile::writeBytes(p, bytes);
        return p;
    }
};

void expectRefused(const Result<Scene>& r, const std::string& needle) {
    ASSERT_FALSE(r.ok()) << "loaded";
    EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
    EXPECT_NE(r.error().find(needle), std::string::npos) << r.error();
}

TEST(HostileGltf, DeepNestingIsRefusedBeforeParsing) {
    // 30,000 nested arrays in extras overflowed the stack inside the JSON parser.
    const std::string deep = std::string(30000, '[') + std::string(30000, ']');
    const std::string text =
        hostile::tetraJson(hostile::dataUri(hostile::tetraBin()), "\"extras\": {\"x\": " + deep + "}, ");
    const std::string p = (tempDir() / "deep.gltf").string();
    hostile::writeBytes(p, text);
    expectRefused(loadGltf(p, 2, 1), "nested deeper than 64");
    const std::string g = (tempDir() / "deep.glb").string();
    hostile::writeBytes(
        g, hostile::glb(hostile::tetraJson("", "\"extras\": " + deep + ", "), hostile::tetraBin()));
    expectRefused(loadGltf(g, 2, 1), "nested deeper than 64");
    // Brackets inside strings do not count; 60 real levels load.
    const std::string fine =
        hostile::tetraJson(hostile::dataUri(hostile::tetraBin()),
                           "\"extras\": {\"s\": \"" + std::string(5000, '[') +
                               "\", \"a\": " + std::string(60, '[') + std::string(60, ']') + "}, ");
    hostile::writeBytes(p, fine);
    auto ok = loadGltf(p, 2, 1);
    EXPECT_TRUE(ok.ok()) << ok.error();
}

TEST(HostileGltf, UrisStayInsideTheSceneFolder) {
    Layout l;
    // Inside the folder (also through '..' that stays inside): loads.
    for (const std::string uri : {"sub/tetra.bin", "sub/../sub/tetra.bin", "sub%2Ftetra.bin"}) {
        auto r = loadGltf(l.write("in.gltf", hostile::tetraJson("\"uri\": \"" + uri + "\"")), 2, 1);
        EXPECT_TRUE(r.ok()) << uri << ": " << r.error();
    }
    // '..' out of the folder, an absolute path, a symlink pointing out: refused by default.
    fs::create_symlink(l.secret, l.scene / "link.bin");
    for (const std::string& uri : {std::string("../secret.bin"), l.secret.string(), std::string("link.bin"),
                                   std::string("sub/../../secret.bin")}) {
        const std::string path = l.write("out.gltf", hostile::tetraJson("\"uri\": \"" + uri + "\""));
        SCOPED_TRACE(uri);
        auto r = loadGltf(path, 2, 1);
        if (uri == l.secret.string()) {
            // tinygltf joins it under the folder (".../scene//root/.../secret.bin"): not read, and the
            // message says it is refused as an absolute path (it used to say "File not found").
            expectRefused(r, "is an absolute path, outside the scene's folder");
            continue;
        }
        expectRefused(r, "outside the scene's folder");
        // A trusted user may allow it.
        auto allowed = loadGltf(path, 2, 1, LoadOptions{true});
        EXPECT_TRUE(allowed.ok()) << allowed.error();
    }
    // The same from a .glb whose buffer names an external file.
    const std::string g =
        l.write("out.glb", hostile::glb(hostile::tetraJson("\"uri\": \"../secret.bin\""), ""));
    expectRefused(loadGltf(g, 2, 1), "outside the scene's folder");
    // A folder or FIFO as a buffer: refused, no hang.
    fs::create_directories(l.scene / "dir.bin");
    expectRefused(loadGltf(l.write("dir.gltf", hostile::tetraJson("\"uri\": \"dir.bin\"")), 2, 1),
                  "not a regular file");
}

// /etc/passwd as a buffer used to be read, and a failing index echoed its bytes.
TEST(HostileGltf, SystemFileIsNotRead) {
    Layout l;
    const std::string p =
        l.write("passwd.gltf", hostile::tetraJson("\"uri\": \"../../../../../../../../etc/passwd\""));
    expectRefused(loadGltf(p, 2, 1), "outside the scene's folder");
}

TEST(HostileGltf, MessagesDoNotEchoBytes) {
    // A broken data URI: tinygltf's message quotes the whole URI; ours gives its length.
    const std::string payload = std::string(3000, 'Q');
    const std::string p = (tempDir() / "baduri.gltf").string();
    hostile::writeBytes(
        p, hostile::tetraJson("\"uri\": \"data:application/octet-stream;base64," + payload + "!\""));
    auto r = loadGltf(p, 2, 1);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().find("QQQQQQQQ"), std::string::npos) << r.error();
    EXPECT_LT(r.error().size(), 600u) << r.error();
    // A JSON syntax error: no "last read: '<bytes>'" quote of the file, no control characters.
    hostile::writeBytes(p, "{\"asset\": SECRETTOKEN\x1b[2J\n}");
    auto j = loadGltf(p, 2, 1);
    ASSERT_FALSE(j.ok());
    EXPECT_EQ(j.error().find("SECRETTOKEN"), std::string::npos) << j.error();
    EXPECT_EQ(j.error().find('\x1b'), std::string::npos) << j.error();
    EXPECT_EQ(j.error().find('\n'), std::string::npos) << j.error();
    // Index values read from a buffer are not printed.
    std::string bin = hostile::tetraBin();
    const uint16_t big = 0x4142;
    std::memcpy(&bin[48 + 6], &big, 2);
    hostile::writeBytes(p, hostile::tetraJson(hostile::dataUri(bin)));
    auto i = loadGltf(p, 2, 1);
    ASSERT_FALSE(i.ok());
    EXPECT_EQ(i.error().find(std::to_string(big)), std::string::npos) << i.error();
    EXPECT_NE(i.error().find("index 3"), std::string::npos) << i.error();
}

// KHR_lights_punctual values out of range are refused, not clamped or replaced.
TEST(HostileGltf, PunctualLightsOutOfRangeRefused) {
    auto scene = [](const std::string& light) {
        const std::string ext =
            R"("extensionsUsed": ["KHR_lights_punctual"], "extensions": {"KHR_lights_punctual": {"lights": [)" +
            light + "]}}, ";
        const std::string p = (tempDir() / "light.gltf").string();
        hostile::writeBytes(p,
                            hostile::tetraJson(hostile::dataUri(hostile::tetraBin()), ext,
                                               R"(, "extensions": {"KHR_lights_punctual": {"light": 0}})"));
        return loadGltf(p, 1, 1);
    };
    auto good = scene(
        R"({"type": "spot", "intensity": 5, "range": 4, "spot": {"outerConeAngle": 0.6, "innerConeAngle": 0.3}})");
    ASSERT_TRUE(good.ok()) << good.error();
    EXPECT_FLOAT_EQ(good->lights[0].outerAngle, 0.6f);
    EXPECT_FLOAT_EQ(good->lights[0].range, 4.0f);
    const std::pair<const char*, const char*> bad[] = {
        {R"({"type": "spot", "spot": {"outerConeAngle": 2.0}})", "outerConeAngle"},
        {R"({"type": "spot", "spot": {"outerConeAngle": 1.5707963267948966}})", "outerConeAngle"},
        {R"({"type": "spot", "spot": {"outerConeAngle": -0.5}})", "outerConeAngle"},
        {R"({"type": "spot", "spot": {"outerConeAngle": 0.5, "innerConeAngle": 0.7}})", "innerConeAngle"},
        {R"({"type": "spot", "spot": {"outerConeAngle": 0.5, "innerConeAngle": -0.1}})", "innerConeAngle"},
        {R"({"type": "point", "range": -3})", "range"},
        {R"({"type": "point", "intensity": -1})", "intensity"},
        {R"({"type": "point", "color": [1, -1, 1]})", "colour"},
    };
    for (const auto& [light, needle] : bad) expectRefused(scene(light), needle);
}

// A primitive mode outside glTF's 0..6 is a broken file: it used to load as triangles. An absent mode
// (tinygltf's -1) stays triangles; 0..6 other than triangles are skipped and counted in the warnings.
TEST(HostileGltf, PrimitiveModesOutsideTheSpecAreRefused) {
    Layout l;
    const std::string buffer = "\"uri\": \"sub/tetra.bin\"";
    const std::string base = hostile::tetraJson(buffer);
    const std::string tag = "\"indices\": 1}";
    ASSERT_NE(base.find(tag), std::string::npos);
    auto withMode = [&](int mode) {
        std::string j = base;
        j.replace(j.find(tag), tag.size(), "\"indices\": 1, \"mode\": " + std::to_string(mode) + "}");
        return loadGltf(l.write("mode.gltf", j), 2, 1);
    };
    for (int bad : {-5, -2, 7, 1000}) {
        SCOPED_TRACE(bad);
        expectRefused(withMode(bad), "mode " + std::to_string(bad) + " is not a glTF primitive mode (0..6)");
    }
    auto triangles = withMode(4);
    ASSERT_TRUE(triangles.ok()) << triangles.error();
    EXPECT_EQ(triangles.value().meshes.size(), 1u);
    auto absent = loadGltf(l.write("absent.gltf", base), 2, 1);
    ASSERT_TRUE(absent.ok()) << absent.error();
    EXPECT_EQ(absent.value().meshes.size(), 1u);
}

// glTF 1.0 files (and versions that are not "2.minor") are refused instead of read with 2.0 meanings.
TEST(HostileGltf, AssetVersionMustBe2x) {
    Layout l;
    const std::string base = hostile::tetraJson("\"uri\": \"sub/tetra.bin\"");
    const std::string tag = "\"version\": \"2.0\"";
    ASSERT_NE(base.find(tag), std::string::npos);
    for (const std::string version : {"1.0", "3.0", "2", "2.x", "20.0", ""}) {
        SCOPED_TRACE(version);
        std::string j = base;
        j.replace(j.find(tag), tag.size(), "\"version\": \"" + version + "\"");
        expectRefused(loadGltf(l.write("v.gltf", j), 2, 1), "asset.version is not 2.x");
    }
    std::string j = base;
    j.replace(j.find(tag), tag.size(), "\"version\": \"2.1\"");
    auto ok = loadGltf(l.write("v21.gltf", j), 2, 1);
    EXPECT_TRUE(ok.ok()) << ok.error();
}

// A buffer over 4 GiB (a sparse file: nothing is written) is refused naming its size and the limit,
// not "cannot read".
TEST(HostileGltf, BufferOver4GiBNamesTheLimit) {
    Layout l;
    const fs::path big = l.scene / "big.bin";
    {
        std::ofstream f(big, std::ios::binary);
        ASSERT_TRUE(f.good());
    }
    fs::resize_file(big, (uint64_t(5) << 30));
    auto r = loadGltf(l.write("big.gltf", hostile::tetraJson("\"uri\": \"big.bin\"")), 2, 1);
    expectRefused(r,
                  "5368709120 bytes, more than the 4294967295-byte limit (a glTF buffer is at most 4 GiB)");
    fs::remove(big);
}

} // namespace
} // namespace ml
