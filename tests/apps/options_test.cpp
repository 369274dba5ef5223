// The commands' option groups (apps/options.h, apps/cli.h) and JSON writer (apps/json.h): flags two
// groups define, bad values and lists, and the escaping of what a summary line or JSON file carries.
#include "apps/cli.h"
#include "apps/json.h"
#include "apps/options.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ml {
namespace {

// cli::parse over a list of words, as a command line after "manylights cmd".
Result<cli::Args> parseWords(std::vector<std::string> words, std::initializer_list<cli::Flags> groups) {
    std::vector<char*> argv = {const_cast<char*>("manylights"), const_cast<char*>("cmd")};
    for (std::string& w : words) argv.push_back(w.data());
    return cli::parse(int(argv.size()), argv.data(), 2, groups);
}

TEST(Options, GroupsAndOwnFlagsParseTogether) {
    auto a = parseWords({"--seed", "7", "--scene", "x.glb", "--allow-outside-scene-dir", "--out", "d"},
                        {opts::kSceneFlags, opts::kSceneDirFlags, {{"--out"}, {}}});
    ASSERT_TRUE(a) << a.error();
    auto scene = opts::scene(a.value());
    ASSERT_TRUE(scene) << scene.error();
    EXPECT_EQ(scene->name, "x.glb");
    EXPECT_EQ(scene->seed, 7u);
    EXPECT_TRUE(scene->allowOutside);
    EXPECT_EQ(a->get("--out", ""), "d");
}

TEST(Options, FlagInTwoGroupsIsRefused) {
    // A command redefining a group's flag (valued or as a switch) would silently take over its parse.
    auto a = parseWords({}, {opts::kSceneFlags, {{"--seed", "--out"}, {}}});
    ASSERT_FALSE(a);
    EXPECT_NE(a.error().find("--seed"), std::string::npos) << a.error();
    auto b = parseWords({}, {opts::kSceneDirFlags, {{}, {"--allow-outside-scene-dir"}}});
    EXPECT_FALSE(b);
    auto c = parseWords({}, {opts::kViewFlags, {{}, {"--frames"}}});
    EXPECT_FALSE(c);
}

TEST(Options, FlagsOutsideTheGroupsAreRefused) {
    EXPECT_FALSE(parseWords({"--seed", "1"}, {opts::kViewFlags}));
    EXPECT_FALSE(parseWords({"--seed"}, {opts::kSceneFlags})); // missing value
}

// A flag given twice, or a valued flag followed by another flag instead of its value, is refused
// naming the flag (both used to pass: the second value won, or "--frames" became the culling mode).
TEST(Options, DuplicatesAndMissingValuesAreRefused) {
    const cli::Flags own{{"--culling", "--out"}, {"--json"}};
    auto twice = parseWords({"--seed", "1", "--seed", "2"}, {opts::kSceneFlags, own});
    ASSERT_FALSE(twice);
    EXPECT_EQ(twice.error(), "--seed: given twice");
    auto sw = parseWords({"--json", "--json"}, {own});
    ASSERT_FALSE(sw);
    EXPECT_EQ(sw.error(), "--json: given twice");
    auto swallowed = parseWords({"--culling", "--frames", "1"}, {opts::kViewFlags, own});
    ASSERT_FALSE(swallowed);
    EXPECT_EQ(swallowed.error(), "--culling: missing value (the next argument is the flag --frames)");
    auto beforeSwitch = parseWords({"--out", "--json"}, {own});
    ASSERT_FALSE(beforeSwitch);
    EXPECT_NE(beforeSwitch.error().find("the next argument is the flag --json"), std::string::npos);
    // Values that merely start with '-' (negative numbers, a camera with a leading space) still parse.
    auto negative = parseWords({"--out", "-0.25,-1,0"}, {own});
    ASSERT_TRUE(negative) << negative.error();
    EXPECT_EQ(negative->get("--out", ""), "-0.25,-1,0");
    // A value that is an unknown flag is not taken as the value either.
    auto unknownFlag = parseWords({"--out", "--bogus"}, {own});
    ASSERT_FALSE(unknownFlag);
    EXPECT_EQ(unknownFlag.error(), "--out: missing value (the next argument, '--bogus', is a flag)");
    EXPECT_FALSE(parseWords({"--out"}, {own})); // last argument, no value
}

// --max-memory: MiB, 64..2^30; the default is half the machine's memory; the check's refusal is one
// line naming the estimate, the limit and the flag.
TEST(Options, MaxMemory) {
    auto none = parseWords({}, {opts::kMemoryFlags});
    ASSERT_TRUE(none);
    auto def = opts::maxMemory(none.value());
    ASSERT_TRUE(def) << def.error();
    EXPECT_EQ(def.value(), opts::machineMemory() / 2);
    EXPECT_GT(def.value(), uint64_t(0));
    auto set = parseWords({"--max-memory", "1024"}, {opts::kMemoryFlags});
    ASSERT_TRUE(set);
    EXPECT_EQ(opts::maxMemory(set.value()).value(), uint64_t(1024) << 20);
    for (const char* bad : {"0", "63", "12G", "-5", "1e3"}) {
        auto a = parseWords({"--max-memory", bad}, {opts::kMemoryFlags});
        ASSERT_TRUE(a) << bad;
        EXPECT_FALSE(opts::maxMemory(a.value())) << bad;
    }
    EXPECT_TRUE(opts::checkMemory("test", uint64_t(100) << 20, uint64_t(200) << 20, "x"));
    auto over = opts::checkMemory("test", (uint64_t(300) << 20) + 1, uint64_t(200) << 20, "two maps");
    ASSERT_FALSE(over);
    EXPECT_NE(over.error().find("estimated peak memory 301 MiB (two maps) exceeds the limit 200 MiB"),
              std::string::npos)
        << over.error();
    EXPECT_NE(over.error().find("--max-memory"), std::string::npos);
    EXPECT_EQ(over.error().find('\n'), std::string::npos);
}

TEST(Options, SeedAndViewBounds) {
    auto a = parseWords({"--seed", "4294967296"}, {opts::kSceneFlags});
    ASSERT_TRUE(a);
    EXPECT_FALSE(opts::scene(a.value()));
    a = parseWords({"--seed", "-1"}, {opts::kSceneFlags});
    EXPECT_FALSE(opts::seed(a.value()));
    a = parseWords({"--seed", "4294967295"}, {opts::kSceneFlags});
    ASSERT_TRUE(opts::seed(a.value()));
    EXPECT_EQ(opts::seed(a.value()).value(), 4294967295u);
    const opts::ViewDefaults d{16, 2, 1000, "320x180"};
    a = parseWords({}, {opts::kViewFlags});
    auto v = opts::view(a.value(), d);
    ASSERT_TRUE(v) << v.error();
    EXPECT_EQ(v->frames, 16u);
    EXPECT_EQ(v->width, 320u);
    EXPECT_EQ(v->height, 180u);
    a = parseWords({"--frames", "1"}, {opts::kViewFlags});
    EXPECT_FALSE(opts::view(a.value(), d)); // below the command's minimum
    a = parseWords({"--size", "0x10"}, {opts::kViewFlags});
    EXPECT_FALSE(opts::view(a.value(), d));
}

TEST(Options, NeedGroup) {
    auto a = parseWords({"--need-min", "32", "--need-size", "64x48"}, {opts::kNeedFlags});
    auto n = opts::need(a.value(), "1280x720");
    ASSERT_TRUE(n) << n.error();
    EXPECT_EQ(n->minRes, 32u);
    EXPECT_EQ(n->width, 64u);
    EXPECT_EQ(n->samples, 120u);
    EXPECT_TRUE(opts::checkNeedMin(64));
    auto bad = opts::checkNeedMin(48);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error(), "--need-min: 48 is not a power of two");
    a = parseWords({"--need-seconds", "0"}, {opts::kNeedFlags});
    EXPECT_FALSE(opts::need(a.value(), "1280x720"));
}

