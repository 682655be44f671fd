#pragma once
// The viewer's orbit camera and its "fly away" animation. World units are object bounding radii
// (the renderer scales every object to a unit bounding sphere at the origin), y is up.
#include <glm/vec3.hpp>

#include "leanfade/core/detail/preset.hpp"
#include "leanfade/gl/renderer.hpp"

namespace leanfade::viewer {

// Closest the camera may come to the point it looks at, in bounding radii.
inline constexpr float kMinOrbitDistance = 1.05f;
// Pitch is kept inside +-kMaxPitchDegrees so that the view never flips over the pole.
inline constexpr float kMaxPitchDegrees = 89.0f;

class OrbitCamera {
  public:
    OrbitCamera() : OrbitCamera(CameraSettings{}) {}
    explicit OrbitCamera(const CameraSettings& settings);

    // The camera as a preset stores it (direction from the target toward the eye, unit length).
    CameraSettings settings() const;
    // The renderer's view: near and far planes enclose the unit sphere.
    gl::View view() const;
    // Unit vector from the target toward the eye.
    glm::vec3 direction() const;

    // Turns about the target: yaw about the world's y axis, pitch up or down (degrees).
    void orbit(float yaw_degrees, float pitch_degrees);
    // Multiplies the distance by `factor`, kept in [kMinOrbitDistance, kMaxCameraDistance].
    void zoom(float factor);
    // Moves the target (and the eye with it) in the image plane so that the point under the
    // cursor follows it: dx, dy in pixels (x right, y down) of an image `height` pixels tall.
    void pan(float dx, float dy, int height);

    float yaw_degrees = 0.0f;    // 0: eye on +z; 90: eye on +x
    float pitch_degrees = 0.0f;  // > 0: eye above the target
    float distance = 3.0f;       // eye to target, bounding radii
    glm::vec3 target{0.0f};
    float fov_y_degrees = 34.0f;

  private:
    bool unchanged() const;
    // The direction the camera was made with (as given, any length), used as long as yaw and
    // pitch are unchanged, so that a preset read and written again, or rendered by
    // `leanfade render --preset`, keeps it exactly.
    glm::vec3 given_direction_{0.0f, 0.0f, 1.0f};
    float given_yaw_ = 0.0f;
    float given_pitch_ = 0.0f;
};

// Distance of the "fly away" animation `seconds` after it started: from near to far and back
// over one period, evenly in log distance (a cosine ease), so that fading is seen in motion.
float fly_away_distance(const FlyAwaySettings& settings, double seconds);

}  // namespace leanfade::viewer
