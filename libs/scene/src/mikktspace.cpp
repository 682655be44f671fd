// MikkTSpace tangents (leanfade/scene/gltf.hpp), written from the algorithm's description:
// per-triangle dP/du directions and uv orientation, corner angles as weights, vertices welded by
// equal attributes and split by orientation.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/gltf.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

// The bits of a vertex's position, normal and uv: vertices with equal keys are one vertex of
// MikkTSpace (it welds by value, not by index).
using WeldKey = std::array<std::uint32_t, 8>;

struct WeldKeyHash {
    std::size_t operator()(const WeldKey& key) const noexcept {
        std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the eight words
        for (std::uint32_t word : key) {
            h ^= word;
            h *= 1099511628211ull;
        }
        return std::size_t(h);
    }
};

// The texture coordinates of `v` in `set` (0: uv, 1: uv1).
glm::vec2 uv_of(const Vertex& v, int set) {
    return set == 1 ? v.uv1 : v.uv;
}

WeldKey weld_key(const Vertex& v, int set) {
    const glm::vec2 uv = uv_of(v, set);
    const float values[8] = {v.position.x, v.position.y, v.position.z, v.normal.x,
                             v.normal.y,   v.normal.z,   uv.x,         uv.y};
    WeldKey key{};
    for (int i = 0; i < 8; ++i) {
        // +0 and -0 weld together.
        const float value = values[i] == 0.0f ? 0.0f : values[i];
        std::memcpy(&key[std::size_t(i)], &value, sizeof(float));
    }
    return key;
}

// `v` without its component along the unit vector n.
glm::dvec3 project_to_plane(const glm::dvec3& v, const glm::dvec3& n) {
    return v - n * glm::dot(n, v);
}

}  // namespace

