// Roughness MIPs from LEAN moments (leanfade/core/roughness.hpp).
#include "leanfade/core/roughness.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "leanfade/core/error.hpp"
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
    if (map.levels.empty()) throw Error("LEAN map", "the map has no levels");
    if (map.roughness_baked)
        throw Error("LEAN map",
                    "its second moments hold a baked roughness (1/s); bake it "
                    "without one for roughness MIPs, the base roughness is added here");
    if (!unit_interval(options.base_roughness))
        throw Error("roughness",
                    "must be in [0, 1], got " + std::to_string(options.base_roughness));
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
            // Σ = M − B Bᵀ (LEAN eq. 5); float rounding can leave a tiny negative variance.
            const glm::vec3 sigma = shading::lf_covariance(m.mean[t], m.second[t], 0.0f);
            const double sxx = std::max(0.0, double(sigma.x)), syy = std::max(0.0, double(sigma.y));
            const double sxy = double(sigma.z);
            const double a0 = double(base[l].pixels[4 * t]);
            level.alpha[t] = float(std::sqrt(a0 + sxx + syy));
            // Eigen-decomposition of the symmetric 2x2 Σ.
            const double half_trace = 0.5 * (sxx + syy);
            const double root = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
            const double lmax = half_trace + root, lmin = std::max(0.0, half_trace - root);
            const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
            level.direction[t] = glm::vec2(float(std::cos(angle)), float(std::sin(angle)));
            level.alpha_t[t] = float(std::sqrt(a0 + 2.0 * lmax));
            level.alpha_b[t] = float(std::sqrt(a0 + 2.0 * lmin));
            level.normal[t] = glm::normalize(glm::vec3(m.mean[t], 1.0f));
        }
        out.push_back(std::move(level));
    }
    return out;
}

RoughnessTextures roughness_textures(const std::vector<RoughnessLevel>& levels,
                                     const Image* metallic_roughness_input, int threads) {
    if (levels.empty()) throw Error("roughness", "no levels");
    std::vector<Image> kept;  // R, G, B, A of the input at every level (G unused)
    if (metallic_roughness_input != nullptr) {
        const Image& in = *metallic_roughness_input;
        if (in.width != levels.front().width || in.height != levels.front().height ||
            in.channels < 3)
            throw Error("roughness map",
                        "a metallic-roughness texture of 3 or 4 channels and " +
                            std::to_string(levels.front().width) + "x" +
                            std::to_string(levels.front().height) + " texels is needed, got " +
                            std::to_string(in.width) + "x" + std::to_string(in.height) + "x" +
                            std::to_string(in.channels));
        Image rgba(in.width, in.height, 4, 1.0f);
        for (std::size_t t = 0; t < in.texel_count(); ++t)
            for (int c = 0; c < in.channels && c < 4; ++c)
                rgba.pixels[4 * t + std::size_t(c)] = in.pixels[t * std::size_t(in.channels) + c];
        kept = build_mip_chain(rgba, threads);
        // Level 0 keeps the input's values exactly.
        kept.front() = std::move(rgba);
    }
    RoughnessTextures out;
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const RoughnessLevel& level = levels[l];
        Image mr(level.width, level.height, 4), normal(level.width, level.height, 4),
            aniso(level.width, level.height, 4);
        for (std::size_t t = 0; t < level.alpha.size(); ++t) {
            const std::size_t i = 4 * t;
            if (!kept.empty()) {
                for (int c : {0, 2, 3}) mr.pixels[i + std::size_t(c)] = kept[l].pixels[i + c];
            } else {
                mr.pixels[i + 3] = 1.0f;
            }
            mr.pixels[i + 1] = std::min(1.0f, perceptual_roughness(level.alpha[t]));
            const glm::vec3 n = level.normal[t];
            normal.pixels[i] = 0.5f * n.x + 0.5f;
            normal.pixels[i + 1] = 0.5f * n.y + 0.5f;
            normal.pixels[i + 2] = 0.5f * n.z + 0.5f;
            normal.pixels[i + 3] = 1.0f;
            const glm::vec2 d = level.direction[t];
            aniso.pixels[i] = 0.5f * d.x + 0.5f;
            aniso.pixels[i + 1] = 0.5f * d.y + 0.5f;
            aniso.pixels[i + 2] = anisotropy_strength(level.alpha_t[t], level.alpha_b[t]);
            aniso.pixels[i + 3] = 1.0f;
        }
        out.metallic_roughness.push_back(std::move(mr));
        out.normal.push_back(std::move(normal));
        out.anisotropy.push_back(std::move(aniso));
    }
    return out;
}

}  // namespace leanfade
