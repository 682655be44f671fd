#pragma once
// glTF 2.0 scenes (.gltf with embedded or external buffers, and .glb), read with tinygltf into the
// conventions of mesh.hpp, MikkTSpace tangents for meshes that come without them, and filtered
// copies of a scene (write_filtered_gltf, at the end). GL-free.
//
// Conventions of the conversion (docs/architecture.md, "glTF scenes"):
// - Texture coordinates: glTF puts uv = (0, 0) at the top-left of an image with v growing
//   downward; leanfade's v grows upward (docs/math.md §1), so TEXCOORD_0 and TEXCOORD_1 are
//   stored as (u, 1 - v) in Vertex::uv and Vertex::uv1 (a primitive without TEXCOORD_1 gets a
//   copy of TEXCOORD_0 in uv1). The image rows are used as stored (top row first), so a texel
//   keeps its place.
// - Texture coordinate sets: each texture reference samples the set its texCoord names, or the
//   one its KHR_texture_transform's texCoord names when that is present (the extension's
//   override), 0 or 1 (GltfTextureTransform::tex_coord). Sets 2 and above are not read: such a
//   reference is a warning and samples TEXCOORD_0, as is a reference to TEXCOORD_1 on a
//   primitive without it.
// - Tangents: glTF's bitangent w * cross(N, T) points toward the image's top (decreasing glTF v),
//   which is +v after the flip: a file's TANGENT is kept as is (orthonormalised against N), and
//   missing tangents are computed by generate_mikktspace_tangents() on the flipped coordinates of
//   the set the material's normal texture samples (without one, its anisotropy texture's, else
//   TEXCOORD_0): the tangent frame is the normal texture's, as glTF's TANGENT is.
// - Normal textures are OpenGL-convention (+Y toward the image's top), as leanfade's bake expects;
//   their `scale` multiplies the X and Y of the decoded normal (glTF 2.0 §3.9.3).
// - Base colour: factor in linear RGB(A); the texture is sRGB-encoded and is decoded to linear
//   by the scene assembly (gltf_scene.hpp).
// - Nodes: every mesh instance of the chosen scene (the file's `scene`, else scene 0, else every
//   root node) becomes one object per primitive with the node's world matrix; a node whose world
//   matrix mirrors (negative determinant) has its triangles' winding reversed and its tangents'
//   w negated, so that the front faces and the bitangents stay right after the transform.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/detail/block_compression.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::scene {

// An image of a glTF file, still encoded (PNG, ...), exactly the bytes the file holds or points
// to; decoding is left to the caller (libs/io readers, which check the format by magic bytes).
struct GltfImage {
    std::string name;                 // "image 2 (bricks_normal.png)": for messages
    std::vector<std::uint8_t> bytes;  // encoded file bytes
};

// The vendor extension of the glTF files `leanfade bake SCENE -o OUT.gltf` writes: a material's
// LEAN map as a KTX2 file beside the glTF, {"uri": "..."} (docs/gltf.md).
inline constexpr const char* kGltfLeanMapExtension = "LEANFADE_lean_map";

// Where a texture reference samples: its texture coordinate set and its KHR_texture_transform,
// in glTF's uv (v down): uv' = T R S uv with T the offset, R the rotation (radians,
// counter-clockwise) and S the scale (the extension's matrices). The identity when the reference
// has none.
struct GltfTextureTransform {
    glm::vec2 offset{0.0f};
    float rotation = 0.0f;
    glm::vec2 scale{1.0f};
    // TEXCOORD_<tex_coord>, 0 or 1: the textureInfo's texCoord, overridden by the extension's
    // texCoord when it has one (KHR_texture_transform); a set above 1 is read as 0 (warned).
    int tex_coord = 0;
};

// The transform in leanfade's uv (v up, uv = (u, 1 - v) of glTF's) for a material's maps, with
// its set (UvTransform::set = tex_coord).
UvTransform leanfade_uv_transform(const GltfTextureTransform& t);

