// Roughness MIPs from LEAN moments (leanfade/core/roughness.hpp).
#include "leanfade/core/roughness.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/parallel.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade {
namespace {

bool unit_interval(float v) {
    return v >= 0.0f && v <= 1.0f;  // false for NaN
}

// α0² of every level: constant, or the map's r⁴ filtered as the moments are.
std::vector<Image> base_alpha_squared(const LeanMap& map, const RoughnessOptions& options) {
    std::vector<Image> levels;
    const MomentLevel& top = map.levels.front();
    if (options.roughness_map == nullptr) {
        const float a2 = std::pow(options.base_roughness, 4.0f);
        for (const MomentLevel& l : map.levels) {
            Image image(l.width, l.height, 4);
            for (std::size_t t = 0; t < image.texel_count(); ++t) image.pixels[4 * t] = a2;
            levels.push_back(std::move(image));
        }
        return levels;
    }
    const Image& r = *options.roughness_map;
    if (r.width != top.width || r.height != top.height || r.channels < 1)
        throw Error("roughness map", "must be " + std::to_string(top.width) + "x" +
                                         std::to_string(top.height) +
                                         " texels like the LEAN map, got " +
                                         std::to_string(r.width) + "x" + std::to_string(r.height));
    Image first(r.width, r.height, 1);
    for (std::size_t t = 0; t < r.texel_count(); ++t)
        first.pixels[t] = r.pixels[t * std::size_t(r.channels)];
    for (Image& level : base_alpha_squared_mips(first, options.threads)) {
        Image rgba(level.width, level.height, 4);
        for (std::size_t t = 0; t < level.texel_count(); ++t) rgba.pixels[4 * t] = level.pixels[t];
        levels.push_back(std::move(rgba));
    }
    return levels;
}

// What roughness MIPs need of their inputs: levels, no baked roughness, r0 in [0, 1].
void check_roughness_inputs(const LeanMap& map, const RoughnessOptions& options) {
    if (map.levels.empty()) throw Error("LEAN map", "the map has no levels");
    if (map.roughness_baked)
        throw Error("LEAN map",
                    "its second moments hold a baked roughness (1/s); bake it "
                    "without one for roughness MIPs, the base roughness is added here");
    if (!unit_interval(options.base_roughness))
        throw Error("roughness",
                    "must be in [0, 1], got " + std::to_string(options.base_roughness));
}

// One texel's roughness from its moments and base α0² (docs/roughness.md).
struct TexelRoughness {
    float alpha = 0.0f;                 // isotropic α = √(α0² + Σxx + Σyy)
    glm::vec2 direction{1.0f, 0.0f};    // of the larger slope variance (with `axes`)
    float alpha_t = 0.0f, alpha_b = 0.0f;  // α along and across it (with `axes`)
};

TexelRoughness texel_roughness(glm::vec2 mean, glm::vec3 second, double a0, bool axes) {
    // Σ = M − B Bᵀ (LEAN eq. 5); float rounding can leave a tiny negative variance.
    const glm::vec3 sigma = shading::lf_covariance(mean, second, 0.0f);
    const double sxx = std::max(0.0, double(sigma.x)), syy = std::max(0.0, double(sigma.y));
    const double sxy = double(sigma.z);
    TexelRoughness r;
    r.alpha = float(std::sqrt(a0 + sxx + syy));
    if (!axes) return r;
    // Eigen-decomposition of the symmetric 2x2 Σ.
    const double half_trace = 0.5 * (sxx + syy);
    const double root = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
    const double lmax = half_trace + root, lmin = std::max(0.0, half_trace - root);
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    r.direction = glm::vec2(float(std::cos(angle)), float(std::sin(angle)));
    r.alpha_t = float(std::sqrt(a0 + 2.0 * lmax));
    r.alpha_b = float(std::sqrt(a0 + 2.0 * lmin));
    return r;
}

// A value in [0, 1] as an 8-bit code, rounded as write_png rounds.
std::uint8_t unorm8(float v) {
    return std::uint8_t(std::lround(std::min(1.0f, std::max(0.0f, v)) * 255.0f));
}

// R, B, A of the input metallic-roughness texture at every level (G unused): its MIP chain
// filtered as the moments, level 0 the input's values exactly; empty without an input.
std::vector<Image> kept_channels(const Image* input, int width, int height, int threads) {
    std::vector<Image> kept;
    if (input == nullptr) return kept;
    const Image& in = *input;
    if (in.width != width || in.height != height || in.channels < 3)
        throw Error("roughness map",
                    "a metallic-roughness texture of 3 or 4 channels and " +
                        std::to_string(width) + "x" + std::to_string(height) +
                        " texels is needed, got " + std::to_string(in.width) + "x" +
                        std::to_string(in.height) + "x" + std::to_string(in.channels));
    Image rgba(in.width, in.height, 4, 1.0f);
    for (std::size_t t = 0; t < in.texel_count(); ++t)
        for (int c = 0; c < in.channels && c < 4; ++c)
            rgba.pixels[4 * t + std::size_t(c)] = in.pixels[t * std::size_t(in.channels) + c];
    kept = build_mip_chain(rgba, threads);
    kept.front() = std::move(rgba);
    return kept;
}

// The float values of one texel of the three textures (roughness_textures' definitions).
struct TexelTextures {
    glm::vec4 metallic_roughness, normal, anisotropy;
};

TexelTextures texel_textures(const TexelRoughness& r, glm::vec3 n, const float* kept) {
    TexelTextures out;
    out.metallic_roughness = kept != nullptr ? glm::vec4(kept[0], 0.0f, kept[2], kept[3])
                                             : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    out.metallic_roughness.y = std::min(1.0f, perceptual_roughness(r.alpha));
    out.normal = glm::vec4(0.5f * n.x + 0.5f, 0.5f * n.y + 0.5f, 0.5f * n.z + 0.5f, 1.0f);
    out.anisotropy = glm::vec4(0.5f * r.direction.x + 0.5f, 0.5f * r.direction.y + 0.5f,
                               anisotropy_strength(r.alpha_t, r.alpha_b), 1.0f);
    return out;
}

}  // namespace

