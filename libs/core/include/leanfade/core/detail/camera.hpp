#pragma once
// The camera's settings, described once for the renderer, presets, eval and the command line:
// distances in bounding radii from the object's centre, the vertical field of view in degrees,
// and the default direction from the target toward the eye (world space, y up).
#include <string>

#include <glm/vec3.hpp>

namespace leanfade {

inline constexpr glm::vec3 kDefaultViewDirection{0.0f, 0.3f, 1.0f};

// A camera distance d (bounding radii from the object's centre) is in (1, kMaxCameraDistance]:
// at 1 the eye touches the bounding sphere; beyond the upper end the object covers far less
// than a pixel of any frame.
inline constexpr float kMaxCameraDistance = 10000.0f;
constexpr bool is_camera_distance(double distance) {
    return distance > 1.0 && distance <= double(kMaxCameraDistance);  // NaN and infinities: no
}
// Throws leanfade::Error(setting, cause) for a distance outside that range or not finite;
// `text` is the value as given, for the message ("" to print the number).
void check_camera_distance(double distance, const std::string& setting,
                           const std::string& text = {});

// The point the camera looks at, bounding radii from the object's centre: each component finite
// and within kMaxCameraDistance (a target further away than the farthest camera puts the object
// outside every view, and its float products lose the object's whole size: --target 1e30,0,0
// rendered an empty frame with exit 0).
constexpr bool is_camera_target(const glm::vec3& target) {
    for (int i = 0; i < 3; ++i)
        if (!(target[i] >= -kMaxCameraDistance && target[i] <= kMaxCameraDistance)) return false;
    return true;
}
// Throws leanfade::Error(setting, "components must be in [-1e4, 1e4] bounding radii ...").
void check_camera_target(const glm::vec3& target, const std::string& setting);

// The vertical field of view, degrees: in (kMinFovDegrees, kMaxFovDegrees).
inline constexpr float kMinFovDegrees = 1.0f;
inline constexpr float kMaxFovDegrees = 170.0f;
constexpr bool is_field_of_view(float degrees) {
    return degrees > kMinFovDegrees && degrees < kMaxFovDegrees;
}
// Throws leanfade::Error(setting, "must be in (1, 170) degrees, got ...") outside that range.
void check_field_of_view(float degrees, const std::string& setting);

}  // namespace leanfade
