// Orbit camera and fly-away animation of the viewer.
#include "leanfade/viewer/camera.hpp"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace leanfade::viewer {

OrbitCamera::OrbitCamera(const CameraSettings& s)
    : distance(std::clamp(s.distance, kMinOrbitDistance, kMaxCameraDistance)),
      target(s.target),
      fov_y_degrees(s.fov_y_degrees) {
    const float length = glm::length(s.direction);
    const glm::vec3 d = length > 0.0f ? s.direction / length : glm::vec3(0.0f, 0.0f, 1.0f);
    pitch_degrees = std::clamp(glm::degrees(std::asin(std::clamp(d.y, -1.0f, 1.0f))),
                               -kMaxPitchDegrees, kMaxPitchDegrees);
    yaw_degrees = (d.x == 0.0f && d.z == 0.0f) ? 0.0f : glm::degrees(std::atan2(d.x, d.z));
    given_direction_ = length > 0.0f ? s.direction : d;
    given_yaw_ = yaw_degrees;
    given_pitch_ = pitch_degrees;
}

glm::vec3 OrbitCamera::direction() const {
    if (unchanged()) return glm::normalize(given_direction_);
    const float yaw = glm::radians(yaw_degrees), pitch = glm::radians(pitch_degrees);
    return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw)};
}

CameraSettings OrbitCamera::settings() const {
    CameraSettings s;
    s.target = target;
    s.direction = unchanged() ? given_direction_ : direction();
    s.distance = distance;
    s.fov_y_degrees = fov_y_degrees;
    return s;
}

gl::View OrbitCamera::view() const {
    return gl::view_at_distance(distance, fov_y_degrees,
                                unchanged() ? given_direction_ : direction(), target);
}

bool OrbitCamera::unchanged() const {
    return yaw_degrees == given_yaw_ && pitch_degrees == given_pitch_;
}

void OrbitCamera::orbit(float yaw, float pitch) {
    yaw_degrees = std::remainder(yaw_degrees + yaw, 360.0f);
    pitch_degrees = std::clamp(pitch_degrees + pitch, -kMaxPitchDegrees, kMaxPitchDegrees);
}

void OrbitCamera::zoom(float factor) {
    if (!(factor > 0.0f) || !std::isfinite(factor)) return;
    distance = std::clamp(distance * factor, kMinOrbitDistance, kMaxCameraDistance);
}

void OrbitCamera::pan(float dx, float dy, int height) {
    if (height < 1) return;
    // World units per pixel in the plane through the target facing the camera.
    const float per_pixel =
        2.0f * distance * std::tan(glm::radians(fov_y_degrees) * 0.5f) / float(height);
    const glm::vec3 forward = -direction();
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0.0f, 1.0f, 0.0f)));
    const glm::vec3 up = glm::cross(right, forward);
    target += (-dx * right + dy * up) * per_pixel;
    // Keep the target within reach of the object (a lost camera helps nobody).
    const float reach = 50.0f;
    if (glm::length(target) > reach) target *= reach / glm::length(target);
}

float fly_away_distance(const FlyAwaySettings& s, double seconds) {
    const double period = std::max(0.5, double(s.period));
    const double phase = std::fmod(std::max(0.0, seconds), period) / period;  // [0, 1)
    const double blend = 0.5 - 0.5 * std::cos(2.0 * 3.14159265358979323846 * phase);
    const double log_near = std::log(double(s.near_distance));
    const double log_far = std::log(double(s.far_distance));
    return float(std::exp(log_near + (log_far - log_near) * blend));
}

}  // namespace leanfade::viewer
