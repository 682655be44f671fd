// The viewer's orbit camera and fly-away animation (no GL).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/glm.hpp>

#include "leanfade/viewer/camera.hpp"

namespace leanfade::viewer {
namespace {

constexpr float kTolerance = 1e-5f;

void expect_near(const glm::vec3& a, const glm::vec3& b, float tolerance = kTolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(OrbitCamera, DefaultsMatchTheFigures) {
    const OrbitCamera camera;
    const gl::View figure = gl::view_at_distance(3.0f);
    const gl::View view = camera.view();
    expect_near(view.eye, figure.eye);
    expect_near(view.target, figure.target);
    EXPECT_FLOAT_EQ(view.fov_y_degrees, figure.fov_y_degrees);
    EXPECT_NEAR(view.near_plane, figure.near_plane, kTolerance);
    EXPECT_NEAR(view.far_plane, figure.far_plane, kTolerance);
}

TEST(OrbitCamera, SettingsRoundTrip) {
    CameraSettings s;
    s.target = {0.2f, -0.3f, 0.1f};
    s.direction = {3.0f, 2.0f, -1.0f};
    s.distance = 12.5f;
    s.fov_y_degrees = 50.0f;
    const OrbitCamera camera(s);
    const CameraSettings back = camera.settings();
    EXPECT_EQ(back.direction, s.direction);  // as given, until the camera turns
    expect_near(camera.direction(), glm::normalize(s.direction));
    expect_near(back.target, s.target);
    EXPECT_EQ(back.distance, 12.5f);
    EXPECT_EQ(back.fov_y_degrees, 50.0f);
    const gl::View view = camera.view();
    expect_near(view.eye, s.target + glm::normalize(s.direction) * 12.5f, 1e-4f);
    // Turning away and back gives the angles' own direction, still the same one.
    OrbitCamera turned = camera;
    turned.orbit(10.0f, 0.0f);
    turned.orbit(-10.0f, 0.0f);
    expect_near(glm::normalize(turned.settings().direction), glm::normalize(s.direction), 1e-5f);
}

TEST(OrbitCamera, ZoomAndPitchStayInRange) {
    OrbitCamera camera;
    camera.zoom(1e-6f);
    EXPECT_EQ(camera.distance, kMinOrbitDistance);
    camera.zoom(1e9f);
    EXPECT_EQ(camera.distance, kMaxCameraDistance);
    camera.zoom(0.0f);  // ignored
    EXPECT_EQ(camera.distance, kMaxCameraDistance);
    camera.orbit(0.0f, 500.0f);
    EXPECT_EQ(camera.pitch_degrees, kMaxPitchDegrees);
    camera.orbit(725.0f, -1000.0f);
    EXPECT_EQ(camera.pitch_degrees, -kMaxPitchDegrees);
    EXPECT_NEAR(camera.yaw_degrees, 5.0f, 1e-3f);
    // Straight up or down is looked at with a finite view matrix.
    CameraSettings up;
    up.direction = {0.0f, 1.0f, 0.0f};
    const glm::mat4 m = OrbitCamera(up).view().view_matrix();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_TRUE(std::isfinite(m[c][r]));
    const glm::mat4 straight = gl::view_at_distance(3.0f, 34.0f, up.direction).view_matrix();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_TRUE(std::isfinite(straight[c][r]));
}

TEST(OrbitCamera, PanMovesInTheImagePlane) {
    OrbitCamera camera;
    const glm::vec3 direction = camera.direction();
    const int height = 500;
    // Dragging by the image's full height moves the target by the view's height at its distance.
    camera.pan(0.0f, float(height), height);
    const float expected =
        2.0f * camera.distance * std::tan(glm::radians(camera.fov_y_degrees) / 2);
    EXPECT_NEAR(glm::length(camera.target), expected, 1e-4f);
    EXPECT_NEAR(glm::dot(camera.target, direction), 0.0f, 1e-5f);
    EXPECT_GT(camera.target.y, 0.0f);  // dragging down moves the scene down: the target goes up
    OrbitCamera sideways;
    sideways.pan(100.0f, 0.0f, height);
    EXPECT_LT(sideways.target.x, 0.0f);  // dragging right: the target moves left
    EXPECT_NEAR(sideways.target.y, 0.0f, 1e-6f);
}

TEST(FlyAway, GoesFromNearToFarAndBack) {
    const FlyAwaySettings s{2.0f, 50.0f, 10.0f};
    EXPECT_NEAR(fly_away_distance(s, 0.0), 2.0f, 1e-4f);
    EXPECT_NEAR(fly_away_distance(s, 5.0), 50.0f, 1e-3f);
    EXPECT_NEAR(fly_away_distance(s, 10.0), 2.0f, 1e-4f);
    EXPECT_NEAR(fly_away_distance(s, 2.5), std::sqrt(2.0f * 50.0f), 1e-3f);  // even in log
    float previous = 0.0f;
    for (int i = 0; i <= 50; ++i) {
        const float d = fly_away_distance(s, 0.1 * i);
        EXPECT_GE(d, previous);
        previous = d;
    }
}

}  // namespace
}  // namespace leanfade::viewer
