// Named bindings (gpu/bindings.h): descriptors given by their binding's name land at that binding in any
// order, and a list that names a binding twice, leaves one out, names one past the shader's or gives one
// the wrong kind of resource is refused with a message naming the program and the binding. No device:
// the ordering is checked on its own.
#include "gpu/bindings.h"

#include <gtest/gtest.h>

namespace ml::test {
namespace {

#define ML_TEST_B_FIRST 0
#define ML_TEST_B_SECOND 1
#define ML_TEST_B_THIRD 2
#define ML_TEST_B_PAST 3

Program threeBuffers() {
    Program p;
    p.name = "test_program";
    p.bindingCount = 3;
    for (uint32_t b = 0; b < 3; ++b) p.bindingTypes[b] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return p;
}

Buffer fakeBuffer(uintptr_t id) {
    Buffer b;
    b.buffer = reinterpret_cast<VkBuffer>(id);
    return b;
}

TEST(NamedBindings, PlacesEachDescriptorAtItsNamedBinding) {
    const Program p = threeBuffers();
    const Buffer a = fakeBuffer(0x10), b = fakeBuffer(0x20), c = fakeBuffer(0x30);
    const Descriptor* ordered[32];
    const std::string error = orderNamedDescriptors(
        p, {ML_BIND(ML_TEST_B_THIRD, c), ML_BIND(ML_TEST_B_FIRST, a), ML_BIND(ML_TEST_B_SECOND, b)}, ordered);
    ASSERT_EQ(error, "");
    EXPECT_EQ(ordered[0]->buffer, a.buffer);
    EXPECT_EQ(ordered[1]->buffer, b.buffer);
    EXPECT_EQ(ordered[2]->buffer, c.buffer);
}

TEST(NamedBindings, RefusesTwiceMissingAndPastWithTheName) {
    const Program p = threeBuffers();
    const Buffer a = fakeBuffer(0x10), b = fakeBuffer(0x20), c = fakeBuffer(0x30);
    const Descriptor* ordered[32];
    EXPECT_EQ(orderNamedDescriptors(
                  p, {ML_BIND(ML_TEST_B_FIRST, a), ML_BIND(ML_TEST_B_FIRST, b), ML_BIND(ML_TEST_B_THIRD, c)},
                  ordered),
              "test_program: ML_TEST_B_FIRST (binding 0) is given twice");
    EXPECT_EQ(orderNamedDescriptors(p, {ML_BIND(ML_TEST_B_FIRST, a), ML_BIND(ML_TEST_B_THIRD, c)}, ordered),
              "test_program: binding 1 is not given (between ML_TEST_B_FIRST at 0 and ML_TEST_B_THIRD at 2)");
    // A missing first or last binding is placed by its one neighbour; none given, by its number alone.
    EXPECT_EQ(orderNamedDescriptors(p, {ML_BIND(ML_TEST_B_THIRD, c), ML_BIND(ML_TEST_B_SECOND, b)}, ordered),
              "test_program: binding 0 is not given (before ML_TEST_B_SECOND at 1)");
    EXPECT_EQ(orderNamedDescriptors(p, {ML_BIND(ML_TEST_B_SECOND, b), ML_BIND(ML_TEST_B_FIRST, a)}, ordered),
              "test_program: binding 2 is not given (after ML_TEST_B_SECOND at 1)");
    EXPECT_EQ(orderNamedDescriptors(p, {}, ordered), "test_program: binding 0 is not given");
    EXPECT_EQ(orderNamedDescriptors(p,
                                    {ML_BIND(ML_TEST_B_FIRST, a), ML_BIND(ML_TEST_B_SECOND, b),
                                     ML_BIND(ML_TEST_B_THIRD, c), ML_BIND(ML_TEST_B_PAST, c)},
                                    ordered),
              "test_program: ML_TEST_B_PAST (binding 3) is past the shader's 3 bindings");
}

// A resource of the wrong kind is refused by its binding's name: an image at a buffer binding, and a
// buffer at an image binding.
TEST(NamedBindings, RefusesTheWrongKindWithTheName) {
    Program p = threeBuffers();
    p.bindingTypes[ML_TEST_B_THIRD] = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    const Buffer a = fakeBuffer(0x10), b = fakeBuffer(0x20);
    const VkImageView view = reinterpret_cast<VkImageView>(uintptr_t(0x40));
    const Descriptor* ordered[32];
    EXPECT_EQ(orderNamedDescriptors(
                  p,
                  {ML_BIND(ML_TEST_B_FIRST, a), ML_BIND(ML_TEST_B_SECOND, b), ML_BIND(ML_TEST_B_THIRD, view)},
                  ordered),
              "");
    EXPECT_EQ(orderNamedDescriptors(p,
                                    {ML_BIND(ML_TEST_B_FIRST, a), ML_BIND(ML_TEST_B_SECOND, view),
                                     ML_BIND(ML_TEST_B_THIRD, view)},
                                    ordered),
              "test_program: ML_TEST_B_SECOND (binding 1) expects a buffer");
    EXPECT_EQ(orderNamedDescriptors(
                  p, {ML_BIND(ML_TEST_B_FIRST, a), ML_BIND(ML_TEST_B_SECOND, b), ML_BIND(ML_TEST_B_THIRD, b)},
                  ordered),
              "test_program: ML_TEST_B_THIRD (binding 2) expects an image");
}

} // namespace
} // namespace ml::test
