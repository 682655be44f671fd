// Cameras of the renderer: view and projection matrices, views at a distance in bounding radii.
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/renderer.hpp"

namespace leanfade::gl {

glm::mat4 View::view_matrix() const {
    return glm::lookAt(eye, target, up);
}

glm::mat4 View::projection_matrix(float aspect) const {
    return glm::perspective(glm::radians(fov_y_degrees), aspect, near_plane, far_plane);
}

View view_at_distance(float distance, float fov_y_degrees, glm::vec3 direction, glm::vec3 target) {
    check_camera_distance(distance, "distances");
    check_field_of_view(fov_y_degrees, "fov");
    if (!(glm::length(direction) > 0.0f) || !std::isfinite(glm::length(direction)))
        throw Error::setting("view_dir", "must be a finite, non-zero vector");
    if (!std::isfinite(target.x) || !std::isfinite(target.y) || !std::isfinite(target.z))
        throw Error::setting("target", "must be finite");
    View v;
    const glm::vec3 unit = glm::normalize(direction);
    v.eye = target + unit * distance;
    v.target = target;
    v.up = std::abs(unit.y) > 0.9999f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    v.fov_y_degrees = fov_y_degrees;
    // Near and far planes enclose the unit sphere about the object's centre (the origin).
    const float centre_distance = target == glm::vec3(0.0f) ? distance : glm::length(v.eye);
    v.near_plane = std::max(0.01f, 0.9f * (centre_distance - 1.0f));
    v.far_plane = 1.1f * (centre_distance + 1.0f);
    return v;
}

float projected_radius_pixels(const View& view, int height) {
    const float d = glm::length(view.eye - view.target);
    const float tangent = 1.0f / std::sqrt(std::max(d * d - 1.0f, 1e-6f));  // tan(asin(1/d))
    return tangent / std::tan(glm::radians(view.fov_y_degrees) * 0.5f) * 0.5f * float(height);
}

}  // namespace leanfade::gl
