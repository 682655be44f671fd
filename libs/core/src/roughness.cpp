// Roughness MIPs from LEAN moments (leanfade/core/roughness.hpp).
#include "leanfade/core/roughness.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/memory.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade {
namespace {

bool unit_interval(float v) {
    return v >= 0.0f && v <= 1.0f;  // false for NaN
}

// α0² of every level of a roughness map (options.roughness_map) for a map of width x height texels.
std::vector<Image> base_alpha_squared_map(int width, int height, const RoughnessOptions& options) {
    std::vector<Image> levels;
    const Image& r = *options.roughness_map;
    if (r.width != width || r.height != height || r.channels < 1)
        throw Error(options.roughness_map_name,
                    "must be " + std::to_string(width) + "x" + std::to_string(height) +
                        " texels like the LEAN map, got " + std::to_string(r.width) + "x" +
                        std::to_string(r.height));
    Image first(r.width, r.height, 1);
    for (std::size_t t = 0; t < r.texel_count(); ++t)
        first.pixels[t] = r.pixels[t * std::size_t(r.channels)];
    const std::string& name = options.roughness_map_name;
    for (Image& level : base_alpha_squared_mips(first, options.threads, name)) {
        Image rgba(level.width, level.height, 4);
        for (std::size_t t = 0; t < level.texel_count(); ++t) rgba.pixels[4 * t] = level.pixels[t];
        levels.push_back(std::move(rgba));
    }
    return levels;
}

// α0² of every level: constant, or the map's r⁴ filtered as the moments are.
std::vector<Image> base_alpha_squared(const LeanMap& map, const RoughnessOptions& options) {
    std::vector<Image> levels;
    if (options.roughness_map == nullptr) {
        const float a2 = std::pow(options.base_roughness, 4.0f);
        for (const MomentLevel& l : map.levels) {
            Image image(l.width, l.height, 4);
            for (std::size_t t = 0; t < image.texel_count(); ++t) image.pixels[4 * t] = a2;
            levels.push_back(std::move(image));
        }
        return levels;
    }
    return base_alpha_squared_map(map.levels.front().width, map.levels.front().height, options);
}

// What roughness MIPs need of their inputs: levels, no baked roughness, r0 in [0, 1].
void check_roughness_inputs(const LeanMap& map, const RoughnessOptions& options) {
    if (map.levels.empty()) throw Error("LEAN map", "the map has no levels");
    if (map.roughness_baked)
        throw Error("LEAN map",
                    "its second moments hold a baked roughness (1/s); bake it "
                    "without one for roughness MIPs, the base roughness is added here");
    if (!unit_interval(options.base_roughness))
        throw Error::setting("roughness",
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

// A value in [0, 1] as an 8-bit code, rounded as write_png rounds: lround(255 v), halves away
// from zero. The scaled value is >= 0, exact in double, and + 0.5 in double rounds no tie up,
// so truncation gives lround's result without a library call.
// Branch-free (std::min / std::max of floats are single instructions), for loops the compiler
// vectorises.
inline std::int32_t unorm8_code(float v) {
    const float scaled = std::min(1.0f, std::max(0.0f, v)) * 255.0f;
    return std::int32_t(double(scaled) + 0.5);
}
std::uint8_t unorm8(float v) {
    return std::uint8_t(unorm8_code(v));
}

// R, B, A of the input metallic-roughness texture at every level (G unused): its MIP chain
// filtered as the moments, level 0 the input's values exactly; empty without an input.
std::vector<Image> kept_channels(const Image* input, int width, int height, int threads,
                                 const std::string& name = "roughness map") {
    std::vector<Image> kept;
    if (input == nullptr) return kept;
    const Image& in = *input;
    if (in.width != width || in.height != height || in.channels < 3)
        throw Error(name, "a metallic-roughness texture of 3 or 4 channels and " +
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
                                             : glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
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

std::vector<Image> base_alpha_squared_mips(const Image& roughness, int threads,
                                           const std::string& name) {
    if (roughness.empty() || roughness.channels < 1) throw Error(name, "the map has no texels");
    const std::size_t channels = std::size_t(roughness.channels);
    Image a2(roughness.width, roughness.height, 4);
    for (std::size_t t = 0; t < roughness.texel_count(); ++t) {
        const float v = roughness.pixels[t * channels];
        if (!unit_interval(v))
            throw Error(name, "roughness " + std::to_string(v) + " at texel (" +
                                  std::to_string(t % std::size_t(roughness.width)) + ", " +
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
    if (levels.empty()) throw Error::setting("roughness", "no levels");
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

RoughnessTextureBuilder::RoughnessTextureBuilder(int width, int height,
                                                 const RoughnessOptions& options,
                                                 const Image* metallic_roughness_input,
                                                 RoughnessTextureSet which,
                                                 const RoughnessTextureTargets& targets)
    : constant_base_(options.roughness_map == nullptr),
      constant_a2_(std::pow(options.base_roughness, 4.0f)) {
    if (width <= 0 || height <= 0) throw Error::setting("roughness", "the map has no texels");
    if (!unit_interval(options.base_roughness))
        throw Error::setting("roughness",
                             "must be in [0, 1], got " + std::to_string(options.base_roughness));
    if (!constant_base_) base_ = base_alpha_squared_map(width, height, options);
    kept_ = kept_channels(metallic_roughness_input, width, height, options.threads,
                          options.roughness_map_name);
    const int count = mip_level_count(width, height);
    // Each texture's level l: the caller's target, or a level of its own (out_).
    const auto destination = [count](const std::vector<std::uint8_t*>& given,
                                     std::vector<Rgba8Image>& own, int l, int w, int h) {
        if (!given.empty()) {
            if (given.size() != std::size_t(count) || given[std::size_t(l)] == nullptr)
                throw std::invalid_argument("RoughnessTextureBuilder: one target per level");
            return given[std::size_t(l)];
        }
        Rgba8Image& image = own.emplace_back(Rgba8Image{w, h, {}});
        assign_large(image.texels, std::size_t(w) * std::size_t(h) * 4, std::uint8_t(0));
        return image.texels.data();
    };
    for (int l = 0, w = width, h = height; l < count; ++l) {
        LevelDestination d{w, h, nullptr, nullptr, nullptr};
        d.metallic_roughness = destination(targets.metallic_roughness, out_.metallic_roughness, l, w, h);
        if (which.normal) d.normal = destination(targets.normal, out_.normal, l, w, h);
        if (which.anisotropy) d.anisotropy = destination(targets.anisotropy, out_.anisotropy, l, w, h);
        levels_.push_back(d);
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
}

void RoughnessTextureBuilder::add(const MomentRun& run) {
    const std::size_t l = std::size_t(run.level);
    if (l >= levels_.size()) throw std::out_of_range("RoughnessTextureBuilder: level");
    const LevelDestination& d = levels_[l];
    if (run.y < 0 || run.y >= d.height || run.x < 0 || run.count < 0 || run.x + run.count > d.width)
        throw std::out_of_range("RoughnessTextureBuilder: run outside its level");
    const std::size_t first = std::size_t(run.y) * std::size_t(d.width) + std::size_t(run.x);
    std::uint8_t* mr_out = d.metallic_roughness + 4 * first;
    std::uint8_t* normal_out = d.normal != nullptr ? d.normal + 4 * first : nullptr;
    std::uint8_t* aniso_out = d.anisotropy != nullptr ? d.anisotropy + 4 * first : nullptr;
    const float* base = constant_base_ ? nullptr : base_[l].pixels.data() + 4 * first;
    const float* kept = kept_.empty() ? nullptr : kept_[l].pixels.data() + 4 * first;
    if (aniso_out == nullptr) {
        add_isotropic(run, base, kept, mr_out, normal_out);
        return;
    }
    for (int i = 0; i < run.count; ++i) {
        const glm::vec2 mean(run.bx[i], run.by[i]);
        const glm::vec3 second(run.mxx[i], run.myy[i], run.mxy[i]);
        const double a0 = base == nullptr ? double(constant_a2_) : double(base[4 * i]);
        const TexelRoughness r = texel_roughness(mean, second, a0, aniso_out != nullptr);
        const glm::vec3 n =
            normal_out != nullptr ? glm::normalize(glm::vec3(mean, 1.0f)) : glm::vec3(0.0f);
        const TexelTextures v = texel_textures(r, n, kept == nullptr ? nullptr : kept + 4 * i);
        for (int c = 0; c < 4; ++c) {
            mr_out[4 * i + c] = unorm8(v.metallic_roughness[c]);
            if (normal_out != nullptr) normal_out[4 * i + c] = unorm8(v.normal[c]);
            if (aniso_out != nullptr) aniso_out[4 * i + c] = unorm8(v.anisotropy[c]);
        }
    }
}

// The metallic-roughness and normal texels of a run (no anisotropy): the arithmetic of
// texel_roughness, texel_textures and glm::normalize written out per channel, the same operations
// in the same order (so the same bytes, RoughnessTextures.* checks), in blocks of loops without
// branches or calls that the compiler vectorises, then interleaved into RGBA texels.
void RoughnessTextureBuilder::add_isotropic(const MomentRun& run, const float* base,
                                            const float* kept, std::uint8_t* mr_out,
                                            std::uint8_t* normal_out) const {
    constexpr int kBlock = 64;
    double a0[kBlock];
    std::int32_t g[kBlock], nx[kBlock], ny[kBlock], nz[kBlock];
    for (int k = 0; k < kBlock; ++k) a0[k] = double(constant_a2_);
    for (int i0 = 0; i0 < run.count; i0 += kBlock) {
        const int n = std::min(kBlock, run.count - i0);
        const float* bx = run.bx + i0;
        const float* by = run.by + i0;
        const float* mxx = run.mxx + i0;
        const float* myy = run.myy + i0;
        if (base != nullptr)
            for (int k = 0; k < n; ++k) a0[k] = double(base[4 * (i0 + k)]);
        for (int k = 0; k < n; ++k) {
            // Σxx, Σyy of lf_covariance (LEAN eq. 5), then α = √(α0² + Σxx + Σyy) in double.
            const float sxx = std::max(mxx[k] - bx[k] * bx[k], 0.0f) + 0.0f;
            const float syy = std::max(myy[k] - by[k] * by[k], 0.0f) + 0.0f;
            const float alpha = float(std::sqrt(a0[k] + double(sxx) + double(syy)));
            g[k] = unorm8_code(std::min(1.0f, std::sqrt(std::max(alpha, 0.0f))));  // r = √α
        }
        std::uint8_t* t = mr_out + 4 * std::size_t(i0);
        if (kept != nullptr) {
            const float* in = kept + 4 * std::size_t(i0);
            for (int k = 0; k < n; ++k) {
                t[4 * k] = std::uint8_t(unorm8_code(in[4 * k]));
                t[4 * k + 1] = std::uint8_t(g[k]);
                t[4 * k + 2] = std::uint8_t(unorm8_code(in[4 * k + 2]));
                t[4 * k + 3] = std::uint8_t(unorm8_code(in[4 * k + 3]));
            }
        } else {  // no input texture: R 1 (occlusion none, for ORM packing), metallic 0, A 1
            for (int k = 0; k < n; ++k) {
                t[4 * k] = 255;
                t[4 * k + 1] = std::uint8_t(g[k]);
                t[4 * k + 2] = 0;
                t[4 * k + 3] = 255;
            }
        }
        if (normal_out == nullptr) continue;
        for (int k = 0; k < n; ++k) {
            // glm::normalize(B.x, B.y, 1): v * (1 / sqrt(dot(v, v))), dot summed (x + y) + z.
            const float inv = 1.0f / std::sqrt((bx[k] * bx[k] + by[k] * by[k]) + 1.0f);
            nx[k] = unorm8_code(0.5f * (bx[k] * inv) + 0.5f);
            ny[k] = unorm8_code(0.5f * (by[k] * inv) + 0.5f);
            nz[k] = unorm8_code(0.5f * (1.0f * inv) + 0.5f);
        }
        std::uint8_t* u = normal_out + 4 * std::size_t(i0);
        for (int k = 0; k < n; ++k) {
            u[4 * k] = std::uint8_t(nx[k]);
            u[4 * k + 1] = std::uint8_t(ny[k]);
            u[4 * k + 2] = std::uint8_t(nz[k]);
            u[4 * k + 3] = 255;
        }
    }
}

MomentRunSink RoughnessTextureBuilder::sink() {
    return [this](const MomentRun& run) { add(run); };
}

RoughnessTexturesRgba8 RoughnessTextureBuilder::take() {
    return std::move(out_);
}

RoughnessTexturesRgba8 roughness_textures_rgba8(const LeanMap& map, const RoughnessOptions& options,
                                                const Image* metallic_roughness_input,
                                                RoughnessTextureSet which) {
    check_roughness_inputs(map, options);
    RoughnessTextureBuilder builder(map.levels.front().width, map.levels.front().height, options,
                                    metallic_roughness_input, which);
    for (std::size_t l = 0; l < map.levels.size(); ++l) {
        const MomentLevel& m = map.levels[l];
        parallel_for_rows(m.height, options.threads, [&](int first, int end) {
            // One row's moments as the planes a bake hands over.
            std::vector<float> planes(5 * std::size_t(m.width));
            float* p[5];
            for (int c = 0; c < 5; ++c) p[c] = planes.data() + std::size_t(c) * std::size_t(m.width);
            for (int y = first; y < end; ++y) {
                for (int x = 0; x < m.width; ++x) {
                    const std::size_t t = std::size_t(y) * std::size_t(m.width) + std::size_t(x);
                    p[0][x] = m.mean[t].x;
                    p[1][x] = m.mean[t].y;
                    p[2][x] = m.second[t].x;
                    p[3][x] = m.second[t].y;
                    p[4][x] = m.second[t].z;
                }
                builder.add(MomentRun{int(l), y, 0, m.width, p[0], p[1], p[2], p[3], p[4]});
            }
        });
    }
    return builder.take();
}

}  // namespace leanfade