TEST(Options, Lists) {
    auto u = opts::uintList("--res", "64,128", 16, 16384);
    ASSERT_TRUE(u) << u.error();
    EXPECT_EQ(u.value(), (std::vector<uint32_t>{64, 128}));
    EXPECT_EQ(opts::uintList("--res", "", 16, 16384).error(), "--res: empty list");
    for (const char* bad : {"64,,128", "64,", ",64", "8", "64,x", "64;128"})
        EXPECT_FALSE(opts::uintList("--res", bad, 16, 16384)) << bad;
    EXPECT_NE(opts::uintList("--res", "64,,128", 16, 16384).error().find("--res"), std::string::npos);

    auto m = opts::methodList("--methods", "sm,dagmh");
    ASSERT_TRUE(m) << m.error();
    EXPECT_EQ(m.value(), (std::vector<StaticMethod>{StaticMethod::SM, StaticMethod::DAGMH}));
    EXPECT_EQ(opts::methodList("--methods", "sm,none").error(), "--methods: method none");
    EXPECT_FALSE(opts::methodList("--methods", "sm,bogus"));

    auto c = opts::cullingList("--culling", "tiled,none");
    ASSERT_TRUE(c) << c.error();
    EXPECT_EQ(c.value(), (std::vector<CullingMode>{CullingMode::Tiled, CullingMode::None}));
    EXPECT_FALSE(opts::cullingList("--culling", "sideways"));
}

