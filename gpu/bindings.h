// Named bindings: a pass's binding numbers are named constants in a header that its shader and its C++
// both include (the shader declares `layout(binding = ML_X_FOO)`), and the C++ passes each resource with
// its binding's name, ML_BIND(ML_X_FOO, buffer), in any order. The dispatch places every descriptor at
// the binding it names and aborts, naming the program and the binding, when a binding is named twice,
// left out, past the shader's bindings, or given the wrong kind of resource. A list by position (the
// plain dispatch of gpu/program.h) checks the kind only, so two buffers of one kind can trade places
// unnoticed; here each resource states where it goes, and a swap reads wrong at the call site.
#pragma once
#include "gpu/program.h"

#include <string>
#include <vector>

namespace ml {

struct NamedDescriptor {
    uint32_t binding;
    const char* name; // the binding constant's name, for the messages
    Descriptor descriptor;
};
#define ML_BIND(binding, resource)                                                                           \
    ::ml::NamedDescriptor {                                                                                  \
        binding, #binding, ::ml::Descriptor(resource)                                                        \
    }

// The named descriptors in binding order (ordered[b] for binding b < program.bindingCount, names[b] its
// constant's name when names is given), or the message naming what does not match the program's
// bindings (empty when they do): a binding named twice or past the shader's, or given the wrong kind of
// resource, by its constant; one left out, by its number and the constants given on either side of it
// (the SPIR-V carries no names). Bound only on success.
std::string orderNamedDescriptors(const Program& program, std::initializer_list<NamedDescriptor> named,
                                  const Descriptor* ordered[32], const char* names[32] = nullptr);

// What one named bind placed, for tests that check a pass hands each binding the resource meant for it
// (a swap of two buffers of one kind passes every other check).
struct BoundName {
    std::string program;
    const char* binding; // the constant's name
    uint32_t index;
    Descriptor descriptor;
};
// While set, every named bind appends its descriptors, in binding order, to `log` (nullptr: off). Tests
// only: it is not synchronised, and the module records its passes on the caller's thread.
void setBindingLog(std::vector<BoundName>* log);

// As bindProgram / dispatchThreads / dispatchIndirect (gpu/program.h), the descriptors placed by name;
// they abort with orderNamedDescriptors' message when the names do not match the program's bindings.
void bindProgramNamed(const Device& device, VkCommandBuffer cmd, const Program& program,
                      std::initializer_list<NamedDescriptor> named, const void* push, uint32_t pushSize);
void dispatchThreadsNamed(const Device& device, VkCommandBuffer cmd, const Program& program,
                          const uint32_t threads[3], const void* push, uint32_t pushSize,
                          std::initializer_list<NamedDescriptor> named);
void dispatchIndirectNamed(const Device& device, VkCommandBuffer cmd, const Program& program,
                           const Buffer& args, VkDeviceSize offset, const void* push, uint32_t pushSize,
                           std::initializer_list<NamedDescriptor> named);

template <class Push>
void bindProgram(const Device& device, VkCommandBuffer cmd, const Program& program, const Push& push,
                 std::initializer_list<NamedDescriptor> named) {
    bindProgramNamed(device, cmd, program, named, &push, pushBytes<Push>());
}
template <class Push>
void dispatch(const Device& device, VkCommandBuffer cmd, const Program& program, uint32_t threadsX,
              uint32_t threadsY, uint32_t threadsZ, const Push& push,
              std::initializer_list<NamedDescriptor> named) {
    const uint32_t threads[3] = {threadsX, threadsY, threadsZ};
    dispatchThreadsNamed(device, cmd, program, threads, &push, pushBytes<Push>(), named);
}
template <class Push>
void dispatch(const Device& device, VkCommandBuffer cmd, const Program& program, uint32_t threadsX,
              uint32_t threadsY, const Push& push, std::initializer_list<NamedDescriptor> named) {
    dispatch(device, cmd, program, threadsX, threadsY, 1, push, named);
}
template <class Push>
void dispatchIndirect(const Device& device, VkCommandBuffer cmd, const Program& program, const Buffer& args,
                      VkDeviceSize offset, const Push& push, std::initializer_list<NamedDescriptor> named) {
    dispatchIndirectNamed(device, cmd, program, args, offset, &push, pushBytes<Push>(), named);
}

} // namespace ml
