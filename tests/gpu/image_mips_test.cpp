// Images with mips and layers (gpu/resources.h): every mip of every layer of a non-power-of-two
// R32_UINT array image is built on the GPU mip by mip (gpu/mip_reduce.comp through the per-mip
// views), read back through the staging path one (mip, layer) at a time and compared with a CPU
// reference; uploads into one (mip, layer) reach exactly that subresource.
#include "gpu/device.h"
#include "gpu/bindings.h"
#include "gpu/mip_reduce_bindings.h"
#include "gpu/resources.h"

#include "mip_reduce.comp.spv.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace ml {
namespace {

using Level = std::vector<uint32_t>; // one mip of one layer, row-major

// CPU twin of mip_reduce.comp: destination (x, y) takes source 2x..2x+1 by 2y..2y+1, the last column /
// row also the odd source column / row.
Level mipReduceReference(const Level& src, uint32_t sw, uint32_t sh, uint32_t op) {
    const uint32_t dw = std::max(1u, sw / 2), dh = std::max(1u, sh / 2);
    Level dst(size_t(dw) * dh);
    for (uint32_t y = 0; y < dh; ++y)
        for (uint32_t x = 0; x < dw; ++x) {
            uint32_t x1 = std::min(2 * x + 1, sw - 1), y1 = std::min(2 * y + 1, sh - 1);
            if (x == dw - 1) x1 = sw - 1;
            if (y == dh - 1) y1 = sh - 1;
            uint32_t r = 0;
            for (uint32_t sy = 2 * y; sy <= y1; ++sy)
                for (uint32_t sx = 2 * x; sx <= x1; ++sx) {
                    const uint32_t v = src[size_t(sy) * sw + sx];
                    r = op == 0 ? r + v : op == 1 ? std::max(r, v) : (r | (v != 0 ? 1u : 0u));
                }
            dst[size_t(y) * dw + x] = r;
        }
    return dst;
}

Level toWords(const std::vector<uint8_t>& bytes) {
    Level w(bytes.size() / 4);
    std::memcpy(w.data(), bytes.data(), w.size() * 4);
    return w;
}

struct Fixture {
    std::unique_ptr<Device> device;
    Fixture() {
        resetValidationCounters();
        DeviceOptions o;
        o.validation = true;
        auto d = Device::create(o);
        EXPECT_TRUE(d.ok()) << d.error();
        if (d) device = std::move(d.value());
    }
};

// Builds mips 1.. of `image` on the GPU with operator `op` (mip 0 uploaded, every mip in GENERAL).
void buildMips(const Device& d, const Image& image, uint32_t op) {
    ShaderModule shader = ML_SHADER(d, spv_mip_reduce_comp);
    Program program = createComputeProgram(d, shader, {{0, op}});
    VkCommandBuffer cmd = d.beginOneTime();
    const auto C = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    // Mips 1.. are written whole: discarded (their first use).
    imageBarrier(cmd, image, 1, image.mips - 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, C, 0, C,
                 VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    for (uint32_t m = 1; m < image.mips; ++m) {
        dispatch(
            d, cmd, program, image.mipWidth(m), image.mipHeight(m), image.layers, NoPush{},
            {ML_BIND(ML_MIP_REDUCE_SRC, image.mipView(m - 1)), ML_BIND(ML_MIP_REDUCE_DST, image.mipView(m))});
        // Mip m -> the next dispatch reads it (read-after-write).
        imageBarrier(cmd, image, m, 1, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL, C,
                     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, C, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    }
    d.endOneTime(cmd);
    destroyProgram(d, program);
    destroyShader(d, shader);
}

TEST(GpuImageMips, EveryMipAndLayerMatchesTheCpuReduction) {
    Fixture f;
    ASSERT_TRUE(f.device);
    const Device& d = *f.device;
    for (uint32_t op : {0u, 1u, 2u}) {
        ImageDesc desc;
        desc.width = 37; // odd and non-power-of-two on both sides: 37x23 -> 18x11 -> 9x5 -> 4x2 -> 2x1 -> 1x1
        desc.height = 23;
        desc.format = VK_FORMAT_R32_UINT;
        desc.usage = VK_IMAGE_USAGE_STORAGE_BIT;
        desc.mips = 0; // full chain
        desc.layers = 3;
        desc.layerViews = true;
        desc.name = "test_mips";
        Image image = createImage(d, desc);
        ASSERT_EQ(image.mips, 6u);
        ASSERT_EQ(image.mipViews.size(), 6u);
        ASSERT_EQ(image.layerViews.size(), 18u);
        for (VkImageView v : image.layerViews) EXPECT_NE(v, VK_NULL_HANDLE);

        // Mip 0: random words (sparse for `any`, so that whole 2x2 blocks are zero).
        std::mt19937 rng(7 + op);
        std::vector<std::vector<Level>> ref(desc.layers);
        for (uint32_t l = 0; l < desc.layers; ++l) {
            Level base(size_t(desc.width) * desc.height);
            for (uint32_t& w : base) w = op == 2 ? (rng() % 11 == 0 ? rng() : 0u) : rng() % 1000;
            uploadImage(d, image, 0, l, base.data(), base.size() * 4, VK_IMAGE_LAYOUT_UNDEFINED,
                        VK_IMAGE_LAYOUT_GENERAL);
            ref[l].push_back(base);
            for (uint32_t m = 1; m < image.mips; ++m)
                ref[l].push_back(
                    mipReduceReference(ref[l][m - 1], image.mipWidth(m - 1), image.mipHeight(m - 1), op));
        }
        buildMips(d, image, op);
        uint32_t zeros = 0, texels = 0;
        for (uint32_t l = 0; l < desc.layers; ++l)
            for (uint32_t m = 0; m < image.mips; ++m) {
                Level gpu = toWords(readImage(d, image, m, l, VK_IMAGE_LAYOUT_GENERAL));
                ASSERT_EQ(gpu.size(), size_t(image.mipWidth(m)) * image.mipHeight(m));
                EXPECT_EQ(gpu, ref[l][m]) << "op " << op << " layer " << l << " mip " << m;
                for (uint32_t w : gpu) zeros += w == 0;
                texels += uint32_t(gpu.size());
            }
        if (op == 2) { // the OR pyramid has both values (the test would not see a constant answer)
            EXPECT_GT(zeros, 0u);
            EXPECT_LT(zeros, texels);
        }
        destroyImage(d, image);
    }
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuImageMips, UploadReachesOnlyItsSubresource) {
    Fixture f;
    ASSERT_TRUE(f.device);
    const Device& d = *f.device;
    ImageDesc desc;
    desc.width = 16;
    desc.height = 8;
    desc.format = VK_FORMAT_R32_UINT;
    desc.mips = 3;
    desc.layers = 2;
    desc.lifetime = Lifetime::Persistent;
    desc.name = "test_upload";
    Image image = createImage(d, desc);
    EXPECT_EQ(image.lifetime, Lifetime::Persistent);
    // Every (mip, layer) gets words that name it; then one of them is overwritten.
    auto fill = [&](uint32_t m, uint32_t l, uint32_t salt) {
        Level w(size_t(image.mipWidth(m)) * image.mipHeight(m));
        for (size_t i = 0; i < w.size(); ++i) w[i] = (salt << 24) | (m << 16) | (l << 12) | uint32_t(i);
        return w;
    };
    for (uint32_t m = 0; m < image.mips; ++m)
        for (uint32_t l = 0; l < image.layers; ++l) {
            Level w = fill(m, l, 1);
            uploadImage(d, image, m, l, w.data(), w.size() * 4, VK_IMAGE_LAYOUT_UNDEFINED,
                        VK_IMAGE_LAYOUT_GENERAL);
        }
    Level second = fill(1, 1, 2);
    uploadImage(d, image, 1, 1, second.data(), second.size() * 4, VK_IMAGE_LAYOUT_GENERAL,
                VK_IMAGE_LAYOUT_GENERAL);
    for (uint32_t m = 0; m < image.mips; ++m)
        for (uint32_t l = 0; l < image.layers; ++l) {
            const Level expect = fill(m, l, m == 1 && l == 1 ? 2 : 1);
            EXPECT_EQ(toWords(readImage(d, image, m, l, VK_IMAGE_LAYOUT_GENERAL)), expect)
                << "mip " << m << " layer " << l;
        }
    destroyImage(d, image);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml
