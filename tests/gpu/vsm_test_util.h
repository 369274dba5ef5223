// The session the VSM GPU tests start from: the night city's drive path at 192x108, the validation layer
// on, 1024^2 virtual maps (small page tables for the CPU references) and a pool of 1024 pages (room
// for every page the path marks). Each test changes what it is about.
#pragma once
#include "host/vsm_session.h"

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

} // namespace ml::test