TEST(Options, Numbers) {
    EXPECT_FLOAT_EQ(opts::number("--light-move", "0.25", 0, 10).value(), 0.25f);
    for (const char* bad : {"", "nan", "inf", "-0.1", "10.5", "1x", "1e40"})
        EXPECT_FALSE(opts::number("--light-move", bad, 0, 10)) << bad;
}

TEST(Json, Escaping) {
    EXPECT_EQ(json::quote("plain"), "\"plain\"");
    EXPECT_EQ(json::quote("a\"b\\c"), "\"a\\\"b\\\\c\"");
    EXPECT_EQ(json::quote(std::string("\n\t\x01\x1f", 4)), "\"\\u000a\\u0009\\u0001\\u001f\"");
    // DEL is escaped too (a terminal acts on it), bytes from 0x80 pass (UTF-8).
    EXPECT_EQ(json::quote("x\x7fy"), "\"x\\u007fy\"");
    EXPECT_EQ(json::quote("\xc3\xa9"), "\"\xc3\xa9\"");
    EXPECT_EQ(json::quote(std::string("a\0b", 3)), "\"a\\u0000b\"");
}

TEST(Json, NumbersObjectsArrays) {
    EXPECT_EQ(json::number(0.1), "0.1");
    EXPECT_EQ(json::number(1234567.0), "1.23457e+06"); // an ostream's default form
    EXPECT_EQ(json::number(2.0 / 3.0, "%.4f"), "0.6667");
    json::Object o;
    o.text("name", "n\"").integer("count", uint64_t(18446744073709551615ull)).integer("delta", -3);
    o.real("ms", 1.5).raw("list", json::array({"1", "2"}));
    EXPECT_EQ(o.str(), "{\"name\": \"n\\\"\", \"count\": 18446744073709551615, \"delta\": -3, \"ms\": 1.5, "
                       "\"list\": [1, 2]}");
    EXPECT_EQ(o.str(json::Style::Compact),
              "{\"name\":\"n\\\"\",\"count\":18446744073709551615,\"delta\":-3,\"ms\":1.5,\"list\":[1, 2]}");
    json::Object lines;
    lines.integer("a", 1).integer("b", 2);
    EXPECT_EQ(lines.str(json::Style::Lines), "{\n  \"a\": 1,\n  \"b\": 2\n}");
    json::Object broken;
    broken.integer("a", 1).breakLine().integer("b", 2);
    EXPECT_EQ(broken.str(), "{\"a\": 1,\n \"b\": 2}");
    EXPECT_EQ(json::array({}), "[]");
    EXPECT_EQ(json::array({"{}", "{}"}, ",\n", "[\n", "\n]"), "[\n{},\n{}\n]");
    json::Object first;
    first.integer("x", 1);
    EXPECT_EQ(first.append(lines).str(), "{\"x\": 1, \"a\": 1, \"b\": 2}");
}

} // namespace
} // namespace ml
