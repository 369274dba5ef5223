// Damaged buffers: truncation and bit flips are rejected by validate(); with the checksum forged back
// to match, whatever validate() still accepts must decode every texel without reading outside the
// buffer (the buffer ends at a PROT_NONE guard page, so an overrun crashes the test).
#include "static_test_util.h"

#include <gtest/gtest-spi.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>

namespace ml::stest {
namespace {

// A copy of `words` that ends exactly at an inaccessible page.
class GuardedBuffer {
  public:
    explicit GuardedBuffer(const std::vector<uint32_t>& words) {
        size_t page = size_t(sysconf(_SC_PAGESIZE));
        size_t bytes = words.size() * 4;
        size_t dataPages = (bytes + page - 1) / page;
        total_ = (dataPages + 1) * page;
        base_ = static_cast<uint8_t*>(
            mmap(nullptr, total_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
        EXPECT_NE(base_, MAP_FAILED);
        mprotect(base_ + dataPages * page, page, PROT_NONE);
        data_ = reinterpret_cast<uint32_t*>(base_ + dataPages * page - bytes);
        if (bytes) std::memcpy(data_, words.data(), bytes);
    }
    ~GuardedBuffer() { munmap(base_, total_); }
    const uint32_t* data() const { return data_; }

  private:
    uint8_t* base_ = nullptr;
    uint32_t* data_ = nullptr;
    size_t total_ = 0;
};

uint32_t checksumIndex(const std::string& name) {
    return name == "DAG-MH" ? uint32_t(dagfmt::kChecksum) : uint32_t(mhfmt::kChecksum);
}

// Words worth damaging: the whole header, and a spread of node/offset/count words.
std::vector<size_t> damageTargets(size_t size, uint32_t header) {
    std::vector<size_t> t;
    for (size_t i = 0; i < std::min<size_t>(size, header + 64); ++i) t.push_back(i);
    for (size_t i = header + 64; i < size; i += std::max<size_t>(1, size / 150)) t.push_back(i);
    return t;
}

void damageSuite(const DualDepthMap& m) {
    for (const Codec& codec : codecs()) {
        SCOPED_TRACE(codec.name);
        auto enc = codec.encode(m);
        ASSERT_TRUE(enc.ok()) << enc.error();
        const std::vector<uint32_t>& good = *enc;
        ASSERT_TRUE(codec.validate(good.data(), good.size()).ok());
        // Truncations.
        for (size_t cut : {size_t(0), size_t(1), size_t(5), good.size() / 2, good.size() - 1}) {
            std::vector<uint32_t> t(good.begin(), good.begin() + std::min(cut, good.size()));
            EXPECT_FALSE(codec.validate(t.data(), t.size()).ok()) << "truncated to " << cut;
        }
        EXPECT_FALSE(codec.validate(nullptr, 0).ok());
        uint32_t header = codec.name == "DAG-MH" ? dagfmt::kHeaderWords : good[mhfmt::kNodeOffset];
        const uint32_t ck = checksumIndex(codec.name);
        uint64_t flips = 0, forgedAccepted = 0, forgedRejected = 0;
        for (size_t w : damageTargets(good.size(), header)) {
            for (uint32_t bit : {0u, 3u, 8u, 17u, 31u}) {
                std::vector<uint32_t> d = good;
                d[w] ^= 1u << bit;
                ++flips;
                EXPECT_FALSE(codec.validate(d.data(), d.size()).ok()) << "word " << w << " bit " << bit;
                if (w == ck) continue;
                // Forge the checksum: only the structural checks stand between the damage and the lookup.
                d[ck] = stat::checksumWords(d.data(), d.size(), ck);
                GuardedBuffer g(d);
                if (!codec.validate(g.data(), d.size()).ok()) {
                    ++forgedRejected;
                    continue;
                }
                ++forgedAccepted;
                uint32_t res = d[mhfmt::kResolution]; // same word in every format
                uint32_t acc = 0;
                for (uint32_t y = 0; y < res; y += (w < header ? 1 : 7))
                    for (uint32_t x = 0; x < res; ++x) acc ^= codec.lookup(g.data(), x, y);
                (void)acc;
            }
        }
        std::printf("  [static] %s: %llu flips rejected by the checksum; forged checksums: %llu rejected, "
                    "%llu accepted "
                    "(decoded without overrun)\n",
                    codec.name.c_str(), (unsigned long long)flips, (unsigned long long)forgedRejected,
                    (unsigned long long)forgedAccepted);
    }
}

TEST(StaticValidate, RejectsTruncatedAndFlippedSynthetic) {
    damageSuite(syntheticMap(128, 9));
}

TEST(StaticValidate, RejectsTruncatedAndFlippedRaster) {
    CasterTriangles c;
    std::mt19937 rng(11);
    for (int i = 0; i < 40; ++i) {
        glm::vec3 p(float(rng() % 100) / 10 - 5, float(rng() % 100) / 10 - 5, -3.0f - float(rng() % 50) / 10);
        glm::vec3 q = p + glm::vec3(0.3f + float(rng() % 10) / 10);
        // Closed boxes as 12 triangles each (two faces per axis direction), alternating open quads.
        if (i % 3 == 0) {
            c.add({p.x, p.y, p.z}, {q.x, p.y, p.z}, {q.x, q.y, p.z}, false);
            c.add({p.x, p.y, p.z}, {q.x, q.y, p.z}, {p.x, q.y, p.z}, false);
        } else {
            glm::vec3 v[8];
            for (int k = 0; k < 8; ++k) v[k] = {k & 1 ? q.x : p.x, k & 2 ? q.y : p.y, k & 4 ? q.z : p.z};
            const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                 {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
            for (auto& q4 : f)
                c.add(v[q4[0]], v[q4[1]], v[q4[2]], true), c.add(v[q4[0]], v[q4[2]], v[q4[3]], true);
        }
    }
    LightFrustum fr;
    fr.fov = 1.2f;
    fr.farPlane = 12.0f;
    DualDepthMap m = rasterizeDual(c, fr, 256);
    for (const Codec& codec : codecs()) encodeChecked(m, codec);
    damageSuite(m);
}

// DAG-MH's value bounds decide lookups without reading the values, so a bounds word that does not hold
// its cell's values would change shadows silently: validate() recomputes every cell. Each cell's word
// widened, narrowed or swapped (checksum forged back) is refused, naming the cell.
TEST(StaticValidate, DagmhForgedValueBoundsRejected) {
    DualDepthMap m = syntheticMap(128, 9);
    auto enc = encodeDAGMH(m);
    ASSERT_TRUE(enc.ok()) << enc.error();
    const uint32_t* d = enc->data();
    const uint32_t S = dagfmt::skipLevel(d), B = dagfmt::boundsLevel(d);
    ASSERT_GE(B, 1u);
    const uint32_t first = d[dagfmt::kSkipOffset] + (dagfmt::kSkipWords << (2 * S));
    uint64_t refused = 0, cells = uint64_t(1) << (2 * B);
    for (uint32_t c = 0; c < cells; ++c) {
        const uint32_t w = (*enc)[first + c];
        for (uint32_t forgedWord : {w ^ 1u, w ^ 0x10000u, (w >> 16) | (w << 16)}) {
            if (forgedWord == w) continue;
            std::vector<uint32_t> bad = *enc;
            bad[first + c] = forgedWord;
            bad[dagfmt::kChecksum] = stat::checksumWords(bad.data(), bad.size(), dagfmt::kChecksum);
            auto r = validateDAGMH(bad.data(), bad.size());
            ASSERT_FALSE(r.ok()) << "cell " << c << " forged " << forgedWord;
            EXPECT_NE(r.error().find("value bounds of cell"), std::string::npos) << r.error();
            ++refused;
        }
    }
    EXPECT_GE(refused, 2 * cells);
}

TEST(StaticValidate, LosslessCheckCatchesAWrongDecoder) {
    // The exhaustive check itself must fail for a decoder that is off by one on non-empty texels.
    DualDepthMap m = syntheticMap(64, 2, false);
    auto enc = encodeMH(m);
    ASSERT_TRUE(enc.ok());
    Codec off = codecs()[0];
    off.lookup = [](const uint32_t* d, uint32_t x, uint32_t y) {
        uint32_t v = mhLookup(d, x, y);
        return v == kDepthEmpty ? v : 0xFFFFFFFEu;
    };
    uint64_t bad = 0;
    {
        testing::TestPartResultArray swallowed;
        testing::ScopedFakeTestPartResultReporter quiet(
            testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &swallowed);
        bad = countLossy(m, *enc, off);
    }
    EXPECT_GT(bad, 0u);
}

} // namespace
} // namespace ml::stest
