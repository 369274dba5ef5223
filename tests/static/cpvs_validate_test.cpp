// CPVS determinism and progress, validation of truncated and bit-flipped data (lookups of accepted data
// stay in bounds: guard pages), and the lookup helpers (base offset, PCF, normal bias).
#include "cpvs_test_util.h"

#include <cstring>
#include <sys/mman.h>
#include <unistd.h>

namespace ml::ctest {
namespace {

// ---------------------------------------------------------------------------------------------------
// Determinism, validation, lookup helpers

TEST(CpvsBake, DeterministicAndProgress) {
    DualDepthMap m = boxesMap(128, 51, false, false);
    CpvsParams p;
    p.resolution = 128;
    p.nearPlane = kNear;
    p.farPlane = kFar;
    std::vector<float> seen;
    p.progress = [&](float f) { seen.push_back(f); };
    auto a = bakeCpvs(m, p);
    auto b = bakeCpvs(m, p);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->data, b->data);
    ASSERT_FALSE(seen.empty());
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.begin() + seen.size() / 2));
    EXPECT_EQ(seen.back(), 1.0f);
    DualDepthMap wrong = m;
    wrong.exit.pop_back();
    EXPECT_FALSE(bakeCpvs(wrong, p).ok());
    p.resolution = 256;
    EXPECT_FALSE(bakeCpvs(m, p).ok());
}

