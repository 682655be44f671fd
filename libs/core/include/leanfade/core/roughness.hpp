#pragma once
// Roughness MIPs for microfacet engines (docs/math.md §9): at every MIP level of a LEAN map, the
// Beckmann roughness that folds the covariance of the bump slopes under each texel into the
// material's base roughness, the normal of the mean slope, and the anisotropic split of
// KHR_materials_anisotropy. GL-free; units: slopes and α are dimensionless, directions are in
// tangent space (x = +u, y = +v).
//
//   Σ = M − B Bᵀ (the slopes' covariance over the texel's footprint, LEAN eq. 5)
//   α² = α0² + Σxx + Σyy                isotropic, Beckmann-matched (engines use it for GGX)
//   α_t² = α0² + 2 λmax, α_b² = α0² + 2 λmin, direction = eigenvector of λmax   anisotropic
//   r = √α (glTF perceptual roughness), normal = normalize(B.x, B.y, 1)
// With a roughness map, α0² is MIP-filtered linearly with the moments' own filter.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade {

struct RoughnessOptions {
    // Base perceptual roughness r0 in [0, 1] (α0 = r0²), used where no map is given.
    float base_roughness = 0.0f;
    // Optional per-texel base roughness: a 1-channel image of perceptual r in [0, 1] of the
    // LEAN map's top-level size (a glTF metallic-roughness texture's G channel, for example).
    const Image* roughness_map = nullptr;
    // What errors about the roughness map (and a metallic-roughness input) name: its file.
    std::string roughness_map_name = "roughness map";
    int threads = 0;  // as BakeOptions::threads
};

struct RoughnessLevel {
    int width = 0;
    int height = 0;
    std::vector<float> alpha;          // isotropic Beckmann α, per texel, rows top first
    std::vector<glm::vec3> normal;     // unit normal of the mean slope B
    std::vector<glm::vec2> direction;  // unit tangent-space direction of the larger slope variance
    std::vector<float> alpha_t;        // α along `direction`
    std::vector<float> alpha_b;        // α across it
};

// One RoughnessLevel per level of `map`. Throws leanfade::Error(setting, cause) for a map with
// baked roughness (its M holds 1/s already: bake it without), a base roughness or map value
// outside [0, 1] or not finite, or a roughness map of another size.
std::vector<RoughnessLevel> roughness_mips(const LeanMap& map, const RoughnessOptions& options);

// The textures engines read, one image per MIP level (level 0 first), 4 channels of values in
// [0, 1], rows top first (docs/roughness.md):
//   metallic_roughness  glTF metallic-roughness: G = perceptual r = √α; R, B, A those of the
//                       input texture (its MIP chain filtered linearly, as the moments), or
//                       (1, 0, 1) without one: R 1 (no occlusion, for engines that read an
//                       ORM texture's R as occlusion), metallic 0
//   normal              0.5 n + 0.5 of the unit normal of the mean slope, A = 1
//   anisotropy          KHR_materials_anisotropy: RG = 0.5 d + 0.5 of the direction d of the larger
//                       slope variance (tangent space), B = strength, A = 1
struct RoughnessTextures {
    std::vector<Image> metallic_roughness;
    std::vector<Image> normal;
    std::vector<Image> anisotropy;
};

// Which of the textures roughness_textures_rgba8 makes (the metallic-roughness one always).
struct RoughnessTextureSet {
    bool normal = true;
    bool anisotropy = true;
};

// The textures engines read, quantised to 8 bits.
struct RoughnessTexturesRgba8 {
    std::vector<Rgba8Image> metallic_roughness;
    std::vector<Rgba8Image> normal;      // empty unless asked for
    std::vector<Rgba8Image> anisotropy;  // empty unless asked for
};

// roughness_textures(roughness_mips(map, options), metallic_roughness_input) with every value
// rounded to 8 bits as write_png rounds (round(255 v), v clamped to [0, 1]), the same bytes, made
// in one pass over each level's texels (rows in parallel, options.threads) without the float
// levels and images in between: what `leanfade bake --roughness-out` and the glTF output write.
// Throws as roughness_mips and roughness_textures do.
RoughnessTexturesRgba8 roughness_textures_rgba8(const LeanMap& map, const RoughnessOptions& options,
                                                const Image* metallic_roughness_input,
                                                RoughnessTextureSet which = {});

// The same textures made as a bake's moments arrive (its MomentRunSink), with no float MIP chain in
// memory: add() of every texel of every level of a LEAN map gives the bytes of
// roughness_textures_rgba8 of that map. `leanfade bake` runs it inside the fused bake
// (bake_packed_to, bake_moments). The map's level 0 is width x height texels; the roughness map
// and metallic-roughness input (as roughness_textures_rgba8) must be of that size. The caller
// refuses maps with baked roughness (roughness_textures_rgba8 does). Throws as
// roughness_textures_rgba8 for the options and inputs.
// Where a RoughnessTextureBuilder writes a texture's levels (level 0 first, width * height * 4
// bytes each, rows top first), e.g. mapped output files (io::Ktx2Rgba8Writer); an empty vector:
// the builder keeps that texture's levels itself, for take().
struct RoughnessTextureTargets {
    std::vector<std::uint8_t*> metallic_roughness, normal, anisotropy;
};

class RoughnessTextureBuilder {
  public:
    RoughnessTextureBuilder(int width, int height, const RoughnessOptions& options,
                            const Image* metallic_roughness_input, RoughnessTextureSet which = {},
                            const RoughnessTextureTargets& targets = {});
    // One run's texels; runs that do not overlap may come from several threads at once.
    void add(const MomentRun& run);
    // A sink calling add (the builder must outlive the bake it is given to).
    MomentRunSink sink();
    // The textures kept by the builder (those without targets), once every texel has been added.
    RoughnessTexturesRgba8 take();
    // Level 0's size.
    int width() const { return levels_.front().width; }
    int height() const { return levels_.front().height; }

  private:
    void add_isotropic(const MomentRun& run, const float* base, const float* kept,
                       std::uint8_t* mr_out, std::uint8_t* normal_out) const;

    struct LevelDestination {
        int width, height;
        std::uint8_t* metallic_roughness;
        std::uint8_t* normal;      // nullptr: not made
        std::uint8_t* anisotropy;  // nullptr: not made
    };

    bool constant_base_;
    float constant_a2_;
    std::vector<Image> base_;  // α0² per level (first channel), with a roughness map
    std::vector<Image> kept_;  // R, B, A of the metallic-roughness input per level
    std::vector<LevelDestination> levels_;
    RoughnessTexturesRgba8 out_;  // the levels without targets
};

// `metallic_roughness_input`: the glTF texture the base roughness came from (3 or 4 channels, the
// size of level 0), or nullptr. Throws leanfade::Error("roughness map", cause) for another size.
RoughnessTextures roughness_textures(const std::vector<RoughnessLevel>& levels,
                                     const Image* metallic_roughness_input, int threads = 0);

// A base roughness map's perceptual roughness r per texel (1 channel, rows as the input's): the
// first channel of a grey image (1-2 channels), G of a glTF metallic-roughness texture (3-4).
Image base_roughness_channel(const Image& map);

// α0² = (r²)² of a perceptual roughness r (docs/math.md §9): Beckmann α0 = r², squared.
inline float base_alpha_squared(float r) {
    const float alpha0 = r * r;
    return alpha0 * alpha0;
}

// The base roughness at render time (docs/roughness.md, docs/math.md §9): α0² = r⁴ per texel of
// `roughness` (base_roughness_channel's 1 channel of r in [0, 1]), then its MIP chain filtered
// linearly with the moments' own filter (build_mip_chain): α0² enters the covariance as a sum, so
// its filtered value is the mean α0² of the footprint, as Σ's is. Level 0 first, 1-channel
// float images, rows as the input's. Throws leanfade::Error(name, cause) for a value outside
// [0, 1] or not finite (naming the texel) or an empty image: `name` is the map's file.
std::vector<Image> base_alpha_squared_mips(const Image& roughness, int threads = 0,
                                           const std::string& name = "roughness map");

// glTF perceptual roughness of a Beckmann α: √α.
float perceptual_roughness(float alpha);

// KHR_materials_anisotropy strength s for α_t along the direction and α_b across it, from the
// extension's α_t = mix(α_b, 1, s²): s = √((α_t − α_b) / (1 − α_b)), clamped to [0, 1].
float anisotropy_strength(float alpha_t, float alpha_b);

}  // namespace leanfade
