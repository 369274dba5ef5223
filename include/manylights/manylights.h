// The host's entry point: #include <manylights/manylights.h> (include/ on the path, nothing else). The
// public API is this folder alone, every header of it standing on its own:
//   module.h        ml::Module and what its calls take and return (includes the headers below)
//   types.h         Float2, Float3, Float4x4: the API's vectors and matrices, of fixed layout
//   lights.h        LightDesc, its units and validateLight
//   enums.h         LightKind, StaticMethod, CullingMode
//   device.h        DeviceOptions, DeviceBorrow, DeviceInfo, memory and validation counters
//   vsm_settings.h  VsmSettings, VsmStats (virtual shadow maps)
//   pass_times.h    PassTimes, PassTime, TimingMode
//   host_bindings.h the binding offsets of manylights.glsl (C++ and GLSL)
//   result.h        Result<T>, Error
//   glm.h           optional: toGlm / fromGlm for a host that uses glm (not included here)
//   manylights.glsl the lights and shadows in a host's own shaders (#include "manylights/manylights.glsl")
#pragma once
#include "manylights/module.h"
