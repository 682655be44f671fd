#pragma once
// A camera given in a scene's own space and units (metres for the ocean, leanfade/scene/detail/ocean.hpp)
// as the renderer's View in world space (Renderer::model_matrix(): the scene moved and scaled to
// its unit bounding sphere, without rotation).
#include <glm/glm.hpp>

#include "leanfade/gl/renderer.hpp"

namespace leanfade::gl {

// eye and target in scene space; near and far planes in scene units from the eye (> 0, near <
// far); the vertical field of view in degrees. y stays up.
inline View view_in_scene(const glm::mat4& model, glm::vec3 eye, glm::vec3 target,
                          float fov_y_degrees, float near_plane, float far_plane) {
    View view;
    view.eye = glm::vec3(model * glm::vec4(eye, 1.0f));
    view.target = glm::vec3(model * glm::vec4(target, 1.0f));
    view.up = glm::vec3(0.0f, 1.0f, 0.0f);
    view.fov_y_degrees = fov_y_degrees;
    const float scale = glm::length(glm::vec3(model[0]));  // uniform: world units per scene unit
    view.near_plane = near_plane * scale;
    view.far_plane = far_plane * scale;
    return view;
}

}  // namespace leanfade::gl