void generate_mikktspace_tangents(Mesh& mesh, int uv_set) {
    const std::size_t vertex_count = mesh.vertices.size();
    if (uv_set != 0 && uv_set != 1)
        throw Error(mesh.name,
                    "texture coordinate set " + std::to_string(uv_set) + " is not 0 or 1");
    detail::require_triangle_indices(mesh);

    // Weld groups: one id per distinct (position, normal, uv of the set).
    std::vector<std::uint32_t> weld(vertex_count);
    {
        std::unordered_map<WeldKey, std::uint32_t, WeldKeyHash> ids;
        ids.reserve(vertex_count);
        for (std::size_t i = 0; i < vertex_count; ++i)
            weld[i] = ids.emplace(weld_key(mesh.vertices[i], uv_set), std::uint32_t(ids.size()))
                          .first->second;
    }

    // Per triangle: its orientation (+1 preserving, -1 mirrored, 0 degenerate uvs) and the unit
    // direction of dP/du; per (weld group, orientation): the angle-weighted sum of the corners'
    // projected directions.
    const std::size_t triangle_count = mesh.indices.size() / 3;
    std::vector<int> orientation(triangle_count, 0);
    std::vector<glm::dvec3> sums(2 * vertex_count, glm::dvec3(0.0));  // [group * 2 + (w < 0)]
    for (std::size_t t = 0; t < triangle_count; ++t) {
        const std::uint32_t* corner = &mesh.indices[3 * t];
        const Vertex* v[3] = {&mesh.vertices[corner[0]], &mesh.vertices[corner[1]],
                              &mesh.vertices[corner[2]]};
        const glm::dvec3 d1 = glm::dvec3(v[1]->position) - glm::dvec3(v[0]->position);
        const glm::dvec3 d2 = glm::dvec3(v[2]->position) - glm::dvec3(v[0]->position);
        const glm::dvec2 s1 = glm::dvec2(uv_of(*v[1], uv_set)) - glm::dvec2(uv_of(*v[0], uv_set));
        const glm::dvec2 s2 = glm::dvec2(uv_of(*v[2], uv_set)) - glm::dvec2(uv_of(*v[0], uv_set));
        // Twice the signed uv area; dP/du = (s2.y d1 - s1.y d2) / area.
        const double area = s1.x * s2.y - s1.y * s2.x;
        if (!(std::abs(area) > 0.0) || !std::isfinite(area)) continue;
        const int sign = area > 0.0 ? 1 : -1;
        const glm::dvec3 dp_du = (s2.y * d1 - s1.y * d2) * double(sign);
        const double length = glm::length(dp_du);
        if (!(length > 0.0) || !std::isfinite(length)) continue;
        orientation[t] = sign;
        const glm::dvec3 direction = dp_du / length;
        for (int c = 0; c < 3; ++c) {
            const glm::dvec3 n = glm::dvec3(v[c]->normal);
            const glm::dvec3 p = glm::dvec3(v[c]->position);
            glm::dvec3 e1 = project_to_plane(glm::dvec3(v[(c + 1) % 3]->position) - p, n);
            glm::dvec3 e2 = project_to_plane(glm::dvec3(v[(c + 2) % 3]->position) - p, n);
            const double l1 = glm::length(e1), l2 = glm::length(e2);
            if (!(l1 > 0.0) || !(l2 > 0.0)) continue;  // a zero-area corner weighs nothing
            const double angle = std::acos(std::clamp(glm::dot(e1 / l1, e2 / l2), -1.0, 1.0));
            glm::dvec3 tangent = project_to_plane(direction, n);
            const double tangent_length = glm::length(tangent);
            if (!(tangent_length > 0.0)) continue;
            tangent /= tangent_length;
            sums[2 * weld[corner[c]] + (sign < 0 ? 1 : 0)] += angle * tangent;
        }
    }

    // Each corner takes its group's tangent for its triangle's orientation; a triangle with
    // degenerate uvs takes, per corner, the orientation the vertex already has (else +1). A
    // vertex needed with both orientations gets a copy for the second.
    constexpr std::uint32_t kUnassigned = ~std::uint32_t(0);
    std::vector<std::array<std::uint32_t, 2>> output_vertex(vertex_count,
                                                            {kUnassigned, kUnassigned});
    std::vector<Vertex> vertices = mesh.vertices;
    auto tangent_of = [&](std::uint32_t vertex, int slot) {
        const glm::dvec3 n = glm::dvec3(mesh.vertices[vertex].normal);
        glm::dvec3 sum = sums[2 * weld[vertex] + std::size_t(slot)];
        sum = project_to_plane(sum, n);
        const double length = glm::length(sum);
        if (length > 1e-20 && std::isfinite(length))
            return glm::vec4(glm::vec3(sum / length), slot == 0 ? 1.0f : -1.0f);
        return glm::vec4(detail::any_orthonormal(glm::vec3(n)), 1.0f);
    };
    // First the corners of oriented triangles, then the degenerate ones.
    for (int pass = 0; pass < 2; ++pass)
        for (std::size_t t = 0; t < triangle_count; ++t) {
            if ((orientation[t] == 0) != (pass == 1)) continue;
            for (int c = 0; c < 3; ++c) {
                std::uint32_t& index = mesh.indices[3 * t + std::size_t(c)];
                const std::uint32_t vertex = index;
                std::array<std::uint32_t, 2>& out = output_vertex[vertex];
                int slot = orientation[t] < 0 ? 1 : 0;
                if (orientation[t] == 0) {
                    if (out[0] != kUnassigned || out[1] != kUnassigned) {
                        index = out[0] != kUnassigned ? out[0] : out[1];
                        continue;
                    }
                    slot = 0;
                }
                if (out[std::size_t(slot)] == kUnassigned) {
                    const bool other_used = out[std::size_t(1 - slot)] != kUnassigned;
                    if (!other_used) {
                        out[std::size_t(slot)] = vertex;
                    } else {
                        out[std::size_t(slot)] = std::uint32_t(vertices.size());
                        vertices.push_back(mesh.vertices[vertex]);
                    }
                    vertices[out[std::size_t(slot)]].tangent = tangent_of(vertex, slot);
                }
                index = out[std::size_t(slot)];
            }
        }
    // Vertices no triangle uses keep a valid frame too.
    for (std::size_t i = 0; i < vertex_count; ++i)
        if (output_vertex[i][0] == kUnassigned && output_vertex[i][1] == kUnassigned)
            vertices[i].tangent = tangent_of(std::uint32_t(i), 0);
    mesh.vertices = std::move(vertices);
}

}  // namespace leanfade::scene
