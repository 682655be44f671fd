// Fuzz target: glTF and GLB loading (scene::load_gltf_from_memory: the GLB container, tinygltf's
// JSON parse, accessors, indices, node trees, MikkTSpace) and the render-scene assembly of what
// loads (image decoding and the LEAN bake of normal textures, no cache).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/gltf.hpp"

using namespace leanfade;

namespace {

template <class Vector>
bool finite(const Vector& v) {
    for (int i = 0; i < Vector::length(); ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    scene::GltfLoadOptions options;
    options.max_file_bytes = 1 << 20;
    options.max_vertices = 1 << 16;
    options.max_objects = 256;
    try {
        const scene::GltfScene gltf = scene::load_gltf_from_memory(
            std::vector<std::uint8_t>(data, data + size), "fuzz.glb", options);
        // The mesh.hpp contract for every object: whole triangles, indices in range, finite
        // vertices, unit normals and tangents orthogonal to them with w = +-1.
        for (const scene::GltfObject& o : gltf.objects) {
            const scene::Mesh& mesh = o.mesh;
            if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) __builtin_trap();
            for (std::uint32_t index : mesh.indices)
                if (index >= mesh.vertices.size()) __builtin_trap();
            for (const scene::Vertex& v : mesh.vertices) {
                if (!finite(v.position) || !finite(v.normal) || !finite(v.uv) ||
                    !finite(v.tangent))
                    __builtin_trap();
                if (std::abs(glm::length(v.normal) - 1.0f) > 1e-3f) __builtin_trap();
                if (std::abs(glm::length(glm::vec3(v.tangent)) - 1.0f) > 1e-3f) __builtin_trap();
                if (std::abs(v.tangent.w) != 1.0f) __builtin_trap();
            }
            if (o.material < 0 || std::size_t(o.material) >= gltf.materials.size())
                __builtin_trap();
        }
        scene::GltfBakeSettings settings;
        settings.max_image_size = 256;
        settings.threads = 1;
        (void)scene::make_render_scene(gltf, settings);
    } catch (const Error&) {
        // One-line errors are the expected outcome for malformed input.
    }
    return 0;
}