// A material's part that leanfade reads: what it shades (base colour, normal texture) and what
// `bake SCENE -o OUT` filters (the metallic-roughness part).
struct GltfMaterial {
    std::string name;                           // the file's name, else "material N"
    int gltf_index = -1;                        // its index in the file's materials, -1: the default
    glm::vec4 base_color_factor{1.0f};          // linear RGBA
    int base_color_image = -1;                  // index into GltfScene::images, -1: none
    int normal_image = -1;                      // index into GltfScene::images, -1: none
    float normal_scale = 1.0f;                  // normalTexture.scale, finite
    // alphaMode MASK: alphaCutoff (>= 0); none for OPAQUE and BLEND.
    std::optional<float> alpha_cutoff;
    bool blend = false;  // alphaMode BLEND
    bool double_sided = false;  // doubleSided
    float metallic_factor = 1.0f;               // pbrMetallicRoughness.metallicFactor, [0, 1]
    float roughness_factor = 1.0f;              // pbrMetallicRoughness.roughnessFactor, [0, 1]
    int metallic_roughness_image = -1;          // metallicRoughnessTexture's image, -1: none
    int occlusion_image = -1;                   // occlusionTexture's image, -1: none
    float occlusion_strength = 1.0f;            // occlusionTexture.strength, [0, 1]
    glm::vec3 emissive_factor{0.0f};            // emissiveFactor, linear RGB, >= 0
    int emissive_image = -1;                    // emissiveTexture's image (sRGB), -1: none
    // KHR_materials_anisotropy: anisotropyStrength [0, 1], anisotropyRotation (radians, finite)
    // and anisotropyTexture's image (linear RG direction, B strength), -1: none.
    float anisotropy_strength = 0.0f;
    float anisotropy_rotation = 0.0f;
    int anisotropy_image = -1;
    // KHR_texture_transform of the normal, base colour, metallic-roughness, occlusion, emissive
    // and anisotropy textures.
    GltfTextureTransform normal_transform, base_color_transform, metallic_roughness_transform,
        occlusion_transform, emissive_transform, anisotropy_transform;
    // The LEAN map the material's kGltfLeanMapExtension names (a path beside the glTF file,
    // checked as every URI is), drawn instead of a bake of its normal texture; "" when none.
    std::string lean_map_file;
    // Or the map's KTX2 bytes, from the buffer view the extension names ({"bufferView": N}: a
    // .glb of `bake SCENE -o OUT.glb`); empty when none. lean_map_view is N (-1: none).
    std::vector<std::uint8_t> lean_map_bytes;
    int lean_map_view = -1;
};

struct GltfObject {
    Mesh mesh;                  // object space of the glTF mesh; uv flipped (see above)
    int material = 0;           // index into GltfScene::materials
    glm::mat4 transform{1.0f};  // the node's world matrix (object space -> scene space)
};

struct GltfScene {
    std::string path;  // the file read (or the name given to load_gltf_from_memory)
    std::vector<GltfObject> objects;
    std::vector<GltfMaterial> materials;  // primitives without a material get a default one
    std::vector<GltfImage> images;        // only those a material uses are filled
    std::size_t primitives_with_tangents = 0;      // TANGENT read from the file
    std::size_t primitives_generated_tangents = 0;  // MikkTSpace
    std::vector<std::string> warnings;              // parts of the file leanfade ignores
};

// The glTF extensions leanfade implements: a file that lists any other in `extensionsRequired`
// is refused, naming it (glTF 2.0 §3.12); extensions that are only used are ignored.
inline constexpr std::array<std::string_view, 2> kSupportedGltfExtensions{
    "KHR_texture_transform", "KHR_materials_anisotropy"};
inline constexpr const char* kGltfAnisotropyExtension = "KHR_materials_anisotropy";

// Deepest nesting of arrays and objects in a glTF file's JSON, checked on the text before it is
// parsed (a scan without recursion that skips strings): deeper files are refused.
inline constexpr int kMaxGltfJsonDepth = 64;

