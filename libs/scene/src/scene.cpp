#include "leanfade/scene/detail/scene.hpp"

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

const BuiltinScene* find_builtin_scene(std::string_view name) {
    for (const BuiltinScene& scene : kBuiltinScenes)
        if (scene.name == name) return &scene;
    return nullptr;
}

std::vector<std::string> builtin_scene_names() {
    std::vector<std::string> names;
    for (const BuiltinScene& scene : kBuiltinScenes)
        if (scene.make_mesh != nullptr) names.emplace_back(scene.name);
    return names;
}

std::string scene_choices_text() {
    std::string text;
    for (const BuiltinScene& scene : kBuiltinScenes) {
        text += scene.name;
        if (!scene.help_note.empty()) text += " (" + std::string(scene.help_note) + ")";
        text += ", ";
    }
    return text + "an .obj file or a glTF scene (.gltf, .glb)";
}

Mesh make_scene_mesh(const std::string& name_or_path) {
    const BuiltinScene* scene = find_builtin_scene(name_or_path);
    if (scene != nullptr && scene->make_mesh != nullptr) return scene->make_mesh();
    if (ends_with_obj(name_or_path)) {
        return load_obj(name_or_path);
    }
    if (scene != nullptr) throw Error(name_or_path, "is a scene of its own, not one mesh");
    throw Error(name_or_path, "unknown scene; valid: " + scene_choices_text());
}

}  // namespace leanfade::scene
