#pragma once
// What the renderer draws: objects (a mesh, a transform and a material) and their materials (the
// maps and the parameters that differ from the frame's shading settings). GL-free.
//
// Today a material has one bump map, a LEAN map (leanfade/core/lean_map.hpp); bump layers will add
// more. Its parameters override ShadingSettings for the objects that use it; those it leaves
// unset come from the frame's settings.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/scene/mesh.hpp"

namespace leanfade::scene {

struct Material {
    std::string name;
    int lean_map = 0;                   // index into Scene::lean_maps
    std::optional<glm::vec3> diffuse;   // Kd, linear RGB (a glTF base colour factor)
    std::optional<glm::vec3> specular;  // Ks, linear RGB
    std::optional<float> shininess;     // Blinn-Phong exponent s > 0
    // Index into Scene::base_color_textures, or -1: the diffuse colour Kd is multiplied by the
    // texture (a glTF base colour texture) at the surface's tiled uv.
    int base_color_texture = -1;
};

struct Object {
    Mesh mesh;
    int material = 0;           // index into Scene::materials
    glm::mat4 transform{1.0f};  // object space -> scene space (a glTF node's world matrix)
};

struct Scene {
    std::vector<Object> objects;
    std::vector<Material> materials;
    std::vector<PackedLeanMap> lean_maps;
    // Base colour textures: 4-channel float images of linear RGB (sRGB decoded) and alpha, rows
    // top first (uploaded flipped, like every texture: v up).
    std::vector<Image> base_color_textures;
};

// The scene-space bounding box of every object's transformed bounds (its eight corners).
Bounds scene_bounds(const Scene& scene);

// Throws leanfade::Error(setting, cause) for a scene the renderer cannot draw: no object, a
// material or map index out of range, an object without triangles, an override that is not
// finite (or a shininess <= 0), a transform that is not finite or not invertible.
void validate(const Scene& scene);

}  // namespace leanfade::scene