// Data placed right before an inaccessible page: a read past the end faults instead of passing silently.
struct GuardedWords {
    size_t pages = 0, page = 0;
    uint8_t* base = nullptr;
    uint32_t* words = nullptr;
    explicit GuardedWords(const std::vector<uint32_t>& w) {
        page = size_t(sysconf(_SC_PAGESIZE));
        size_t bytes = w.size() * 4, dataPages = (bytes + page - 1) / page;
        pages = dataPages + 2;
        base = static_cast<uint8_t*>(
            mmap(nullptr, pages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
        mprotect(base, page, PROT_NONE);
        mprotect(base + (dataPages + 1) * page, page, PROT_NONE);
        words = reinterpret_cast<uint32_t*>(base + (dataPages + 1) * page - bytes);
        std::memcpy(words, w.data(), bytes);
    }
    ~GuardedWords() { munmap(base, pages * page); }
};

TEST(CpvsValidate, RejectsTruncatedAndBitFlippedData) {
    const uint32_t n = 64;
    DualDepthMap m = boxesMap(n, 61, false, false);
    CpvsBake b = bakeOrDie(m, n, 2);
    const std::vector<uint32_t>& d = b.data;
    ASSERT_TRUE(validateCpvs(d.data(), d.size()).ok());
    EXPECT_FALSE(validateCpvs(nullptr, 0).ok());
    for (size_t len = 0; len < d.size(); ++len) ASSERT_FALSE(validateCpvs(d.data(), len).ok()) << len;
    // truncated and re-declared (header says the shorter size, checksum re-signed): offsets disagree
    for (size_t len = kCpvsHeaderWords; len < d.size(); len += 7) {
        std::vector<uint32_t> t(d.begin(), d.begin() + len);
        t[kCpvsHTotalWords] = uint32_t(len);
        t[kCpvsHChecksum] = cpvsChecksum(t.data(), t.size());
        ASSERT_FALSE(validateCpvs(t.data(), t.size()).ok()) << len;
    }
    // every single bit flip is caught (the checksum sees any change within one word)
    std::vector<uint32_t> c = d;
    for (size_t i = 0; i < c.size(); ++i)
        for (uint32_t bit = 0; bit < 32; bit += (i < 64 ? 1 : 11)) {
            c[i] ^= 1u << bit;
            ASSERT_FALSE(validateCpvs(c.data(), c.size()).ok()) << i << ":" << bit;
            c[i] ^= 1u << bit;
        }
    // flips with a re-signed checksum: the structural checks alone. Either rejected, or every lookup stays
    // inside the data (guard pages) and terminates.
    uint64_t rejected = 0, accepted = 0;
    for (size_t i = 0; i < c.size(); ++i)
        for (uint32_t bit = 0; bit < 32; bit += 5) {
            if (i == kCpvsHChecksum) continue;
            c[i] ^= 1u << bit;
            c[kCpvsHChecksum] = cpvsChecksum(c.data(), c.size());
            if (!validateCpvs(c.data(), c.size()).ok()) {
                ++rejected;
            } else {
                ++accepted;
                GuardedWords g(c);
                for (int32_t s = 0; s < int32_t(n); s += 3)
                    for (int32_t y = 0; y < int32_t(n); y += 2)
                        for (int32_t x = 0; x < int32_t(n); ++x) (void)cpvsShadowedVoxel(g.words, 0, x, y, s);
                (void)verifyCpvs(g.words, m);
            }
            c[i] ^= 1u << bit;
            c[kCpvsHChecksum] = d[kCpvsHChecksum];
        }
    std::printf("  [cpvs] re-signed flips: %llu rejected, %llu accepted (lookups stayed in bounds)\n",
                (unsigned long long)rejected, (unsigned long long)accepted);
    EXPECT_GT(rejected, 0u);
}

TEST(CpvsLookup, BaseOffsetPcfAndNormalBias) {
    const uint32_t n = 128;
    DualDepthMap m = boxesMap(n, 71, false, false);
    CpvsBake b = bakeOrDie(m, n);
    const uint32_t base = 1234;
    std::vector<uint32_t> big(base, 0xDEADBEEFu);
    big.insert(big.end(), b.data.begin(), b.data.end());
    Rng r(5);
    for (int i = 0; i < 20000; ++i) {
        int32_t x = int32_t(r.below(n + 20)) - 10, y = int32_t(r.below(n + 20)) - 10,
                s = int32_t(r.below(n + 20)) - 10;
        bool a = cpvsShadowedVoxel(b.data.data(), 0, x, y, s);
        ASSERT_EQ(a, cpvsShadowedVoxel(big.data(), base, x, y, s));
        if (x < 0 || y < 0 || x >= int32_t(n) || y >= int32_t(n)) {
            ASSERT_FALSE(a);
        }
        int32_t nq[3] = {int32_t(r.below(2049)) - 1024, int32_t(r.below(2049)) - 1024,
                         int32_t(r.below(2049)) - 1024};
        int32_t radius = int32_t(r.below(5)), o[3];
        cpvsNormalOffset(nq, radius, o);
        uint32_t lit = 0;
        for (int32_t dy = -radius; dy <= radius; ++dy)
            for (int32_t dx = -radius; dx <= radius; ++dx)
                lit += !cpvsShadowedVoxel(b.data.data(), 0, x + o[0] + dx, y + o[1] + dy, s + o[2]);
        ASSERT_EQ(cpvsPcfLitCount(big.data(), base, x, y, s, nq, radius), lit);
        ASSERT_LE(lit, uint32_t((2 * radius + 1) * (2 * radius + 1)));
    }
    int32_t o[3];
    int32_t up[3] = {0, 0, -1024};
    cpvsNormalOffset(up, 4, o);
    EXPECT_EQ(o[0], 0);
    EXPECT_EQ(o[2], -5);
    int32_t diag[3] = {512, -1024, 0};
    cpvsNormalOffset(diag, 0, o);
    EXPECT_EQ(o[0], 1); // 0.5 rounds away from zero
    EXPECT_EQ(o[1], -1);
    int32_t zero[3] = {0, 0, 0};
    cpvsNormalOffset(zero, 3, o);
    EXPECT_EQ(o[0] | o[1] | o[2], 0);
    // a light-facing normal (toward the light: +z in view space) moves toward the near slices
    float nView[3] = {0.0f, 0.0f, 1.0f};
    int32_t v[3];
    cpvsVoxelNormal(nView, 0.0f, 0.0f, 0.5f, std::log(kFar / kNear), v);
    EXPECT_EQ(v[0], 0);
    EXPECT_EQ(v[2], -1024);
}

// Filtering by level: at every level of a 128^3 grid, each receiver's kernel reads the centre voxels of
// level texels (floor division, also left of and below the map) at its own slice biased by whole level
// voxels; every receiver in one level texel gets the same answer; level 0 is the finest-level kernel.
TEST(CpvsLookup, PcfByLevelReadsTheLevelTexelsCentres) {
    const uint32_t n = 128, levels = 7;
    DualDepthMap m = boxesMap(n, 72, false, false);
    CpvsBake b = bakeOrDie(m, n);
    const uint32_t* d = b.data.data();
    Rng r(9);
    uint64_t shadowedTaps = 0, litTaps = 0;
    for (int i = 0; i < 4000; ++i) {
        int32_t x = int32_t(r.below(n + 40)) - 20, y = int32_t(r.below(n + 40)) - 20, s = int32_t(r.below(n));
        int32_t nq[3] = {int32_t(r.below(2049)) - 1024, int32_t(r.below(2049)) - 1024,
                         int32_t(r.below(2049)) - 1024};
        int32_t radius = int32_t(r.below(5)), o[3];
        cpvsNormalOffset(nq, radius, o);
        ASSERT_EQ(cpvsPcfLitLevel(d, 0, x, y, s, nq[0], nq[1], nq[2], radius, 0u),
                  cpvsPcfLitCount(d, 0, x, y, s, nq, radius));
        for (uint32_t step = 0; step <= levels; ++step) {
            const int32_t side = 1 << step;
            auto levelOf = [&](int32_t v) { return int32_t(std::floor(double(v) / side)); };
            uint32_t lit = 0;
            for (int32_t dy = -radius; dy <= radius; ++dy)
                for (int32_t dx = -radius; dx <= radius; ++dx)
                    lit += !cpvsShadowedVoxel(d, 0, (levelOf(x) + o[0] + dx) * side + side / 2,
                                              (levelOf(y) + o[1] + dy) * side + side / 2, s + o[2] * side);
            const uint32_t got = cpvsPcfLitLevel(d, 0, x, y, s, nq[0], nq[1], nq[2], radius, step);
            ASSERT_EQ(got, lit) << x << "," << y << "," << s << " step " << step;
            litTaps += lit;
            shadowedTaps += uint32_t((2 * radius + 1) * (2 * radius + 1)) - lit;
            // Any other receiver in the same level texel, at the same slice, gets the same answer.
            const int32_t x2 = levelOf(x) * side + int32_t(r.below(uint32_t(side)));
            const int32_t y2 = levelOf(y) * side + int32_t(r.below(uint32_t(side)));
            ASSERT_EQ(cpvsPcfLitLevel(d, 0, x2, y2, s, nq[0], nq[1], nq[2], radius, step), got);
        }
    }
    std::printf("  [cpvs by level] %llu lit and %llu shadowed taps over 8 levels\n",
                (unsigned long long)litTaps, (unsigned long long)shadowedTaps);
    EXPECT_GT(shadowedTaps, litTaps / 20)
        << "the boxes must shadow a share of the taps for this to test anything";
}

} // namespace
} // namespace ml::ctest
