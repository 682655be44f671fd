#pragma once
// The vertex input of every shader variant (shaders/scene.vert): one interleaved binding of
// scene::Vertex, each attribute 32-bit floats at its location. Read by the renderer's vertex
// arrays (libs/gl) and by `leanfade shaders`' index (shaders.json `vertex_layout`).
#include <cstddef>

#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::scene {

struct VertexAttribute {
    int location;        // layout(location = ...) of scene.vert
    const char* name;    // the Vertex member (the shader's input is a_<name>)
    int components;      // floats
    std::size_t offset;  // bytes from the vertex's start
};

inline constexpr VertexAttribute kVertexAttributes[] = {
    {0, "position", 3, offsetof(Vertex, position)},
    {1, "normal", 3, offsetof(Vertex, normal)},
    {2, "uv", 2, offsetof(Vertex, uv)},
    {3, "tangent", 4, offsetof(Vertex, tangent)},
    {4, "uv1", 2, offsetof(Vertex, uv1)},
    {5, "linear_normal_change", 1, offsetof(Vertex, linear_normal_change)},
};

}  // namespace leanfade::scene
