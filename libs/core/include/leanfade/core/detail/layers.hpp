#pragma once
// Bump layers (LEAN §3.5, docs/math.md §6): up to kMaxLayers height fields on one surface, each
// with a weight t_i (the weights sum to 1) and a strength k_i (a negative strength flips the
// layer). The mixed surface's slopes are sum t_i k_i B_i, so its moments are
//   B = sum t_i k_i B_i,   M = sum t_i^2 k_i^2 M_i + sum_{i<j} t_i t_j k_i k_j C_ij,
// with C_ij = (2 Bi.x Bj.x, 2 Bi.y Bj.y, Bi.x Bj.y + Bj.x Bi.y) averaged over the texel's
// footprint. Three ways to get C_ij, as in the paper:
//   Height    mix the slopes and bake one LEAN map (per frame for moving layers): exact.
//   Textures  a texture of the pair's four slope products, MIP-mapped with the moments' own
//             filter ("mixing textures"): exact at every level while the pair does not move
//             relative to itself.
//   Approx    the products of the filtered B's at shading time ("mixing approximation"): exact
//             at the finest level only; coherent layers (f and -f) keep a variance they lack.
// The per-texel formulas are the shared shading header's (lf_mix_*), so the shaders and this
// CPU path mix alike. All slopes are tangent-space projected slopes, dimensionless.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade {

inline constexpr int kMaxLayers = 4;

enum class LayerMixing { Height, Textures, Approx };

// The mixing methods, described once: the command line's choices and help, the renderer's
// shader constant (LF_MIXING_* of shaders/lean_shading.glsl) and the figures' labels read it.
struct LayerMixingInfo {
    LayerMixing id;
    const char* name;         // command-line and preset name
    const char* label;        // figure column title
    const char* description;  // one line for --help
    int shader_mixing;        // LF_MIXING_* (the renderer's per-material uniform)
};
inline constexpr LayerMixingInfo kLayerMixings[] = {
    {LayerMixing::Height, "height", "mixed heights",
     "mix the layers' slopes and bake one LEAN map (per frame on the GPU for moving layers): "
     "exact",
     0},
    {LayerMixing::Textures, "textures", "mixing textures",
     "a MIP-mapped texture of each pair's slope products: exact while the pair moves together",
     1},
    {LayerMixing::Approx, "approx", "mixing approximation",
     "the products of the filtered mean slopes at shading time: exact at the finest level only",
     2},
};
const LayerMixingInfo& info(LayerMixing mixing);

const char* to_string(LayerMixing mixing);  // "height", "textures", "approx"
// Throws leanfade::Error(setting, cause) for another name.
LayerMixing parse_layer_mixing(std::string_view name, const std::string& setting = "mixing");

// Weights and strengths of the layers, one each per layer.
struct LayerBlend {
    std::vector<float> weights;    // t_i >= 0, sum 1 (within 1e-4)
    std::vector<float> strengths;  // k_i finite and non-zero; < 0 flips the layer
};

// Throws leanfade::Error(setting, cause) unless there are 1..kMaxLayers layers with valid
// weights and strengths (settings named "layer-weights" and "layer-strengths").
void validate(const LayerBlend& blend);

// The "height" method's slopes: sum t_i k_i B_i of 2-channel slope images of one size.
Image mix_slopes(std::span<const Image> slopes, const LayerBlend& blend);

// Where a layer lies on the surface at one instant: its texture coordinates are
// uv * tiling + offset (uv of the surface's tiled texture space; offset = velocity * time, taken
// modulo 1 since the layers repeat).
struct LayerPlacement {
    float tiling = 1.0f;       // repeats per unit of the surface's uv: a whole number >= 1 here
    glm::vec2 offset{0.0f};    // uv units
};

// Largest side of the map the "height" method generates for layers that move or tile
// differently (mixed_map_size).
inline constexpr int kMaxMixedMapSize = 4096;

// The size of the one map that holds the mixed slopes of layers of sizes `sizes` (texels) at
// `placements` over the surface's uv square [0, 1)^2: per axis, the largest size x tiling, so
// that no layer is read at fewer texels than its own. Throws leanfade::Error("layer-tiling",
// cause) for a tiling that is not a whole number >= 1 (the map repeats once per unit of uv, and
// a layer that does not repeat with it would leave a seam), and Error("layers", cause) for a map
// beyond kMaxMixedMapSize.
glm::ivec2 mixed_map_size(std::span<const glm::ivec2> sizes,
                          std::span<const LayerPlacement> placements);

// The "height" method for layers that move or tile differently, at one instant (docs/math.md
// §6): at the texel centres of a width x height grid over uv [0, 1)^2 (rows top first, v = 1 at
// the top like every image here), the slopes sum t_i k_i B_i(uv tiling_i + offset_i). Each
// layer's slopes (2-channel, rows top first, repeating) are read bilinearly, as texel values at
// texel centres; the weights are blend.weights, or read bilinearly from `weights` (RGBA =
// t_0..t_3 per texel, repeating) when it is not null. With equal sizes, tiling 1 and offset 0 it
// is mix_slopes. The GPU's per-frame generation (shaders/generate_lean.comp, SOURCE_LAYERS)
// computes the same. Throws leanfade::Error("layers", cause) for mismatched inputs.
Image mix_slopes_at(std::span<const Image> slopes, const LayerBlend& blend,
                    std::span<const LayerPlacement> placements, const Image* weights, int width,
                    int height);

// The cross-term texture of layers i and j: the four products (Bi.x Bj.x, Bi.y Bj.y, Bi.x Bj.y,
// Bj.x Bi.y) of their slopes at strength 1, with the MIP chain of build_mip_chain. Both images
// are 2-channel slopes of one size.
std::vector<Image> build_cross_terms(const Image& slopes_i, const Image& slopes_j, int threads = 0);

// Index of the pair (i, j), i < j < layer_count, in the list of cross-term chains: the pairs in
// the order (0,1), (0,2), ..., (0,n-1), (1,2), ...
int pair_index(int i, int j, int layer_count);

// Mixed moments of one MIP level of aligned layers (LEAN maps of one size baked at strength 1,
// without baked roughness), by Textures or Approx (Height mixes the slopes before baking).
// `cross` holds one chain per pair (pair_index order) for Textures and is ignored for Approx.
// The normal is that of the mixed mean slope (lf_mix_end).
MomentLevel mix_layer_level(std::span<const LeanMap> layers,
                            std::span<const std::vector<Image>> cross, int level,
                            LayerMixing mixing, const LayerBlend& blend);

}  // namespace leanfade
