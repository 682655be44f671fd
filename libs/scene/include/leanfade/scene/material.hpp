#pragma once
// What the renderer draws: objects (a mesh, a transform and a material) and their materials (the
// maps and the parameters that differ from the frame's shading settings). GL-free.
//
// A material has one bump map, a LEAN map (leanfade/core/lean_map.hpp), or 2..kMaxLayers bump
// layers (leanfade/core/detail/layers.hpp, docs/math.md §6) whose moments are mixed at shading time.
// Its parameters override ShadingSettings for the objects that use it; those it leaves unset come
// from the frame's settings.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"
#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::scene {

// One bump layer of a material: a LEAN map baked at strength 1 without baked roughness, and how
// it lies on the surface.
struct MaterialLayer {
    int lean_map = 0;        // index into Scene::lean_maps
    float strength = 1.0f;   // k: slopes times k (k < 0 flips the layer), finite, non-zero
    float tiling = 1.0f;     // repeats per unit of the surface's tiled uv, finite, > 0
    glm::vec2 velocity{0.0f};  // uv offset per second (a moving layer), finite
};

// How the layers' mixed second moments get their cross terms (docs/math.md §6).
struct MaterialLayers {
    std::vector<MaterialLayer> layers;  // 2..kMaxLayers; empty: the material's one lean_map
    LayerMixing mixing = LayerMixing::Textures;
    std::vector<float> weights;  // t_i, one per layer, >= 0, sum 1 (the weights' default)
    // Index into Scene::weight_maps (RGBA = t_0..t_3 per texel, replacing `weights`), or -1.
    int weight_map = -1;
    // Textures: index into Scene::cross_terms of each pair, in pair_index order.
    std::vector<int> cross_terms;
};

constexpr std::array<int, kMapKindCount> filled_map_slots(int value) {
    std::array<int, kMapKindCount> slots{};
    for (int& slot : slots) slot = value;
    return slots;
}

// Where a map is sampled: a texture coordinate set of the mesh (Vertex::uv or Vertex::uv1, a
// glTF texture reference's texCoord) and an affine map of it in leanfade's uv (v up): uv' =
// (dot(row0.xy, uv) + row0.z, dot(row1.xy, uv) + row1.z); set 0 and the identity by default
// (glTF KHR_texture_transform).
struct UvTransform {
    glm::vec3 row0{1.0f, 0.0f, 0.0f};
    glm::vec3 row1{0.0f, 1.0f, 0.0f};
    int set = 0;  // 0: Vertex::uv, 1: Vertex::uv1 (kUvSetCount sets)
};
inline constexpr int kUvSetCount = 2;

struct Material {
    std::string name;
    int lean_map = 0;                   // index into Scene::lean_maps (the single-map case)
    std::optional<glm::vec3> diffuse;   // Kd, linear RGB (a glTF base colour factor)
    std::optional<glm::vec3> specular;  // Ks, linear RGB
    std::optional<float> shininess;     // Blinn-Phong exponent s > 0
    MaterialLayers layered;             // bump layers instead of lean_map when not empty
    // Its surface maps (leanfade/scene/detail/map_kinds.hpp), one slot per kind: an index into
    // Scene::maps[kind], or -1 for none. Base colour: Kd is multiplied by the texture (a glTF
    // base colour texture) at the surface's tiled uv. Base roughness: with Cook-Torrance the base
    // roughness comes per texel from the map (α0², docs/math.md §9) instead of the frame's
    // uniform roughness; Blinn-Phong, whose base roughness is 1/s, ignores it.
    std::array<int, kMapKindCount> maps = filled_map_slots(-1);
    // glTF alphaMode MASK: the base colour's alpha (texture alpha times base_alpha) below the
    // cutoff is cut out (not drawn); none: opaque.
    std::optional<float> alpha_cutoff{};
    float base_alpha = 1.0f;  // the base colour factor's alpha, [0, 1]
    // glTF alphaMode BLEND: drawn after the opaque objects, back to front, over what is behind
    // (its alpha the base colour's, texture times base_alpha), without writing depth.
    bool blend = false;
    // glTF doubleSided: false culls back faces; true draws them, shaded with the reversed frame;
    // none (built-in and OBJ scenes): back faces drawn, shaded as front faces.
    std::optional<bool> double_sided{};
    // glTF metallic-roughness (glTF 2.0 §3.9.2): the metalness is `metallic` times the metallic
    // map's texel (MapKind::Metallic, 1 without one), applied per texel with the base colour
    // (lf_surface_params); it replaces the frame's `metallic`. None: the frame's.
    std::optional<float> metallic{};
    // glTF occlusionTexture.strength, [0, 1]: with an occlusion map (MapKind::Occlusion) the
    // ambient term is multiplied by 1 + strength (occlusion - 1) (glTF 2.0 §3.9.4).
    float occlusion_strength = 1.0f;
    // glTF emissiveFactor, linear RGB radiance >= 0, times the emissive texture
    // (MapKind::Emissive, white without one), added to the colour (glTF 2.0 §3.9.5).
    glm::vec3 emissive{0.0f};
    // KHR_materials_anisotropy (Cook-Torrance): the strength in [0, 1] (times the anisotropy
    // texture's B, MapKind::Anisotropy) and the rotation (radians, counter-clockwise from the
    // tangent +u) of the base roughness's stretch along the direction (the texture's RG).
    float anisotropy_strength = 0.0f;
    float anisotropy_rotation = 0.0f;
    // Texture coordinate transforms: of the LEAN map (its plateau layer alike) and of each surface
    // map kind (the plateau's entry unused).
    UvTransform lean_uv{};
    std::array<UvTransform, kMapKindCount> map_uv{};
    int& map(MapKind kind) { return maps[std::size_t(kind)]; }
    int map(MapKind kind) const { return maps[std::size_t(kind)]; }
};

