#include "host/fly_camera.h"

#include <algorithm>
#include <cmath>

namespace ml {

FlyCamera FlyCamera::lookingAt(glm::vec3 position, glm::vec3 target) {
    FlyCamera c;
    c.position_ = position;
    glm::vec3 d = target - position;
    float len = glm::length(d);
    if (!(len > 0.0f)) return c;
    d /= len;
    c.yaw_ = std::atan2(d.x, -d.z);
    c.pitch_ = std::clamp(std::asin(std::clamp(d.y, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
    return c;
}

glm::vec3 FlyCamera::forward() const {
    return {std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_), -std::cos(yaw_) * std::cos(pitch_)};
}

void FlyCamera::update(const FlyInput& in, float seconds) {
    // Mouse right turns right, mouse down looks down (screen y grows downwards).
    yaw_ += in.lookX * kRadiansPerPixel;
    pitch_ = std::clamp(pitch_ - in.lookY * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
    glm::vec3 f = forward();
    glm::vec3 right = glm::normalize(glm::cross(f, glm::vec3(0.0f, 1.0f, 0.0f)));
    float step = kSpeed * (in.fast ? kFastFactor : 1.0f) * seconds;
    position_ += (f * in.forward + right * in.right + glm::vec3(0.0f, 1.0f, 0.0f) * in.up) * step;
}

CameraDesc FlyCamera::desc(const CameraDesc& base) const {
    CameraDesc c = base;
    c.position = position_;
    c.target = position_ + forward();
    c.up = {0.0f, 1.0f, 0.0f};
    return c;
}

} // namespace ml