// Largest number of elements of each top-level array of a glTF file (docs/robustness.md),
// checked on the parsed JSON before tinygltf builds its structures: one element costs tinygltf
// up to a few kilobytes, whatever the file spends on it.
struct GltfArrayLimit {
    std::string_view key;
    std::size_t max_elements;
};
inline constexpr GltfArrayLimit kGltfArrayLimits[] = {
    {"accessors", std::size_t(1) << 18},
    {"bufferViews", std::size_t(1) << 18},
    {"nodes", std::size_t(1) << 16},
    {"meshes", std::size_t(1) << 16},
    {"buffers", 4096},
    {"materials", 4096},
    {"textures", 4096},
    {"images", 4096},
    {"samplers", 4096},
    {"scenes", 4096},
    {"cameras", 4096},
    {"skins", 4096},
    {"animations", 4096},
};
// Largest total of the encoded bytes of the images that the materials use (only those are
// kept; an image no material references is never copied).
inline constexpr std::uint64_t kMaxGltfImageBytes = std::uint64_t(512) << 20;
// Each (normal image, scale) pair of the materials is a bake of its own: one image may be used
// with at most this many different normalTexture scales.
inline constexpr std::size_t kMaxGltfScalesPerImage = 4;
// Largest total size of the LEAN maps a render scene holds (make_render_scene), counted as they
// are baked or read from the cache.
inline constexpr std::uint64_t kMaxGltfLeanMapBytes = std::uint64_t(4) << 30;
// Largest number of primitives of one mesh.
inline constexpr std::size_t kMaxGltfPrimitivesPerMesh = 4096;

// Limits checked while reading (docs/robustness.md).
struct GltfLoadOptions {
    // Largest file read: the .gltf/.glb itself, each external buffer and each external image.
    std::uint64_t max_file_bytes = std::uint64_t(1) << 30;
    // Largest number of vertices of all objects together (node instances count each time).
    std::size_t max_vertices = std::size_t(1) << 25;
    // Largest number of objects (mesh primitives times their instances).
    std::size_t max_objects = 1 << 16;
    // Largest number of triangle indices of all objects together, after strips and fans are
    // expanded to triangle lists (node instances count each time: each holds its own copy),
    // checked before an instance is copied. 2^26 indices are 256 MiB.
    std::size_t max_indices = std::size_t(1) << 26;
    // Largest total of the encoded bytes of the images the materials use.
    std::uint64_t max_image_bytes = kMaxGltfImageBytes;
};

// Reads a .gltf (JSON; buffers and images embedded as data: URIs or in files beside it) or .glb
// (binary container, recognised by its magic bytes). External files are read only inside the
// glTF's folder: an absolute URI, one with a scheme (http:) or one whose path leaves the folder
// ("..") is refused. Supported: triangle lists, strips and fans; POSITION (float), NORMAL
// (float; computed flat as the specification asks when absent), TANGENT (float), TEXCOORD_0 and
// TEXCOORD_1 (float or normalised unsigned byte/short); indices of unsigned byte, short or int.
// A texture reference to a set above 1, or to TEXCOORD_1 on a primitive that lacks it, is a
// warning (GltfScene::warnings) and samples TEXCOORD_0.
// Throws leanfade::Error(path, cause) with a one-line cause for a missing, unreadable, truncated
// or malformed file, an accessor or buffer view outside its buffer, an index out of range, a
// value that is not finite, a node cycle, a URI outside the folder, or a limit exceeded.
GltfScene load_gltf(const std::string& path, const GltfLoadOptions& options = {});

// The external files (buffers, images and the LEANFADE_lean_map of a material) that the glTF
// file at `path` names by a URI that
// load_gltf would read, as paths beside it: inputs of a run, which its outputs may not replace.
// Never throws: a file that cannot be read or parsed gives the files found so far (load_gltf
// then names the cause).
std::vector<std::string> gltf_referenced_files(const std::string& path,
                                               const GltfLoadOptions& options = {});

// The relative path a glTF URI names: percent-decoded (glTF URIs are RFC 3986 references; an
// invalid escape stays as it is). Not checked: see load_gltf for what is read.
std::string gltf_uri_path(const std::string& uri);

// load_gltf on a file's bytes in memory (same checks and messages); `name` names it in errors.
// Only embedded data (data: URIs, the GLB binary chunk) is read: an external URI is refused.
GltfScene load_gltf_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name,
                                const GltfLoadOptions& options = {});

