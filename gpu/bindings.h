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

// The named descriptors in binding order (ordered[b] for binding b < program.bindingCount), or the
// message naming what does not match the program's bindings (empty when they do). Bound only on success.
std::string orderNamedDescriptors(const Program& program, std::initializer_list<NamedDescriptor> named,
                                  const Descriptor* ordered[32]);

// As dispatchThreads (gpu/program.h), the descriptors placed by name; aborts with orderNamedDescriptors'
// message when they do not match.
void dispatchThreadsNamed(const Device& device, VkCommandBuffer cmd, const Program& program,
                          const uint32_t threads[3], const void* push, uint32_t pushSize,
                          std::initializer_list<NamedDescriptor> named);

template <class Push>
void dispatch(const Device& device, VkCommandBuffer cmd, const Program& program, uint32_t threadsX,
              uint32_t threadsY, const Push& push, std::initializer_list<NamedDescriptor> named) {
    const uint32_t threads[3] = {threadsX, threadsY, 1};
    dispatchThreadsNamed(device, cmd, program, threads, &push, pushBytes<Push>(), named);
}

} // namespace ml
