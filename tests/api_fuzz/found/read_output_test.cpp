// What the API-sequence fuzzer (tests/api_fuzz/api_fuzz.cpp) found, kept as plain regression tests.
//
// readOutput right after createTargets, before any frame, copied the new output image while it was still
// in UNDEFINED layout (a validation error, and bytes nothing wrote): it now refuses with one line until a
// frame is recorded into the current targets.
#include "../../gpu/gpu_test_util.h"

namespace ml::test {
namespace {

TEST(FuzzFound, ReadOutputBeforeAFrameIsRefused) {
    auto m = makeModule();
    ASSERT_TRUE(m);
    std::vector<uint8_t> rgba;
    auto none = m->readOutput(rgba);
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error(), "readOutput: no targets (call createTargets first)");
    ASSERT_TRUE(m->setCamera({{0, 5, 10}, {0, 0, 0}}).ok());
    ASSERT_TRUE(m->createTargets(32, 18).ok());
    auto early = m->readOutput(rgba);
    ASSERT_FALSE(early.ok());
    EXPECT_EQ(early.error(),
              "readOutput: no frame was recorded into these targets yet (record or submitFrame first)");
    ASSERT_TRUE(m->submitFrame().ok());
    auto r = m->readOutput(rgba);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(rgba.size(), 32u * 18u * 4u);
    // New targets start empty again (the old ones had a frame).
    ASSERT_TRUE(m->createTargets(16, 16).ok());
    EXPECT_FALSE(m->readOutput(rgba).ok());
    ASSERT_TRUE(m->submitFrame().ok());
    EXPECT_TRUE(m->readOutput(rgba).ok());
    m->detachTargets();
    EXPECT_FALSE(m->readOutput(rgba).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
