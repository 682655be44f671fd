#pragma once
// Helpers shared by the scene library's sources (not installed, not part of the API).
#include <functional>

#include <glm/glm.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::scene::detail {

// A normal map whose slopes are `scale` times those of `normals` (2 rgb - 1 decoded, X and Y
// scaled, renormalised, encoded again): glTF's normalTexture.scale, an MTL norm's -bm.
void scale_normals(Image& normals, float scale);

// Channel `channel` of `image` as a 1-channel image.
Image image_channel(const Image& image, int channel);

// An image of 1-4 channels as RGBA, values as they are: grey expanded to RGB, alpha kept (1 when
// absent).
Image rgba_of(const Image& image);

// A decoded colour texture (1-4 channels, sRGB encoded) as linear RGBA: rgba_of with the sRGB
// transfer function inverted on RGB.
Image linear_base_colour(const Image& decoded);

// Throws leanfade::Error(mesh.name, cause) unless the indices form whole triangles (a multiple
// of 3) and each names a vertex of the mesh.
void require_triangle_indices(const Mesh& mesh);

// Any unit vector orthogonal to the unit vector n (Duff et al. 2017, branchless basis).
glm::vec3 any_orthonormal(const glm::vec3& n);

// Drops vertices no triangle references and renumbers the indices (order of the rest kept).
void remove_unused_vertices(Mesh& mesh);

// Translates all positions so the bounding box is centred on the origin.
void center_on_origin(Mesh& mesh);

// uv1 = uv (the built-in meshes and OBJ files have one texture coordinate set), then
// generate_tangents(), measure_normal_linearity() and compute_bounds(): the last step of every
// builder.
void finish(Mesh& mesh);

// Which edges of a parameter grid collapse to a single point (a pole).
struct CollapsedEdges {
    bool v0 = false;  // t = 0
    bool v1 = false;  // t = 1
    bool u0 = false;  // s = 0
    bool u1 = false;  // s = 1
};

// Appends a (nu + 1) x (nv + 1) grid of vertices sampled at s = i / nu, t = j / nv (i along +u,
// j along +v) and two triangles per cell, (i,j) (i+1,j) (i+1,j+1) and (i,j) (i+1,j+1) (i,j+1),
// counter-clockwise in the (u, v) plane. Triangles with two corners on a collapsed edge are
// dropped, so each cell next to a pole keeps one triangle with its own pole vertex; that pole
// vertex is sampled at the middle of its cell along the edge (s or t shifted by half a cell) so
// its UV and limit normal belong to its triangle. The unused corner copy of each collapsed edge
// stays in the vertex array (see remove_unused_vertices()).
void append_grid(Mesh& mesh, int nu, int nv, const CollapsedEdges& collapsed,
                 const std::function<Vertex(double s, double t)>& vertex_at);

}  // namespace leanfade::scene::detail
