// Scenes of objects and materials (leanfade/scene/material.hpp).
#include "leanfade/scene/material.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "leanfade/core/error.hpp"

namespace leanfade::scene {
namespace {

bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

Bounds scene_bounds(const Scene& scene) {
    const float inf = std::numeric_limits<float>::infinity();
    Bounds box{glm::vec3(inf), glm::vec3(-inf)};
    for (const Object& o : scene.objects)
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p((corner & 1) ? o.mesh.bounds.max.x : o.mesh.bounds.min.x,
                              (corner & 2) ? o.mesh.bounds.max.y : o.mesh.bounds.min.y,
                              (corner & 4) ? o.mesh.bounds.max.z : o.mesh.bounds.min.z);
            const glm::vec3 q = glm::vec3(o.transform * glm::vec4(p, 1.0f));
            box.min = glm::min(box.min, q);
            box.max = glm::max(box.max, q);
        }
    if (scene.objects.empty()) return Bounds{};
    return box;
}

void validate(const Scene& scene) {
    if (scene.objects.empty()) throw Error("scene", "the scene has no object");
    for (const Material& m : scene.materials) {
        if (m.lean_map < 0 || m.lean_map >= int(scene.lean_maps.size()))
            throw Error("scene", "material '" + m.name + "' uses LEAN map " +
                                     std::to_string(m.lean_map) + " of " +
                                     std::to_string(scene.lean_maps.size()));
        if ((m.diffuse && !finite(*m.diffuse)) || (m.specular && !finite(*m.specular)) ||
            (m.shininess && !(*m.shininess > 0.0f && std::isfinite(*m.shininess))))
            throw Error("scene", "material '" + m.name +
                                     "' has a colour or shininess that is "
                                     "not a finite, positive number");
        if (m.base_color_texture < -1 ||
            m.base_color_texture >= int(scene.base_color_textures.size()))
            throw Error("scene", "material '" + m.name + "' uses base colour texture " +
                                     std::to_string(m.base_color_texture) + " of " +
                                     std::to_string(scene.base_color_textures.size()));
    }
    for (const Image& texture : scene.base_color_textures)
        if (texture.channels != 4 || texture.width < 1 || texture.height < 1)
            throw Error("scene", "a base colour texture is not a non-empty RGBA image");
    for (const Object& o : scene.objects) {
        if (o.material < 0 || o.material >= int(scene.materials.size()))
            throw Error(o.mesh.name, "uses material " + std::to_string(o.material) + " of " +
                                         std::to_string(scene.materials.size()));
        if (o.mesh.vertices.empty() || o.mesh.indices.empty() || o.mesh.indices.size() % 3 != 0)
            throw Error(o.mesh.name, "the mesh has no triangles");
        for (int c = 0; c < 4; ++c)
            if (!finite(glm::vec3(o.transform[c])) || !std::isfinite(o.transform[c].w))
                throw Error(o.mesh.name, "the object's transform is not finite");
        const float det = glm::determinant(glm::mat3(o.transform));
        if (!(std::abs(det) > 1e-12f) || !std::isfinite(det))
            throw Error(o.mesh.name, "the object's transform is not invertible");
    }
}

}  // namespace leanfade::scene
