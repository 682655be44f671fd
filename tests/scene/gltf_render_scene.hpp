#pragma once
// The render scene of a test glTF file, for the suites that draw glTF scenes.
#include <filesystem>
#include <string>

#include "leanfade/scene/gltf.hpp"
#include "test_gltf_builder.hpp"

namespace leanfade::scene::test {

// The render scene of `file` written as `<LEANFADE_TEST_TMP>/<folder>/<name>.glb` and loaded
// back (default bake settings: no cache).
inline Scene render_scene_of(const GltfTestFile& file, const std::string& folder,
                             const std::string& name) {
    const std::filesystem::path dir = std::filesystem::path(LEANFADE_TEST_TMP) / folder;
    std::filesystem::create_directories(dir);
    const std::string path = (dir / (name + ".glb")).string();
    write_gltf(file, path, GltfStorage::Binary);
    return make_render_scene(load_gltf(path), GltfBakeSettings{});
}

}  // namespace leanfade::scene::test
