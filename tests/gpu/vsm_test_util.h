// The session the VSM GPU tests start from: the night city's drive path at 192x108, the validation layer
// on, 1024^2 virtual maps (small page tables for the CPU references) and a pool of 1024 pages (room
// for every page the path marks). Each test changes what it is about.
#pragma once
#include "gpu_test_util.h"
#include "host/vsm_session.h"
#include "shadows/virtual/vsm_reference.h"

namespace ml::test {

inline VsmSessionOptions vsmSmallDrive(VsmRaster raster = VsmRaster::Auto) {
    VsmSessionOptions o;
    o.width = 192;
    o.height = 108;
    o.path = CameraPath::Drive;
    o.module.device.validation = true;
    o.module.vsm.resolution = 1024;
    o.module.vsm.poolPages = 1024;
    o.module.vsm.raster = raster;
    return o;
}

// The inputs of the mark references (vsm_reference.h) as the module's last frame left them.
inline VsmMarkInputs markInputs(Module& m) {
    auto& impl = internals(m);
    const VirtualShadowMaps& vsm = impl.vsm;
    const uint32_t slot = impl.lastSlot;
    VsmMarkInputs in;
    in.frame = impl.lastConstants;
    in.sliceFar = impl.lastSliceFar;
    in.lights = impl.lastLights;
    const size_t clusters = impl.cull.grid.count();
    std::vector<glm::uvec2> rangesRead = readBufferAs<glm::uvec2>(*impl.device, impl.cull.ranges); // GPU-only
    auto* ranges = rangesRead.data();
    in.ranges.assign(ranges, ranges + clusters);
    std::vector<uint32_t> poolRead = readBufferAs<uint32_t>(*impl.device, impl.cull.pool); // GPU-only
    auto* pool = poolRead.data();
    in.pool.assign(pool, pool + impl.cull.poolCapacity);
    in.depth = toFloats(readImage(m, impl.targets.depth, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    auto normal = readImage(m, impl.targets.normal, 8, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    in.normal.resize(in.depth.size());
    for (size_t i = 0; i < in.normal.size(); ++i) in.normal[i] = half4(normal, i);
    in.constants = vsm.lastConstants();
    in.maps = vsm.slotHost(slot).maps;
    in.coverage = vsm.slotHost(slot).coverage;
    in.markWords = vsm.layout().markWords;
    return in;
}

} // namespace ml::test
