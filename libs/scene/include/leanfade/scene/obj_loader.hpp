#pragma once
// Wavefront OBJ loading (tinyobjloader), into the conventions of mesh.hpp.
#include <string>

#include "leanfade/scene/mesh.hpp"

namespace leanfade::scene {

// Loads every face of every object in an OBJ file into one mesh named after the file's stem.
// Positions are kept as stored (object space, the file's units; no re-centring or axis change).
// Polygons are triangulated in linear time: quads on their shorter diagonal, faces of up to 64
// vertices by ear clipping (concave faces come out right), larger ones as fans; vertices are
// shared where position, normal and UV indices all agree. Missing (or zero-length) normals are computed as the area-weighted average of the
// normals of the triangles around each position index (smooth shading). Missing UVs use a box
// projection: each triangle picks the axis its geometric normal is most aligned with (with sign)
// and projects onto the other two, oriented so that (+u, +v, axis) is right-handed, in units of
// the largest bounding-box extent (so the object spans about one tile). Tangents are always
// computed by generate_tangents(); bounds by compute_bounds(). Materials are ignored.
// Throws leanfade::Error(path, cause) with a one-line cause when the file cannot be read, does
// not parse, has a non-numeric or non-finite coordinate, an index out of range, or no triangles.
Mesh load_obj(const std::string& path);

// load_obj on a file's text already in memory (same checks and messages); `name` is the file
// name the errors give and whose stem names the mesh.
Mesh load_obj_from_memory(const std::string& text, const std::string& name);

}  // namespace leanfade::scene
