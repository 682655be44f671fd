#pragma once
// Where a surface's bumps come from, as typed settings shared by presets, the viewer and the
// command line: one map (a built-in set, a height or normal image, or a .ktx2 LEAN map) with the
// settings of its bake on the fly, or 2-4 bump layers mixed on one surface (docs/math.md §6).
// Every range of these settings is checked here, once; errors name the settings
// ("texture_size", "layer-tiling"), which the command line prints as its flags.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade {

// Texels per side of a built-in bump set.
inline constexpr int kMinTextureSize = 4;
// The size of a built-in bump set: kMinTextureSize to kDefaultMaxImageDimension texels per side
// and, when a built-in set is made at that size (`builtin`), at most `max_size` as an image's
// size is. Throws leanfade::Error(setting, "must be in [4, N], got S"), with "('max_size')" after
// the range when `max_size` is the bound.
void check_texture_size(int texture_size, int max_size, bool builtin,
                        const std::string& setting = "texture_size");

// One map and the settings of its bake on the fly (the "Bumps" flags of the command line).
struct BumpSource {
    std::string source = "bumps";        // built-in set name, height/normal map image, or .ktx2 map
    BakeSource from = BakeSource::Auto;  // images: by channel count, or height / normal
    bool directx = false;                // normal maps in the DirectX convention
    // The storage of bakes on the fly (`--bits`): auto, as `leanfade bake` chooses it.
    StoragePolicy bits = StoragePolicy::measured();
    std::uint32_t seed = 1;              // built-in sets
    int texture_size = 256;              // built-in sets, texels per side (check_texture_size)

    bool operator==(const BumpSource&) const = default;
};

// Bump layers of a material (docs/math.md §6); empty `sources`: the one map of a BumpSource.
// The per-layer lists are empty for their defaults or hold one value per layer.
struct LayerSettings {
    std::vector<std::string> sources;  // built-in sets, images or .ktx2 maps
    std::vector<float> weights;        // t_i, sum 1 (default: equal)
    std::vector<float> strengths;      // k_i, < 0 flips (default: 1)
    std::vector<float> tiling;         // repeats per tiled uv, (0, kMaxTiling] (default: 1)
    std::vector<glm::vec2> velocity;   // uv per second, each component within kMaxTiling
    std::string weight_map;            // RGBA = t_0..t_3 per texel, instead of weights
    LayerMixing mixing = LayerMixing::Textures;

    bool empty() const { return sources.empty(); }
    bool operator==(const LayerSettings&) const = default;
};

// The layers' weights and strengths with the defaults filled in (equal weights, strength 1).
LayerBlend layer_blend(const LayerSettings& layers);
// Each layer's tiling and velocity with the defaults filled in (1 and 0).
std::vector<float> layer_tilings(const LayerSettings& layers);
std::vector<glm::vec2> layer_velocities(const LayerSettings& layers);
// Throws leanfade::Error(setting, cause) unless `layers` is empty or has 2 to kMaxLayers
// non-empty sources, a value per layer in each list that is not empty, and values in range:
// settings "layers", "layer-weights", "layer-strengths", "layer-tiling", "layer-velocity".
void validate(const LayerSettings& layers);

}  // namespace leanfade
