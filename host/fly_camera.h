// A first-person camera for interactive hosts (demo --window): mouse movement turns it (yaw about
// world +y, pitch clamped to +-85 degrees so the view never becomes parallel to `up`, which the module
// refuses), keys move it along its own axes. No window code here: the input arrives as numbers, so the
// tests drive it directly.
#pragma once
#include "manylights/glm.h"
#include "manylights/manylights.h"

namespace ml {

struct FlyInput {
    float forward = 0.0f, right = 0.0f, up = 0.0f; // -1..1 each (W/S, D/A, E/Q)
    bool fast = false;                             // shift: kFastFactor times faster
    float lookX = 0.0f, lookY = 0.0f;              // mouse movement in pixels while a button is held
};

class FlyCamera {
  public:
    static constexpr float kSpeed = 8.0f; // metres per second (a street crossing in ~2 s)
    static constexpr float kFastFactor = 5.0f;
    static constexpr float kRadiansPerPixel = 0.004f;
    static constexpr float kMaxPitch = 1.4835f; // 85 degrees

    static FlyCamera lookingAt(glm::vec3 position, glm::vec3 target);
    void update(const FlyInput& input, float seconds);
    glm::vec3 position() const { return position_; }
    glm::vec3 forward() const;
    // The camera with this position and orientation (target one metre ahead), other fields from `base`.
    CameraDesc desc(const CameraDesc& base) const;

  private:
    glm::vec3 position_{0.0f};
    float yaw_ = 0.0f, pitch_ = 0.0f; // yaw 0 looks down -z; positive pitch looks up
};

} // namespace ml