Image base_roughness_channel(const Image& map) {
    // A grey map holds r itself; a colour one is a glTF metallic-roughness texture (r in G).
    const int channel = map.channels >= 3 ? 1 : 0;
    Image r(map.width, map.height, 1);
    for (std::size_t t = 0; t < map.texel_count(); ++t)
        r.pixels[t] = map.pixels[t * std::size_t(map.channels) + std::size_t(channel)];
    return r;
}

std::vector<Image> base_alpha_squared_mips(const Image& roughness, int threads) {
    if (roughness.empty() || roughness.channels < 1)
        throw Error("roughness map", "the map has no texels");
    const std::size_t channels = std::size_t(roughness.channels);
    Image a2(roughness.width, roughness.height, 4);
    for (std::size_t t = 0; t < roughness.texel_count(); ++t) {
        const float v = roughness.pixels[t * channels];
        if (!unit_interval(v))
            throw Error("roughness map", "roughness " + std::to_string(v) + " at texel (" +
                                             std::to_string(t % std::size_t(roughness.width)) +
                                             ", " +
                                             std::to_string(t / std::size_t(roughness.width)) +
                                             ") is outside [0, 1]");
        a2.pixels[4 * t] = base_alpha_squared(v);
    }
    // The moments' filter works on 4 channels: α0² rides in the first.
    std::vector<Image> levels;
    for (const Image& level : build_mip_chain(a2, threads)) {
        Image one(level.width, level.height, 1);
        for (std::size_t t = 0; t < level.texel_count(); ++t) one.pixels[t] = level.pixels[4 * t];
        levels.push_back(std::move(one));
    }
    return levels;
}

float perceptual_roughness(float alpha) {
    return std::sqrt(std::max(alpha, 0.0f));
}

float anisotropy_strength(float alpha_t, float alpha_b) {
    if (!(alpha_b < 1.0f)) return 0.0f;
    const float s2 = (alpha_t - alpha_b) / (1.0f - alpha_b);
    return std::sqrt(std::clamp(s2, 0.0f, 1.0f));
}

std::vector<RoughnessLevel> roughness_mips(const LeanMap& map, const RoughnessOptions& options) {
    check_roughness_inputs(map, options);
    const std::vector<Image> base = base_alpha_squared(map, options);

    std::vector<RoughnessLevel> out;
    for (std::size_t l = 0; l < map.levels.size(); ++l) {
        const MomentLevel& m = map.levels[l];
        RoughnessLevel level;
        level.width = m.width;
        level.height = m.height;
        const std::size_t count = m.mean.size();
        level.alpha.resize(count);
        level.normal.resize(count);
        level.direction.resize(count);
        level.alpha_t.resize(count);
        level.alpha_b.resize(count);
        for (std::size_t t = 0; t < count; ++t) {
            const TexelRoughness r =
                texel_roughness(m.mean[t], m.second[t], double(base[l].pixels[4 * t]), true);
            level.alpha[t] = r.alpha;
            level.direction[t] = r.direction;
            level.alpha_t[t] = r.alpha_t;
            level.alpha_b[t] = r.alpha_b;
            level.normal[t] = glm::normalize(glm::vec3(m.mean[t], 1.0f));
        }
        out.push_back(std::move(level));
    }
    return out;
}

RoughnessTextures roughness_textures(const std::vector<RoughnessLevel>& levels,
                                     const Image* metallic_roughness_input, int threads) {
    if (levels.empty()) throw Error("roughness", "no levels");
    const std::vector<Image> kept = kept_channels(metallic_roughness_input, levels.front().width,
                                                  levels.front().height, threads);
    RoughnessTextures out;
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const RoughnessLevel& level = levels[l];
        Image mr(level.width, level.height, 4), normal(level.width, level.height, 4),
            aniso(level.width, level.height, 4);
        for (std::size_t t = 0; t < level.alpha.size(); ++t) {
            const TexelRoughness r{level.alpha[t], level.direction[t], level.alpha_t[t],
                                   level.alpha_b[t]};
            const TexelTextures v = texel_textures(
                r, level.normal[t], kept.empty() ? nullptr : &kept[l].pixels[4 * t]);
            for (int c = 0; c < 4; ++c) {
                mr.pixels[4 * t + std::size_t(c)] = v.metallic_roughness[c];
                normal.pixels[4 * t + std::size_t(c)] = v.normal[c];
                aniso.pixels[4 * t + std::size_t(c)] = v.anisotropy[c];
            }
        }
        out.metallic_roughness.push_back(std::move(mr));
        out.normal.push_back(std::move(normal));
        out.anisotropy.push_back(std::move(aniso));
    }
    return out;
}

RoughnessTexturesRgba8 roughness_textures_rgba8(const LeanMap& map, const RoughnessOptions& options,
                                                const Image* metallic_roughness_input,
                                                RoughnessTextureSet which) {
    check_roughness_inputs(map, options);
    // α0² per level: one constant, or the map's chain.
    const bool constant_base = options.roughness_map == nullptr;
    const float constant_a2 = std::pow(options.base_roughness, 4.0f);
    const std::vector<Image> base =
        constant_base ? std::vector<Image>{} : base_alpha_squared(map, options);
    const std::vector<Image> kept = kept_channels(metallic_roughness_input, map.levels.front().width,
                                                  map.levels.front().height, options.threads);
    RoughnessTexturesRgba8 out;
    for (std::size_t l = 0; l < map.levels.size(); ++l) {
        const MomentLevel& m = map.levels[l];
        const std::size_t bytes = std::size_t(m.width) * std::size_t(m.height) * 4;
        Rgba8Image& mr = out.metallic_roughness.emplace_back(Rgba8Image{m.width, m.height, {}});
        mr.texels.resize(bytes);
        Rgba8Image* normal = nullptr;
        Rgba8Image* aniso = nullptr;
        if (which.normal) {
            normal = &out.normal.emplace_back(Rgba8Image{m.width, m.height, {}});
            normal->texels.resize(bytes);
        }
        if (which.anisotropy) {
            aniso = &out.anisotropy.emplace_back(Rgba8Image{m.width, m.height, {}});
            aniso->texels.resize(bytes);
        }
        parallel_for_rows(m.height, options.threads, [&](int first, int end) {
            for (std::size_t t = std::size_t(first) * std::size_t(m.width);
                 t < std::size_t(end) * std::size_t(m.width); ++t) {
                const double a0 = constant_base ? double(constant_a2) : double(base[l].pixels[4 * t]);
                const TexelRoughness r = texel_roughness(m.mean[t], m.second[t], a0, aniso != nullptr);
                const glm::vec3 n = normal != nullptr ? glm::normalize(glm::vec3(m.mean[t], 1.0f))
                                                      : glm::vec3(0.0f);
                const TexelTextures v =
                    texel_textures(r, n, kept.empty() ? nullptr : &kept[l].pixels[4 * t]);
                for (int c = 0; c < 4; ++c) {
                    mr.texels[4 * t + std::size_t(c)] = unorm8(v.metallic_roughness[c]);
                    if (normal != nullptr) normal->texels[4 * t + std::size_t(c)] = unorm8(v.normal[c]);
                    if (aniso != nullptr) aniso->texels[4 * t + std::size_t(c)] = unorm8(v.anisotropy[c]);
                }
            }
        });
    }
    return out;
}

}  // namespace leanfade