struct Object {
    Mesh mesh;
    int material = 0;           // index into Scene::materials
    glm::mat4 transform{1.0f};  // object space -> scene space (a glTF node's world matrix)
};

struct Scene {
    std::vector<Object> objects;
    std::vector<Material> materials;
    std::vector<PackedLeanMap> lean_maps;
    // Cross-term textures of layer pairs ("textures" mixing): each a MIP chain (finest first) of
    // 4-channel float images (Bi.x Bj.x, Bi.y Bj.y, Bi.x Bj.y, Bj.x Bi.y), build_cross_terms.
    std::vector<std::vector<Image>> cross_terms;
    // Per-texel layer weights: 4-channel float images, RGBA = t_0..t_3 (each texel's weights of
    // the layers it has sum to 1), sampled at the surface's tiled uv.
    std::vector<Image> weight_maps;
    // The surface maps of each kind (kMapKinds): textures, each a MIP chain (finest first, every
    // level half the previous) of images with the kind's channels and meaning, rows top first
    // (uploaded flipped, like every texture: v up). A kind whose MIPs are Generated holds level 0
    // only; one whose MIPs are Given holds every level down to 1x1. Base colour: 4-channel linear
    // RGB (sRGB decoded) and alpha. Base roughness (leanfade::base_alpha_squared_mips): 1-channel
    // α0² = r⁴ >= 0 (dimensionless; α0 the Beckmann roughness), filtered linearly as the LEAN
    // moments are.
    std::array<std::vector<std::vector<Image>>, kMapKindCount> maps;
    std::vector<std::vector<Image>>& maps_of(MapKind kind) { return maps[std::size_t(kind)]; }
    const std::vector<std::vector<Image>>& maps_of(MapKind kind) const {
        return maps[std::size_t(kind)];
    }
    // Adds a texture of `kind` and returns its index.
    int add_map(MapKind kind, std::vector<Image> chain) {
        maps_of(kind).push_back(std::move(chain));
        return int(maps_of(kind).size()) - 1;
    }
};

// The size of the map the "height" method generates for `material`'s layers (mixed_map_size of
// leanfade/core/detail/layers.hpp over the top levels of their LEAN maps and their tilings). Throws
// mixed_map_size's errors, and Error("scene", cause) for a layer map without levels.
// Gives every material drawn from one LEAN map (not from bump layers) that has no plateau map
// the plateau layer its LEAN map stores (MapKind::Plateau, unpack_plateau_layer of
// leanfade/core/detail/plateau.hpp: two-lobe LEAN's spike, docs/math.md §10), decoded once per map. A
// LEAN map without the layer (a file of an older version, a bake with plateau_epsilon 0) gives
// none, and neither do materials of bump layers: two-lobe shades them as LEAN (f = 0).
void add_plateau_maps(Scene& scene);

glm::ivec2 mixed_map_size(const Scene& scene, const Material& material);

// The scene-space bounding box of every object's transformed bounds (its eight corners).
Bounds scene_bounds(const Scene& scene);

// Throws leanfade::Error(setting, cause) for a scene the renderer cannot draw: no object, a
// material or map index out of range, a texture coordinate set outside [0, kUvSetCount), an object
// without triangles, an override that is not finite (or a shininess <= 0), a transform that is not
// finite or not invertible, layers that are not 2..kMaxLayers with valid weights, strengths,
// tilings and velocities, a cross-term texture missing for a pair of "textures" layers, a weight
// map that is not 4-channel, a surface map slot out of range, or a surface map whose levels do not
// follow its kind (channels, the full chain of a Given kind, finite values; a roughness map's
// >= 0).
void validate(const Scene& scene);

}  // namespace leanfade::scene
