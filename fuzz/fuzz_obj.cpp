// Fuzz target: the Wavefront OBJ loader (scene::load_obj_from_memory: pre-check, tinyobjloader,
// triangulation, normals, box-projected UVs, tangents).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include <glm/geometric.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"

using namespace leanfade;

namespace {

template <class Vector>
bool finite(const Vector& v) {
    for (int i = 0; i < Vector::length(); ++i) {
        if (!std::isfinite(v[i])) return false;
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const scene::Mesh mesh = scene::load_obj_from_memory(
            std::string(reinterpret_cast<const char*>(data), size), "fuzz.obj");
        // The mesh.hpp contract: whole triangles, indices in range, finite vertices with unit
        // normals and tangents.
        if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) __builtin_trap();
        for (const std::uint32_t index : mesh.indices) {
            if (index >= mesh.vertices.size()) __builtin_trap();
        }
        for (const scene::Vertex& v : mesh.vertices) {
            if (!finite(v.position) || !finite(v.normal) || !finite(v.uv) || !finite(v.tangent)) {
                __builtin_trap();
            }
            if (std::abs(glm::length(v.normal) - 1.0f) > 1e-3f) __builtin_trap();
            if (std::abs(glm::length(glm::vec3(v.tangent)) - 1.0f) > 1e-3f) __builtin_trap();
        }
    } catch (const Error&) {
    }
    return 0;
}
