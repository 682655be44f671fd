#pragma once
// Triangle meshes of leanfade (no GL here; the renderer uploads these arrays directly).
//
// World convention for every mesh built by this library: right-handed, y up, object-space units
// are arbitrary "world units", and each built-in object is centred on the origin (its bounding box
// centre is (0, 0, 0), up to rounding).
//
// Tangent space (docs/math.md §1): T points along +u, the bitangent Bt along +v, N is the outward
// surface normal; T is orthonormalised against N by Gram-Schmidt and the handedness is stored in
// T.w so that Bt = T.w * cross(N, T.xyz). Texture coordinates follow the OpenGL convention (v up).
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

namespace leanfade::scene {

// One vertex: 15 tightly packed floats (60 bytes), standard layout, uploaded as is (offsets 0,
// 12, 24, 32, 48 and 56).
struct Vertex {
    glm::vec3 position;  // object space, world units
    glm::vec3 normal;    // object space, unit length, pointing out of the surface
    glm::vec2 uv;        // texture coordinates, set 0 (tiles of the bump texture; may exceed
                         // [0, 1]); glTF's TEXCOORD_0
    glm::vec4 tangent;   // xyz: unit, orthogonal to normal, along +u of the set the normal
                         // texture uses (uv unless a glTF normal texture reads TEXCOORD_1);
                         // w = +-1 handedness so that bitangent = w * cross(normal,
                         // tangent.xyz) points along that set's +v
    glm::vec2 uv1;       // texture coordinates, set 1: glTF's TEXCOORD_1 (UvTransform::set 1
                         // samples it); a copy of uv for every mesh with one set
    // The largest change per pixel of the normal's slope (dimensionless) up to which geometric
    // antialiasing trusts a pixel's normal derivatives here (docs/math.md §11): half the
    // normal's change to the neighbouring vertices where the mesh's normals are not smooth
    // over a few rings of neighbours (measure_normal_linearity); 0: smooth, or not measured
    // (the derivatives are always trusted).
    float linear_normal_change;
};
static_assert(std::is_standard_layout_v<Vertex>, "Vertex is uploaded to GL as raw floats");
static_assert(sizeof(Vertex) == 15 * sizeof(float), "Vertex must be 15 tightly packed floats");
static_assert(offsetof(Vertex, linear_normal_change) == 14 * sizeof(float),
              "linear_normal_change follows uv1");
static_assert(offsetof(Vertex, uv1) == 12 * sizeof(float), "uv1 follows the tangent");

// Axis-aligned bounding box in object space (world units).
struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};

    // Centre of the box, world units.
    glm::vec3 center() const;
    // Radius of a sphere about center() enclosing the box (half its diagonal), world units.
    float radius() const;
};

// An indexed triangle list.
struct Mesh {
    std::string name;                    // "sphere", "teapot", the OBJ file's stem, ...
    std::vector<Vertex> vertices;        // see Vertex for spaces and units
    std::vector<std::uint32_t> indices;  // 3 per triangle, counter-clockwise front faces seen from
                                         // outside (the side the normals point to)
    Bounds bounds;                       // of all vertex positions; see compute_bounds()

    // indices.size() / 3.
    std::size_t triangle_count() const;
};

// Recomputes mesh.tangent for every vertex from positions, UVs and normals (unitless directions).
// Per triangle, dP/du and dP/dv (object space) are solved from the UV differences; their unit
// directions are accumulated per vertex weighted by triangle area, T is made orthogonal to the
// vertex normal by Gram-Schmidt and normalised, and w = sign(dot(cross(N, T), accumulated dP/dv))
// (+1 when undecided). Triangles with degenerate UVs (zero UV area) or zero area contribute
// nothing; a vertex left without a usable direction gets T = cross(accumulated dP/dv, N) when
// that exists, otherwise any unit vector orthogonal to N, with w = +1.
// Throws leanfade::Error(mesh.name, cause) if an index is out of range or the index count is not
// a multiple of 3. Vertex normals must be unit length (they are not modified).
void generate_tangents(Mesh& mesh);

// Sets Vertex::linear_normal_change of every vertex from the mesh's own normals (object space;
// the result is dimensionless, independent of the mesh's scale). Around each vertex, over its
// 1, 2, ... kLinearityRings rings of neighbours (by index: split normals are separate regions),
// the neighbours' normals, as slopes in the vertex's tangent frame, are fitted as a quadratic
// function of their offsets in its tangent plane. Where a ring's fit leaves a residual above a
// quarter of the slopes' spread, the normals are not smooth at the mesh's resolution and the
// vertex gets half its largest slope change to its first ring: a triangle's derivatives hold
// inside it, and the 2 x 2 pixels they come from fit in it while a pixel spans at most half an
// edge. Smooth vertices (a plane, a sphere, a torus) get 0. docs/math.md §11.
inline constexpr int kLinearityRings = 4;
void measure_normal_linearity(Mesh& mesh);

// Sets mesh.bounds to the axis-aligned box of all vertex positions (object space, world units);
// an empty mesh gets a zero box at the origin. Throws leanfade::Error(mesh.name, cause) when the
// box's bounding radius is not 0 and outside [1e-12, 1e12] (the renderer's float scaling).
void compute_bounds(Mesh& mesh);

}  // namespace leanfade::scene
