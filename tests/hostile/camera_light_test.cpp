// Hostile cameras and lights: non-finite, huge and degenerate cameras refused by
// validateCamera and by the --camera parser; spot angles and ranges out of range refused by
// validateLight (not clamped).
#include "hostile_test_util.h"

#include "manylights/glm.h"
#include "manylights/manylights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ml {
namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(HostileCamera, ValidateCamera) {
    CameraDesc good;
    good.position = {0, 5, 10};
    good.target = {0, 0, 0};
    ASSERT_TRUE(validateCamera(good).ok());
    auto refused = [&](CameraDesc c, const char* needle) {
        auto r = validateCamera(c);
        ASSERT_FALSE(r.ok()) << needle;
        EXPECT_NE(r.error().find(needle), std::string::npos) << r.error();
        EXPECT_EQ(r.error().find('\n'), std::string::npos);
    };
    for (float bad : {kNan, kInf, -kInf, 2e6f}) {
        CameraDesc c = good;
        c.position.x = bad;
        refused(c, "position");
        c = good;
        c.target.z = bad;
        refused(c, "target");
    }
    CameraDesc c = good;
    c.target = c.position;
    refused(c, "target equals position");
    c = good;
    c.target = toGlm(c.position) - glm::vec3(0, 3, 0); // straight down along up
    refused(c, "parallel to up");
    c.target = toGlm(c.position) + glm::vec3(0, 1e-3f, 0);
    refused(c, "parallel to up");
    c = good;
    c.up = {0, 0, 0};
    refused(c, "up");
    c = good;
    c.up = {kNan, 1, 0};
    refused(c, "up");
    c = good;
    c.fovY = kNan;
    refused(c, "fovY");
    c = good;
    c.fovY = 3.2f;
    refused(c, "fovY");
    c = good;
    c.farPlane = kInf;
    refused(c, "near < far");
    c = good;
    c.nearPlane = 0.0f;
    refused(c, "near < far");
    // Nearly straight down, but not parallel: a valid view.
    c = good;
    c.target = toGlm(c.position) + glm::vec3(0.01f, -10.0f, 0);
    EXPECT_TRUE(validateCamera(c).ok());
}

TEST(HostileLight, SpotAnglesAndRangeRefused) {
    LightDesc good;
    good.kind = LightKind::Spot;
    good.position = {0, 5, 0};
    good.direction = {0, -1, 0};
    good.range = 10;
    good.outerAngle = 0.6f;
    good.innerAngle = 0.3f;
    ASSERT_TRUE(validateLight(good).ok());
    for (float outer : {0.0f, -0.1f, 1.5707964f, 2.0f, kNan, kInf}) {
        LightDesc l = good;
        l.outerAngle = outer;
        l.innerAngle = 0.0f;
        EXPECT_FALSE(validateLight(l).ok()) << "outer " << outer;
    }
    for (float inner : {-0.01f, 0.61f, kNan}) {
        LightDesc l = good;
        l.innerAngle = inner;
        EXPECT_FALSE(validateLight(l).ok()) << "inner " << inner;
    }
    for (LightKind kind : {LightKind::Spot, LightKind::Point})
        for (float range : {0.0f, -1.0f, kNan, kInf}) {
            LightDesc l = good;
            l.kind = kind;
            l.range = range;
            EXPECT_FALSE(validateLight(l).ok()) << "range " << range;
        }
}

// The command line: one line, exit 1 (a usage error), before any frame is rendered.
TEST(HostileCli, CameraArgumentRefused) {
    const std::pair<const char*, const char*> cases[] = {
        {"nan,1,2,3,4,5", "not a finite number"},  {"1,inf,2,3,4,5", "not a finite number"},
        {"1e39,1,1,0,0,0", "not a finite number"}, {"2e6,1,1,0,0,0", "not a finite number"},
        {"0,10,0,0,0,0", "parallel to up"},        {"1,1,1,1,1,1", "target equals position"},
        {"1,2,3", "is not X,Y,Z,TX,TY,TZ"},        {"1,2,3,4,5,6,7", "is not X,Y,Z,TX,TY,TZ"},
        {"1,2,3,4,5,6x", "is not X,Y,Z,TX,TY,TZ"}, {"1,,3,4,5,6", "is not X,Y,Z,TX,TY,TZ"},
    };
    const std::string out = (hostile::tempDir() / "camera_out").string();
    for (const auto& [camera, needle] : cases) {
        auto r = hostile::runCli(std::string("demo --frames 1 --size 32x32 --lights 4 --out ") + out +
                                 " --camera '" + camera + "'");
        EXPECT_EQ(r.status, 1) << camera << ": " << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << camera << ": " << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << camera << ": " << r.err;
    }
}

} // namespace
} // namespace ml
