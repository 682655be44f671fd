#pragma once
// The scene library's entry point: mesh types, built-in generators, OBJ loading, and a by-name
// dispatcher for command lines and configuration files.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/scene/detail/generators.hpp"
#include "leanfade/scene/detail/mesh.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"

namespace leanfade::scene {

// The built-in scenes, described once: the command lines' help and messages, the viewer's list
// and make_scene_mesh() read this table.
struct BuiltinScene {
    std::string_view name;         // in command lines and presets
    std::string_view description;  // one line for the docs and the viewer
    // Its one mesh at the default parameters (make_scene_mesh), or nullptr for a scene with a
    // builder of its own (the ocean: make_ocean_scene).
    Mesh (*make_mesh)();
    std::string_view help_note = {};  // what the --scene help adds after the name, or ""
};
inline constexpr std::array<BuiltinScene, 6> kBuiltinScenes{{
    {"sphere", "a unit sphere", +[] { return make_sphere(); }},
    {"torus", "a torus", +[] { return make_torus(); }},
    {"teapot", "the Utah teapot", +[] { return make_teapot(); }},
    {"terrain", "a procedural height field (seed 1)", +[] { return make_terrain(1); }},
    {"plane", "a flat 20 x 20 square", +[] { return make_plane(20.0f, 64); },
     "20 x 20 units, uv 0..50 for the built-in sets, 0..5 for a map of one's own"},
    {"ocean", "the animated ocean: moving Gabor wave layers (docs/ocean.md)", nullptr},
}};
// The built-in scene called `name`, or nullptr.
const BuiltinScene* find_builtin_scene(std::string_view name);

// The names make_scene_mesh() accepts besides OBJ paths: the rows of kBuiltinScenes that are
// one mesh, in table order ("sphere", "torus", "teapot", "terrain", "plane").
std::vector<std::string> builtin_scene_names();

// Every scene a rendering command accepts, for help texts and messages: the table's names (with
// their help notes), then the files ("sphere, torus, teapot, terrain, plane (20 x 20 units, ...),
// ocean, an .obj file or a glTF scene (.gltf, .glb)").
std::string scene_choices_text();

// A built-in object at its default parameters (see generators.hpp; "terrain" uses seed 1,
// "plane" is 20 x 20 world units in 64 x 64 quads), or load_obj(name_or_path) for a path ending
// in ".obj" (any case). Throws leanfade::Error(name_or_path, cause) for anything else, the cause
// listing the valid names, and whatever load_obj() throws.
Mesh make_scene_mesh(const std::string& name_or_path);

}  // namespace leanfade::scene