// Tangents as the glTF 2.0 specification asks for meshes without them: MikkTSpace (Mikkelsen,
// "Simulation of Wrinkled Surfaces Revisited", 2008), written from its description. Per triangle,
// the direction of dP/du (object space) and the orientation of its uv mapping (the sign of its
// signed uv area); per corner, that direction projected onto the plane of the vertex normal and
// normalised, weighted by the corner's angle in that plane. Corners are grouped when their
// vertices have equal position, normal and uv (welded, as MikkTSpace does, also across
// different indices) and their triangles have the same orientation; each group's sum is
// normalised into T, with w = +1 for orientation-preserving triangles and -1 for mirrored uvs. A
// vertex used by triangles of both orientations is split in two (one per w). Simplification
// against the full algorithm: a group is not split further into fans that do not share edges,
// nor by an angle threshold; on smooth manifold meshes the results agree. A group with no usable
// triangle (zero uv or position area) gets a unit vector orthogonal to N, w = +1.
// `uv_set` names the texture coordinates the tangents follow: 0 Vertex::uv, 1 Vertex::uv1 (the
// glTF normal texture's set); the other set is carried along unchanged.
// Throws leanfade::Error(mesh.name, cause) for an index out of range, a count not a multiple
// of 3 or a set other than 0 and 1. Normals must be unit length.
void generate_mikktspace_tangents(Mesh& mesh, int uv_set = 0);

// How make_render_scene and bake_normal_texture bake normal textures into LEAN maps.
struct GltfBakeSettings {
    Storage storage = Storage::Unorm16;
    int max_image_size = kDefaultMaxImageDimension;  // per side, checked before decoding
    int threads = 0;                                 // 0: all cores
    std::string cache_folder;  // LEAN-map cache (lean_map_cache.hpp); empty: no cache
    std::uint64_t max_cache_bytes = kMaxLeanCacheBytes;       // the cache folder's bound
    std::uint64_t max_lean_map_bytes = kMaxGltfLeanMapBytes;  // held by make_render_scene
    // Refuse normal textures with texels of z <= 0 instead of repairing them (NormalRepairs,
    // BakeOptions::strict_normals).
    bool strict_normals = false;
};

struct GltfBakeReport {
    std::size_t baked = 0;       // normal textures baked in this call
    std::size_t from_cache = 0;  // normal textures read from the cache
    std::vector<std::string> warnings;  // cache entries that could not be stored
    // The normal textures whose bake repaired texels (PackedLeanMap::normal_repairs), by image.
    std::vector<std::pair<std::string, NormalRepairs>> repaired;
    // The normal textures that fit the DirectX convention clearly better than glTF's OpenGL one
    // (PackedLeanMap::source_looks_flipped), by image.
    std::vector<std::string> other_convention;
};

// The size limit of `max_dimension` texels per side checked for the image `image` of `gltf`
// whose size a cached result records (a LEAN map has its image's size): a cache hit refuses what
// a bake would, with the decoder's message ("GLTF: image 0 (n.png): image size 4096x4096 exceeds
// the limit of 1024 texels per side"). The cache saves the work, never a check.
void check_cached_image_size(const GltfScene& gltf, int image, int width, int height,
                             int max_dimension);

// The LEAN map of one normal texture with its glTF `scale` (slopes times scale: the normal's X
// and Y scaled, glTF 2.0 §3.9.3), OpenGL convention, repeat wrap, no baked roughness. Looked up
// in the cache first (key: the image's encoded bytes, the scale, the storage and the bake
// version; lean_map_cache.hpp), else decoded with the project's readers, baked and stored.
// `from_cache` (optional) tells which. Throws leanfade::Error(gltf.path, cause) for an image
// that does not decode, has fewer than 3 channels or is not a normal map the bake accepts.
PackedLeanMap bake_normal_texture(const GltfScene& gltf, int image, float scale,
                                  const GltfBakeSettings& settings, bool* from_cache = nullptr,
                                  std::string* cache_warning = nullptr);

// The renderer's scene (material.hpp) of a loaded glTF scene: one object per GltfObject, one
// material per GltfMaterial with Kd = the base colour factor's RGB, its base colour texture
// decoded to linear RGBA (sRGB transfer function inverted; alpha kept, not used for blending),
// and its normal texture baked to a LEAN map (bake_normal_texture); materials without a normal
// texture share one flat LEAN map; a material whose file names its LEAN map (lean_map_file) draws
// that map (read with read_ktx2's checks). Every material gets a base roughness map
// (MapKind::BaseRoughness, read with Cook-Torrance): r = roughness_factor times the G of its
// metallic-roughness texture, or the factor alone (1 x 1); its metalness is metallic_factor
// (Material::metallic) times the texture's B (MapKind::Metallic). The occlusion texture's R
// (MapKind::Occlusion, with its strength), the emissive texture decoded to linear RGB
// (MapKind::Emissive, times emissive_factor) and KHR_materials_anisotropy's texture
// (MapKind::Anisotropy, linear, with its strength and rotation) become maps of their kinds.
// alphaMode MASK cuts out the texels whose base colour alpha (texture times factor) is below
// alphaCutoff (Material::alpha_cutoff). Throws leanfade::Error(gltf.path, cause).
Scene make_render_scene(const GltfScene& gltf, const GltfBakeSettings& settings,
                        GltfBakeReport* report = nullptr);

