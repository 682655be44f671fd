#pragma once
// Geometric checks shared by the scene tests.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::scene::test {

// Per-vertex frame statistics (worst cases over all vertices).
struct FrameStats {
    std::size_t non_finite = 0;           // vertices with any NaN / inf component
    float max_normal_error = 0.0f;        // max | |N| - 1 |
    float max_tangent_error = 0.0f;       // max | |T| - 1 |
    float max_tangent_dot_normal = 0.0f;  // max |T . N|
    std::size_t bad_handedness = 0;       // |w| != 1
    std::size_t left_handed = 0;          // w == -1
};
FrameStats frame_stats(const Mesh& mesh);

// Agreement of the vertex tangent frames with each triangle's UV derivatives. For each corner of
// each triangle with non-degenerate UVs: the cosine between the vertex T projected into the
// triangle plane and dP/du, and between the bitangent w * cross(N, T) projected and dP/dv.
struct UvFrameStats {
    std::size_t corners = 0;       // corners checked
    float min_cos_tangent = 1.0f;  // worst T vs dP/du
    float min_cos_bitangent = 1.0f;
    // Bitangent against the part of dP/dv orthogonal to the projected T (the Gram-Schmidt frame
    // cannot follow a skewed parametrisation, so this is the strict comparison).
    float min_cos_bitangent_orthogonal = 1.0f;
    std::size_t tangent_opposed = 0;    // corners with cos(T, dP/du) <= 0
    std::size_t bitangent_opposed = 0;  // corners with cos(B, dP/dv) <= 0
};
UvFrameStats uv_frame_stats(const Mesh& mesh);

// Vertex normals against the geometric normal of their triangles (CCW winding).
struct WindingStats {
    std::size_t triangles = 0;
    std::size_t degenerate = 0;   // zero-area triangles (skipped)
    std::size_t disagreeing = 0;  // triangles with some corner normal . face normal <= 0
    float min_dot = 1.0f;         // min over corners of N . face normal (unit vectors)
};
WindingStats winding_stats(const Mesh& mesh);

// Topology after welding positions closer than `tolerance` (world units): each undirected edge
// counted by how often it appears in each direction.
struct EdgeStats {
    std::size_t welded_vertices = 0;
    std::size_t edges = 0;           // undirected edges
    std::size_t boundary = 0;        // used by exactly one triangle
    std::size_t paired = 0;          // used exactly twice, in opposite directions
    std::size_t same_direction = 0;  // used twice in the same direction (inconsistent winding)
    std::size_t non_manifold = 0;    // used three or more times
    std::size_t degenerate_triangles = 0;  // triangles with two corners welded together
};
EdgeStats edge_stats(const Mesh& mesh, float tolerance = 1e-5f);

// For each vertex, the id of its welded position (positions closer than `tolerance` share an id;
// ids are 0 .. count - 1).
std::vector<std::uint32_t> weld_positions(const Mesh& mesh, float tolerance, std::size_t& count);

// Signed volume enclosed by the triangles, (1/6) sum p0 . (p1 x p2); positive when a closed mesh
// is wound counter-clockwise seen from outside.
double signed_volume(const Mesh& mesh);

// True when every index is in range and the count is a multiple of 3.
bool indices_valid(const Mesh& mesh);

}  // namespace leanfade::scene::test
