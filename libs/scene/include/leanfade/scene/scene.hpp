#pragma once
// The scene library's entry point: mesh types, built-in generators, OBJ loading, and a by-name
// dispatcher for command lines and configuration files.
#include <string>
#include <vector>

#include "leanfade/scene/generators.hpp"
#include "leanfade/scene/mesh.hpp"
#include "leanfade/scene/obj_loader.hpp"

namespace leanfade::scene {

// The names make_scene_mesh() accepts besides OBJ paths, in a fixed order:
// "sphere", "torus", "teapot", "terrain", "plane".
std::vector<std::string> builtin_scene_names();

// A built-in object at its default parameters (see generators.hpp; "terrain" uses seed 1,
// "plane" is 20 x 20 world units in 64 x 64 quads), or load_obj(name_or_path) for a path ending
// in ".obj" (any case). Throws leanfade::Error(name_or_path, cause) for anything else, the cause
// listing the valid names, and whatever load_obj() throws.
Mesh make_scene_mesh(const std::string& name_or_path);

}  // namespace leanfade::scene