// True for a path that names a glTF file by its extension (.gltf or .glb, any case).
bool is_gltf_path(const std::string& path);

// ---------------------------------------------------------------------------------------------
// A filtered copy of a glTF scene (docs/gltf.md): every material with a normal texture gets
// roughness MIPs (metallic-roughness, G = sqrt(alpha) with alpha^2 = alpha0^2 + Sxx + Syy per
// level), the matching normal MIPs, a KHR_materials_anisotropy texture where its bumps are
// anisotropic, and its LEAN map (the LEANFADE_lean_map extension); the textures' KTX2 files are
// stored as KHR_texture_basisu asks (Basis Universal UASTC) or as RGBA8. Everything else of the
// file (geometry, nodes, cameras, animations, other extensions) passes through unchanged.
// `leanfade bake SCENE -o OUT.gltf|OUT.glb` is this function; an engine's importer can call it.

struct FilteredGltfSettings {
    // The LEAN maps' bake (storage, image size limit, threads, the LEAN-map cache, strict
    // normals): the cache also keeps each material's output files, under one key, so that a
    // later run copies them instead of filtering again.
    GltfBakeSettings bake;
    // The LEAN maps' KTX2 supercompression and Zstandard level.
    io::Supercompression supercompression = io::Supercompression::Zstandard;
    int zstd_level = 3;
    // The engine textures' KTX2 files: Basis Universal UASTC (KHR_texture_basisu) or None (RGBA8).
    io::BlockCompression compression = io::BlockCompression::Basis;
    io::Durability durability = io::Durability::Rename;
    // Also a JSON array of one summary per material (its files, sizes, anisotropy, cache use,
    // seconds) at this path; empty: none.
    std::string summary_path;
};

// What a write did, in the order met: `warnings` about the input scene (the loader's, cache
// entries that could not be stored), `other_convention`: normal textures (by image) that fit the
// DirectX convention clearly better than glTF's OpenGL one; `written`: every file published, the
// output first.
struct FilteredGltfReport {
    std::vector<std::string> warnings;
    std::vector<std::string> other_convention;
    std::vector<std::string> written;
    std::size_t materials = 0;  // materials filtered
};

// Called before each material is filtered: its index (from 0), the count and its name.
using GltfWriteProgress =
    std::function<void(std::size_t index, std::size_t count, const std::string& material)>;

// Writes `output` (.gltf or .glb) from `input` and, beside a .gltf, per material with a normal
// texture: OUT.<material>.roughness.ktx2/.png, .normal.ktx2/.png, .anisotropy.ktx2/.png and
// .lean.ktx2 (a .glb holds them in its binary chunk); a .gltf written from a .glb also gets
// OUT.bin. External files the output names are copied beside it when its folder is another.
// All are published together, nothing on an error, and none replaces an input (the scene, its
// buffers, its images). Throws leanfade::Error naming the file (a refused compression names the
// setting "compress"); `report` (if given) holds what was found, also when it throws.
void write_filtered_gltf(const std::string& input, const std::string& output,
                         const FilteredGltfSettings& settings, FilteredGltfReport* report = nullptr,
                         const GltfWriteProgress& progress = {});

// A material's (or file's) name as part of a file name: letters, digits, '-' and '_' kept, the
// rest '_', at most 64 characters, "material" when nothing is left.
std::string file_name_part(const std::string& name);
// `base` + `suffix`, or `base`-2 + `suffix`, -3, ...: the first not in `taken`, which it joins.
std::string unique_name(const std::string& base, const std::string& suffix,
                        std::set<std::string>& taken);

}  // namespace leanfade::scene
