// LightDesc::shadowTexelScale on lavapipe with the validation layer: a light's scale s reaches its maps
// (GpuVsmMap.info.z = log2 s) and its lookups pick mips as VsmSettings::texelsPerPixel times s would, so
// a module at texelsPerPixel 1 whose lights all take s = 2 marks and allocates exactly what one at
// texelsPerPixel 2 does; with mixed scales the GPU marks still equal the per-pixel CPU reference, and
// the cluster marks equal theirs and contain the per-pixel marks.
#include <bit>
#include <cmath>

#include "vsm_test_util.h"

namespace ml::test {
namespace {

VsmSessionOptions scaleOptions() {
    VsmSessionOptions o = vsmSmallDrive();
    o.module.vsm.maxMaps = 512; // the references' mark arrays cover every slot
    return o;
}

// Sets every static light of the session's scene to scale(i) (moving lights are re-set by the session
// every frame, so they keep 1).
template <class Scale> void setStaticScales(VsmSession& s, Scale scale) {
    for (uint32_t i = 0; i < s.scene.lights.size(); ++i) {
        if (s.scene.lights[i].dynamic) continue;
        LightDesc l = toLightDesc(s.scene.lights[i]);
        l.shadowTexelScale = scale(i);
        ASSERT_TRUE(s.module->setLight(i, l).ok());
    }
}

TEST(GpuVsmTexelScale, LightScaleEqualsTheGlobalSetting) {
    resetValidationCounters();
    VsmSessionOptions global = scaleOptions(), perLight = scaleOptions(), plain = scaleOptions();
    for (VsmSessionOptions* o : {&global, &perLight, &plain}) o->module.vsm.movingLights = false; // all set
    global.module.vsm.texelsPerPixel = 2.0f;
    auto a = VsmSession::create(global), b = VsmSession::create(perLight), c = VsmSession::create(plain);
    ASSERT_TRUE(a.ok() && b.ok() && c.ok());
    setStaticScales(*b.value(), [](uint32_t) { return 2.0f; });
    size_t words = 0, marked = 0, finer = 0;
    for (uint32_t f : {0u, 7u, 14u}) { // the camera and the cars move between these frames
        for (auto* s : {&a, &b, &c}) ASSERT_TRUE(s->value()->frame(f).ok());
        Module &ma = *a.value()->module, &mb = *b.value()->module, &mc = *c.value()->module;
        const std::vector<uint32_t> marksA = internals(ma).vsm.read(deviceOf(ma), VsmState::Marks);
        const std::vector<uint32_t> marksB = internals(mb).vsm.read(deviceOf(mb), VsmState::Marks);
        const std::vector<uint32_t> marksC = internals(mc).vsm.read(deviceOf(mc), VsmState::Marks);
        ASSERT_EQ(marksA, marksB) << "frame " << f << ": scale 2 on every light marks otherwise than tpp 2";
        ASSERT_EQ(internals(ma).vsm.read(deviceOf(ma), VsmState::Table),
                  internals(mb).vsm.read(deviceOf(mb), VsmState::Table))
            << "frame " << f;
        for (size_t w = 0; w < marksB.size(); ++w) {
            marked += size_t(std::popcount(marksB[w]));
            finer += size_t(std::popcount(marksB[w])) > 0 && w < marksC.size() && marksB[w] != marksC[w];
        }
        words += marksB.size();
        const VsmMarkInputs in = markInputs(mb);
        uint32_t scaled = 0;
        for (const gpu::GpuVsmMap& map : in.maps) scaled += map.info.z == 1u;
        EXPECT_GT(scaled, 0u) << "no map carries log2 2 = 1";
    }
    EXPECT_GT(marked, 0u) << "nothing marked (nothing tested)";
    EXPECT_GT(finer, 0u) << "scale 2 marked the same words as scale 1";
    EXPECT_EQ(validationErrors(), 0u);
}

// Scales 1/4..8 across the static lights, moving lights at 1: per-pixel marks equal vsmMarkReference,
// cluster marks equal vsmMarkClusterReference and hold every page of the per-pixel reference.
void mixedScales(bool clusterMarking) {
    resetValidationCounters();
    VsmSessionOptions o = scaleOptions();
    o.module.vsm.clusterMarking = clusterMarking;
    o.module.vsm.fallbacksOnDemand = false; // reserve fallbacks every frame: both regions compared
    auto session = VsmSession::create(o);
    ASSERT_TRUE(session.ok()) << session.error();
    VsmSession& s = *session.value();
    setStaticScales(s, [](uint32_t i) { return 0.25f * float(1u << (i % 6)); });
    Module& m = *s.module;
    size_t differ = 0, missing = 0, marked = 0;
    uint32_t scales = 0;
    for (uint32_t f : {0u, 14u}) { // the camera and the cars move between them
        ASSERT_TRUE(s.frame(f).ok());
        const VsmMarkInputs in = markInputs(m);
        const std::vector<uint32_t> gpu = internals(m).vsm.read(deviceOf(m), VsmState::Marks);
        const std::vector<uint32_t> pixel = vsmMarkReference(in);
        const std::vector<uint32_t> ref = clusterMarking ? vsmMarkClusterReference(in) : pixel;
        ASSERT_GE(gpu.size(), ref.size());
        for (size_t w = 0; w < ref.size(); ++w) {
            differ += gpu[w] != ref[w];
            missing += size_t(std::popcount(pixel[w] & ~gpu[w]));
            marked += size_t(std::popcount(gpu[w]));
        }
        for (const gpu::GpuVsmMap& map : in.maps) scales |= 1u << ((int32_t(map.info.z) + 2) & 31);
    }
    EXPECT_EQ(differ, 0u) << "GPU mark words differ from the CPU reference";
    EXPECT_EQ(missing, 0u) << "pages the per-pixel reference marks that the GPU does not";
    EXPECT_GT(marked, 0u) << "nothing marked (nothing tested)";
    EXPECT_GE(std::popcount(scales), 4)
        << "the maps in use carry too few of the scales (mask " << scales << ")";
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuVsmTexelScale, MixedScalesMarkAsThePixelReference) {
    mixedScales(false);
}
TEST(GpuVsmTexelScale, MixedScalesMarkAsTheClusterReference) {
    mixedScales(true);
}

// The API refuses a scale that is not a power of two in 1/4..8.
TEST(GpuVsmTexelScale, BadScalesAreRefused) {
    LightDesc l;
    for (float bad : {0.0f, 3.0f, 16.0f, 0.125f, -1.0f, std::nanf("")}) {
        l.shadowTexelScale = bad;
        EXPECT_FALSE(validateLight(l).ok()) << bad;
    }
    for (float good : {0.25f, 0.5f, 1.0f, 2.0f, 4.0f, 8.0f}) {
        l.shadowTexelScale = good;
        EXPECT_TRUE(validateLight(l).ok()) << good;
    }
}

} // namespace
} // namespace ml::test
