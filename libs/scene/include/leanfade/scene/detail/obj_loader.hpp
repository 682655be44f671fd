#pragma once
// Wavefront OBJ loading (tinyobjloader), into the conventions of mesh.hpp.
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/scene/detail/mesh.hpp"

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
// computed by generate_tangents(); bounds by compute_bounds(). Materials are ignored
// (load_obj_model reads them).
// Throws leanfade::Error(path, cause) with a one-line cause when the file cannot be read, does
// not parse, has a non-numeric or non-finite coordinate, an index out of range, or no triangles.
Mesh load_obj(const std::string& path);

// load_obj on a file's text already in memory (same checks and messages); `name` is the file
// name the errors give and whose stem names the mesh.
Mesh load_obj_from_memory(const std::string& text, const std::string& name);

// An OBJ file with its material statements: the mesh of load_obj split by `usemtl` into one part
// per material (the faces before any usemtl form the part of material -1), each part with the
// vertices its triangles use (normals and tangents of the whole mesh: no seams between parts).
struct ObjModel {
    std::string path;
    std::vector<Mesh> parts;
    std::vector<int> part_materials;          // per part: index into material_names, or -1
    std::vector<std::string> material_names;  // usemtl names, in order of first use
    std::vector<std::string> libraries;       // mtllib names as written (relative to the OBJ)
};
ObjModel load_obj_model(const std::string& path);

// One material of an MTL file (newmtl and the statements leanfade reads; others are ignored).
// Texture paths are as written, relative to the MTL's folder.
struct MtlMaterial {
    std::string name;
    std::optional<glm::vec3> kd;      // Kd: diffuse colour, linear RGB
    std::optional<glm::vec3> ks;      // Ks: specular colour
    std::optional<float> ns;          // Ns: Blinn-Phong exponent (> 0; 0 is left unset)
    std::optional<float> roughness;   // Pr: perceptual roughness r in [0, 1] (PBR extension)
    std::string kd_map;               // map_Kd: base colour texture (sRGB)
    std::string roughness_map;        // map_Pr: perceptual roughness texture
    std::string bump_map;             // map_Bump / bump: a height map ...
    std::string normal_map;           // norm: ... or a tangent-space normal map
    float bump_multiplier = 1.0f;     // -bm of map_Bump / bump / norm
};
// Parses an MTL file (every number checked; options other than -bm skipped with their values;
// backslashes in paths read as '/'). Throws leanfade::Error(path, "line N: cause").
std::vector<MtlMaterial> parse_mtl(const std::string& text, const std::string& path);
std::vector<MtlMaterial> load_mtl(const std::string& path);

// How make_obj_render_scene bakes the materials' bump and normal maps.
struct ObjBakeSettings {
    Storage storage = Storage::Unorm16;
    bool auto_storage = true;    // storage by a StorageProbe (lean_map.hpp), ignoring `storage`
    int max_image_size = kDefaultMaxImageDimension;  // per side, checked before decoding
    int threads = 0;
    bool strict_normals = false;  // BakeOptions::strict_normals
};
struct ObjSceneReport {
    // usemtl names no MTL file defines; map_Bump files taken as normal maps
    std::vector<std::string> warnings;
    std::vector<std::pair<std::string, NormalRepairs>> repaired;  // normal maps, by file
};

// The renderer's scene (material.hpp) of an OBJ model and its MTL files, as make_render_scene
// makes a glTF scene's: one object per part, one material per MTL material used, with Kd, Ks,
// Ns (the Blinn-Phong shininess), its map_Kd (sRGB, decoded to linear RGBA, times Kd), its Pr or
// map_Pr (the base roughness map, alpha0^2 = r^4, read by Cook-Torrance) and its bump map baked
// to a LEAN map: map_Bump / bump a height map at strength -bm (height per texel spacing), or a
// normal map when it is a colour image (bake's content rule, BakeSource::Auto; a warning says
// so), norm a normal map (OpenGL convention) with slopes times -bm; no bump map: flat. Parts without a
// material, or whose usemtl no MTL file defines (a warning), get a material with no overrides.
// mtllib and texture names are relative paths inside the OBJ's folder (absolute paths, '..',
// drive letters and schemes are refused); a missing or malformed MTL or texture throws
// leanfade::Error naming that file.
Scene make_obj_render_scene(const ObjModel& model, const ObjBakeSettings& settings,
                            ObjSceneReport* report = nullptr);

// The files the OBJ file at `path` makes a run read: its mtllib files and the textures they
// name (map_Kd, map_Pr, map_Bump / bump, norm), as paths inside the OBJ's folder, where
// make_obj_render_scene reads them: inputs of the run, which its outputs may not replace. Never
// throws: a file that cannot be read or parsed, or a name make_obj_render_scene refuses, gives
// the files found so far (loading the scene then names the cause).
std::vector<std::string> obj_referenced_files(const std::string& path);

}  // namespace leanfade::scene
