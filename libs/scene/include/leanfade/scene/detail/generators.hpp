#pragma once
// Built-in meshes. All follow the convention of mesh.hpp: right-handed, y up, centred on the
// origin, CCW front faces seen from outside, unit outward normals, tangents from
// generate_tangents() (T along +u, bitangent along +v, right-handed: T.w = +1 on every built-in
// object). Texture coordinates repeat the bump texture in whole tiles with seams duplicated, so
// u and v are continuous across each seam and one tile spans about kTileLength world units.
// Triangle counts at the defaults approximate the specular-fading paper's (docs/math.md §8).
// Invalid arguments throw leanfade::Error(object name, cause).
#include <cstdint>

#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::scene {

// Approximate length of one bump-texture tile on the built-in objects, world units.
inline constexpr float kTileLength = 0.4f;

// Unit sphere (radius 1 world unit) about the origin, poles on +-y. `segments` around the y axis
// (3 to 4096), `stacks` from pole to pole (2 to 4096); triangles = 2 * segments * (stacks - 1),
// i.e. 1,984 at the defaults (each pole is a fan of `segments` triangles, each with its own pole
// vertex). u = 16 * longitude / 2 pi in [0, 16] (increasing toward +x seen from +z), v in [0, 8]
// from the south pole (v = 0, y = -1) to the north pole (v = 8, y = +1).
Mesh make_sphere(int segments = 32, int stacks = 32);

// Torus about the y axis: tube centre radius 0.75, tube radius 0.25 (outer radius 1 world unit,
// height 0.5). `major_segments` around the y axis, `minor_segments` around the tube (each 3 to
// 4096); triangles = 2 * major * minor, i.e. 5,824 at the defaults (91 x 32).
// u in [0, 12] around the y axis (same sense as the sphere's longitude), v in [0, 4] around the
// tube (increasing from the outer equator upward).
Mesh make_torus(int major_segments = 91, int minor_segments = 32);

// The Utah teapot: the 32 bicubic Bezier patches of Newell's data (embedded in the library),
// each evaluated exactly on a (subdivisions + 1)^2 parameter grid; normals are the normalised
// cross product of the patch derivatives, with the exact limit at the collapsed lid-top and
// bottom poles. The data's z-up axes are rotated to y up (x stays x, spout toward +x, handle
// toward -x), scaled by 1/3 (about 2.14 x 1.05 x 1.33 world units) and translated so the
// bounding box is centred on the origin. Every patch has its own vertices (no welding across
// patches, so each keeps its UVs); triangles at a collapsed edge are dropped, so triangles =
// 64 * n^2 - 8 * n for n = subdivisions (1 to 512): 78,120 at the default 35. Per patch, u and v
// run over [0, k] with k a whole number of tiles (about kTileLength each) along that parameter. The
// surface is not closed: the lid rests on the rim, and the handle and spout pierce the body.
Mesh make_teapot(int subdivisions = 35);

// A 20 x 20 world-unit fBm terrain: a regular grid of 247 x 247 cells (248^2 = 61,504 vertices,
// 122,018 triangles) over x, z in [-10, 10] with heights y = f(x, z) from 5 octaves of gradient
// noise (roughly +-2 world units), shifted so the bounding box is centred on the origin; normals
// from the height field's central differences. The same seed always gives the same mesh (no
// platform-dependent random numbers). u = (x + 10) / 0.4 and v = (10 - z) / 0.4 in [0, 50]:
// u along +x, v along -z, so the frame is right-handed with the +y-facing normal.
Mesh make_terrain(std::uint32_t seed = 1);

// A flat square in the xz-plane at y = 0, facing +y, centred on the origin: x, z in
// [-size / 2, size / 2] (size > 0 world units), `segments` x `segments` quads (1 to 4096),
// 2 * segments^2 triangles. u = (x + size / 2) / kTileLength runs along +x and
// v = (size / 2 - z) / kTileLength along -z.
Mesh make_plane(float size = 20.0f, int segments = 64);

}  // namespace leanfade::scene
