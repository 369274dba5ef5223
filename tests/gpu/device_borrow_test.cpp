// Borrowing a host's device: the documented requirement list equals the table create() enables and
// borrow() checks; a device missing any feature or extension, or handed over with a wrong queue, is
// refused with a line naming it; a correct borrow renders with no validation message.
#include "gpu_test_util.h"
#include "tests/common/borrowed_device.h"

#include <fstream>
#include <regex>
#include <sstream>

namespace ml {
namespace {

using test::HostDevice;

// The names after "//   features:" / "//   extensions:" in manylights/device.h's header comment.
std::vector<std::string> documented(const std::string& key) {
    std::ifstream in(std::string(ML_SOURCE_DIR) + "/include/manylights/device.h");
    EXPECT_TRUE(in.good());
    std::vector<std::string> names;
    std::string line;
    const std::string prefix = "//   " + key + ":";
    while (std::getline(in, line)) {
        if (line.rfind(prefix, 0) != 0) continue;
        std::istringstream words(line.substr(prefix.size()));
        for (std::string w; words >> w;) names.push_back(w);
    }
    return names;
}

TEST(DeviceBorrow, DocumentedListEqualsTable) {
    EXPECT_EQ(documented("features"), requiredDeviceFeatures());
    EXPECT_EQ(documented("extensions"), requiredDeviceExtensions());
    EXPECT_GE(requiredDeviceFeatures().size(), 10u);
}

std::unique_ptr<Device> ownDevice() {
    resetValidationCounters();
    DeviceOptions o;
    o.validation = true;
    auto d = Device::create(o);
    EXPECT_TRUE(d.ok()) << d.error();
    return d ? std::move(d.value()) : nullptr;
}

TEST(DeviceBorrow, EachMissingFeatureIsRefusedByName) {
    auto own = ownDevice();
    ASSERT_TRUE(own);
    for (const std::string& feature : requiredDeviceFeatures()) {
        HostDevice host(*own, feature);
        auto r = Device::borrow(host.borrow(*own));
        ASSERT_FALSE(r.ok()) << feature << " missing but the borrow was accepted";
        EXPECT_NE(r.error().find("not enabled: " + feature), std::string::npos) << r.error();
        EXPECT_EQ(r.error().find('\n'), std::string::npos);
    }
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(DeviceBorrow, MissingExtensionOrChainIsRefused) {
    auto own = ownDevice();
    ASSERT_TRUE(own);
    HostDevice host(*own);
    DeviceBorrow b = host.borrow(*own);
    b.enabledExtensions = {VK_EXT_MESH_SHADER_EXTENSION_NAME};
    auto r = Device::borrow(b);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("extensions not enabled: " VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME),
              std::string::npos)
        << r.error();
    b = host.borrow(*own);
    b.enabledFeatures = nullptr;
    r = Device::borrow(b);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("enabledFeatures"), std::string::npos) << r.error();
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(DeviceBorrow, WrongQueueIsRefused) {
    auto own = ownDevice();
    ASSERT_TRUE(own);
    HostDevice host(*own);
    DeviceBorrow b = host.borrow(*own);
    b.queueFamily = 77; // no such family
    auto r = Device::borrow(b);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("queue family 77 does not exist"), std::string::npos) << r.error();
    b = host.borrow(*own);
    b.queue = own->queue; // a queue of another device
    r = Device::borrow(b);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("queue is not queue 0 of family"), std::string::npos) << r.error();
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(DeviceBorrow, CorrectBorrowRendersWithoutValidationMessages) {
    auto own = ownDevice();
    ASSERT_TRUE(own);
    HostDevice host(*own);
    {
        ModuleOptions o;
        o.borrow = host.borrow(*own);
        auto created = Module::create(o);
        ASSERT_TRUE(created.ok()) << created.error();
        Module& m = *created.value();
        EXPECT_EQ(deviceOf(m).device, host.device);
        std::vector<MeshVertex> v = {
            {{-5, 0, -5}, {0, 1, 0}}, {{5, 0, -5}, {0, 1, 0}}, {{0, 0, 5}, {0, 1, 0}}};
        std::vector<uint32_t> idx = {0, 2, 1};
        auto mesh = m.addMesh({v, idx});
        ASSERT_TRUE(mesh.ok()) << mesh.error();
        ASSERT_TRUE(m.addInstance(mesh.value(), glm::mat4(1.0f), glm::vec3(0.5f), false).ok());
        LightDesc spot;
        spot.position = {0, 3, 0};
        spot.intensity = 30;
        ASSERT_TRUE(m.addLight(spot).ok());
        ASSERT_TRUE(m.setCamera({{0, 4, 6}, {0, 0, 0}}).ok());
        ASSERT_TRUE(m.createTargets(64, 36).ok());
        test::renderFrame(m);
        std::vector<uint8_t> rgba;
        ASSERT_TRUE(m.readOutput(rgba).ok());
        uint32_t lit = 0, maxRed = 0;
        for (size_t i = 0; i < rgba.size(); i += 4)
            lit += rgba[i] > 100, maxRed = std::max<uint32_t>(maxRed, rgba[i]);
        EXPECT_GT(lit, 20u) << "brightest red " << maxRed; // the spot's pool on the triangle
    }                                                      // the module goes before the host's device
    EXPECT_EQ(validationErrors(), 0u);
}

// ModuleOptions::pipelineCache on the module's own device: refused with one line (a cache belongs to the
// device it was created on, and the host could not have made one on a device that did not exist yet).
// That a borrowed device's module builds through the host's cache is checked by interposing the
// pipeline calls (QueueAccess.PipelinesGoThroughTheHostsCache): lavapipe's cache data stays a header.
TEST(DeviceBorrow, PipelineCacheWithoutBorrowIsRefused) {
    resetValidationCounters();
    ModuleOptions alone;
    alone.device.validation = true;
    alone.pipelineCache = reinterpret_cast<VkPipelineCache>(uintptr_t(1)); // never used: refused first
    auto refused = Module::create(alone);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().find("pipelineCache needs a borrowed device"), std::string::npos)
        << refused.error();
    EXPECT_EQ(refused.error().find('\n'), std::string::npos);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml
