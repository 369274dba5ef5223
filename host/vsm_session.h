// A scene bound to a module with virtual shadow maps, driven along a camera path one frame at a time:
// shared by `check vsm`, `bench vsm` and the VSM tests.
#pragma once
#include "manylights/manylights.h"
#include "host/scene_host.h"
#include "scenes/camera_path.h"

#include <memory>

namespace ml {

struct VsmSessionOptions {
    std::string scene = "night-city";
    uint32_t lights = 256, seed = 1, width = 320, height = 180;
    CameraPath path = CameraPath::Drive;
    std::string bake;     // optional bake file: its lights' maps hold dynamic casters only
    ModuleOptions module; // vsm settings, timing, culling
    double secondsPerFrame = 1.0 / 30.0;
};

struct VsmSession {
    Scene scene;
    SceneBinding binding;
    std::unique_ptr<Module> module;
    VsmSessionOptions options;

    // settingsRefused (optional): set when the module refused the settings against the device's limits
    // or ranges (its "vsm: ..." and target-size refusals; a usage error for the commands), not for a
    // device or scene failure.
    static Result<std::unique_ptr<VsmSession>> create(const VsmSessionOptions& options,
                                                      bool* settingsRefused = nullptr);
    // Animates the scene to frame f, moves the camera along the path, records and submits the frame and
    // waits for it (reports are collected).
    Result<FrameReport> frame(uint32_t f);
};

} // namespace ml
