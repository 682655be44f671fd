// The camera's settings (leanfade/core/detail/camera.hpp).
#include "leanfade/core/detail/camera.hpp"

#include <cmath>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/text.hpp"

namespace leanfade {

void check_camera_distance(double distance, const std::string& setting, const std::string& text) {
    if (is_camera_distance(distance)) return;
    const std::string shown = text.empty() ? shortest_text(distance) : text;
    if (!(distance > 1.0) || !std::isfinite(distance))
        throw Error::setting(
            setting,
            "distances are in bounding radii from the object's centre and must be > 1, "
            "got " +
                shown);
    throw Error::setting(
        setting,
        "distances must be at most 1e4 bounding radii (the object covers far less than a "
        "pixel beyond), got " +
            shown);
}

void check_camera_target(const glm::vec3& target, const std::string& setting) {
    for (int i = 0; i < 3; ++i)
        if (!(target[i] >= -kMaxCameraDistance && target[i] <= kMaxCameraDistance))
            throw Error::setting(
                setting,
                "components must be in [-1e4, 1e4] bounding radii from the object's "
                "centre (beyond, the object is outside every view), got " +
                    shortest_text(target[i]));
}

void check_field_of_view(float degrees, const std::string& setting) {
    if (!is_field_of_view(degrees))
        throw Error::setting(setting, "must be in (1, 170) degrees, got " + shortest_text(degrees));
}

}  // namespace leanfade
