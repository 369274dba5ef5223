// Hostile format fields: reserved header words and the MH/MMH value count,
// each forged with a valid checksum so that only the new check can catch it; a scene name with control
// characters in `inspect` / `verify` output; a bake file with zero records given to `verify`.
#include "hostile_test_util.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

using hostile::tempDir;

// Sets data[word] = value and fixes the format's own checksum (word `checksum`).
std::vector<uint32_t> forged(std::vector<uint32_t> data, uint32_t word, uint32_t value, uint32_t checksum) {
    data[word] = value;
    data[checksum] = stat::checksumWords(data.data(), data.size(), checksum);
    return data;
}

std::vector<uint32_t> encoded(StaticMethod m) {
    auto e = encodeStatic(m, stest::syntheticMap(64, 5), {});
    EXPECT_TRUE(e.ok()) << e.error();
    return e.value();
}

TEST(HostileFormat, ReservedHeaderWordsMustBeZero) {
    struct Case {
        StaticMethod method;
        uint32_t reserved, checksum;
    };
    const Case cases[] = {{StaticMethod::SM, smfmt::kReserved, smfmt::kChecksum},
                          {StaticMethod::MH, mhfmt::kReserved, mhfmt::kChecksum},
                          {StaticMethod::MMH, mhfmt::kReserved, mhfmt::kChecksum},
                          {StaticMethod::DAGMH, dagfmt::kReserved, dagfmt::kChecksum}};
    for (const Case& c : cases) {
        SCOPED_TRACE(staticMethodName(c.method));
        const auto good = encoded(c.method);
        ASSERT_TRUE(validateStatic(c.method, good.data(), good.size()).ok());
        for (uint32_t v : {1u, 0x80000000u, 0xFFFFFFFFu}) {
            const auto bad = forged(good, c.reserved, v, c.checksum);
            auto r = validateStatic(c.method, bad.data(), bad.size());
            ASSERT_FALSE(r.ok());
            EXPECT_NE(r.error().find("reserved"), std::string::npos) << r.error();
        }
    }
}

TEST(HostileFormat, MhValueCountCannotWrap) {
    for (StaticMethod m : {StaticMethod::MH, StaticMethod::MMH}) {
        SCOPED_TRACE(staticMethodName(m));
        const auto good = encoded(m);
        const uint32_t nodeWords = good[mhfmt::kNodeWords];
        ASSERT_EQ(uint64_t(good[mhfmt::kValued]) + good[mhfmt::kInnerRecords], nodeWords);
        // More values than node words used to print 18446744056529703216 node bytes in inspect.
        for (auto [field, value] : {std::pair{mhfmt::kValued, nodeWords + 1},
                                    {mhfmt::kValued, 0xFFFFFFFFu},
                                    {mhfmt::kValued, 0u},
                                    {mhfmt::kInnerRecords, good[mhfmt::kInnerRecords] + 1},
                                    {mhfmt::kInnerRecords, 0xFFFFFFFFu}}) {
            const auto bad = forged(good, field, value, mhfmt::kChecksum);
            auto r = validateStatic(m, bad.data(), bad.size());
            EXPECT_FALSE(r.ok()) << "field " << field << " = " << value;
        }
    }
    // A single-leaf root must be the only node word.
    DualDepthMap flat = stest::emptyMap(4);
    auto leaf = encodeStatic(StaticMethod::MH, flat, {});
    ASSERT_TRUE(leaf.ok()) << leaf.error();
    ASSERT_EQ(leaf.value()[mhfmt::kRootType], 1u);
    EXPECT_TRUE(validateStatic(StaticMethod::MH, leaf->data(), leaf->size()).ok());
}

// The bake-file reader runs the same checks on every record.
TEST(HostileFormat, BakeFileWithForgedReservedWordRejected) {
    BakeFile f = hostile::syntheticBake(StaticMethod::DAGMH, 1);
    f.records[0].data = forged(f.records[0].data, dagfmt::kReserved, 7, dagfmt::kChecksum);
    auto words = serializeBakeFile(f);
    ASSERT_TRUE(words.ok());
    auto r = parseBakeFile("forged.mlbk", words->data(), words->size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("record 0: DAG-MH: reserved"), std::string::npos) << r.error();
}

// Writes a bake file straight from words (writeBakeFile would refuse nothing here: these are valid).
std::string bakeFileOnDisk(const std::string& name, const BakeFile& f) {
    const std::string p = (tempDir() / name).string();
    auto w = writeBakeFile(p, f);
    EXPECT_TRUE(w.ok()) << w.error();
    return p;
}

TEST(HostileCli, VerifyWithZeroRecordsIsNotAPass) {
    BakeFile f = hostile::syntheticBake(StaticMethod::SM, 0);
    const std::string p = bakeFileOnDisk("empty.mlbk", f);
    ASSERT_TRUE(readBakeFile(p).ok());
    auto r = hostile::runCli("verify " + p);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("no records"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_EQ(r.out.find("\"mismatches\": 0"), std::string::npos) << "no JSON pass line: " << r.out;
}

// A scene name with a newline and terminal escape codes: inspect prints it escaped on one line; verify's
// error (the scene cannot be re-created) is one escaped line too.
TEST(HostileCli, ControlCharactersFromFilesAreEscaped) {
    BakeFile f = hostile::syntheticBake(StaticMethod::SM, 1);
    f.scene.scene = "night\ncity\x1b[2J\x1b[31mFAKE: all good\x07.glb";
    const std::string p = bakeFileOnDisk("evil_name.mlbk", f);
    auto ins = hostile::runCli("inspect " + p);
    EXPECT_EQ(ins.status, 0) << ins.err;
    EXPECT_EQ(ins.out.find('\x1b'), std::string::npos) << ins.out;
    EXPECT_EQ(ins.out.find('\x07'), std::string::npos) << ins.out;
    EXPECT_NE(ins.out.find("night\\ncity\\x1b[2J"), std::string::npos) << ins.out;
    auto json = hostile::runCli("inspect --json " + p);
    EXPECT_EQ(json.status, 0) << json.err;
    EXPECT_NE(json.out.find("night\\u000acity\\u001b"), std::string::npos) << json.out;
    auto ver = hostile::runCli("verify --quiet " + p);
    EXPECT_EQ(ver.status, 2) << ver.err;
    EXPECT_EQ(ver.err.find('\x1b'), std::string::npos) << ver.err;
    EXPECT_EQ(ver.err.find('\n'), ver.err.size() - 1) << ver.err;
    EXPECT_EQ(ver.out.find('\x1b'), std::string::npos) << ver.out;
}

} // namespace
} // namespace ml
