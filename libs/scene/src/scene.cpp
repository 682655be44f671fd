#include "leanfade/scene/scene.hpp"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"

namespace leanfade::scene {
namespace {

bool ends_with_obj(const std::string& s) {
    if (s.size() < 4) {
        return false;
    }
    std::string tail = s.substr(s.size() - 4);
    std::transform(tail.begin(), tail.end(), tail.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return tail == ".obj";
}

}  // namespace

std::vector<std::string> builtin_scene_names() {
    return {"sphere", "torus", "teapot", "terrain", "plane"};
}

Mesh make_scene_mesh(const std::string& name_or_path) {
    if (name_or_path == "sphere") {
        return make_sphere();
    }
    if (name_or_path == "torus") {
        return make_torus();
    }
    if (name_or_path == "teapot") {
        return make_teapot();
    }
    if (name_or_path == "terrain") {
        return make_terrain(1);
    }
    if (name_or_path == "plane") {
        return make_plane(20.0f, 64);
    }
    if (ends_with_obj(name_or_path)) {
        return load_obj(name_or_path);
    }
    std::string valid;
    for (const std::string& name : builtin_scene_names()) {
        valid += name + ", ";
    }
    throw Error(name_or_path, "unknown scene; valid: " + valid + "or a path ending in .obj");
}

}  // namespace leanfade::scene
