// Bump layers: slopes mixed for the "height" method, cross-term textures, and the moments of
// aligned layers mixed per texel with the shared header's formulas (leanfade/core/detail/layers.hpp).
#include "leanfade/core/detail/layers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "leanfade/core/error.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade {

const LayerMixingInfo& info(LayerMixing mixing) {
    for (const LayerMixingInfo& row : kLayerMixings)
        if (row.id == mixing) return row;
    return kLayerMixings[0];
}

const char* to_string(LayerMixing mixing) {
    return info(mixing).name;
}

LayerMixing parse_layer_mixing(std::string_view name, const std::string& setting) {
    std::string names;
    for (const LayerMixingInfo& row : kLayerMixings) {
        if (name == row.name) return row.id;
        names += (names.empty() ? "" : ", ") + std::string(row.name);
    }
    throw Error::setting(
        setting, "unknown mixing method '" + std::string(name) + "' (expected " + names + ")");
}

void validate(const LayerBlend& blend) {
    const std::size_t n = blend.weights.size();
    if (n < 1 || n > std::size_t(kMaxLayers))
        throw Error::setting("layer-weights", "1 to " + std::to_string(kMaxLayers) +
                                                  " layers are supported, got " +
                                                  std::to_string(n));
    if (blend.strengths.size() != n)
        throw Error::setting("layer-strengths",
                             "one strength per layer: " + std::to_string(n) + " layers, " +
                                 std::to_string(blend.strengths.size()) + " strengths");
    double sum = 0.0;
    for (float t : blend.weights) {
        if (!(t >= 0.0f && t <= 1.0f))
            throw Error::setting("layer-weights",
                                 "weights must be in [0, 1], got " + std::to_string(t));
        sum += t;
    }
    if (!(std::abs(sum - 1.0) <= 1e-4))
        throw Error::setting("layer-weights", "weights must sum to 1, got " + std::to_string(sum));
    for (float k : blend.strengths)
        if (!std::isfinite(k) || k == 0.0f || std::abs(k) > 1e3f)
            throw Error::setting(
                "layer-strengths",
                "strengths must be finite, non-zero and at most 1000 in magnitude, got " +
                    std::to_string(k));
}

namespace {

void check_same_slopes(std::span<const Image> slopes) {
    for (const Image& s : slopes)
        if (s.channels != 2 || s.empty() || s.width != slopes[0].width ||
            s.height != slopes[0].height)
            throw Error::setting("layers", "every layer needs 2-channel slopes of one size");
}

}  // namespace

Image mix_slopes(std::span<const Image> slopes, const LayerBlend& blend) {
    validate(blend);
    if (slopes.size() != blend.weights.size())
        throw Error::setting("layers", std::to_string(slopes.size()) + " slope images for " +
                                           std::to_string(blend.weights.size()) + " weights");
    check_same_slopes(slopes);
    Image mixed(slopes[0].width, slopes[0].height, 2);
    for (std::size_t i = 0; i < slopes.size(); ++i) {
        const float f = blend.weights[i] * blend.strengths[i];
        for (std::size_t v = 0; v < mixed.pixels.size(); ++v)
            mixed.pixels[v] += f * slopes[i].pixels[v];
    }
    return mixed;
}

namespace {

// A float as printf's %g writes it: 1.5, not 1.500000.
std::string shortest(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(value));
    return text;
}

}  // namespace

glm::ivec2 mixed_map_size(std::span<const glm::ivec2> sizes,
                          std::span<const LayerPlacement> placements) {
    if (sizes.size() != placements.size() || sizes.empty())
        throw Error::setting("layers", "one size and one placement per layer");
    glm::ivec2 size(0);
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        const float tiling = placements[i].tiling;
        if (!(tiling >= 1.0f) || tiling > float(kMaxMixedMapSize) ||
            std::abs(tiling - std::round(tiling)) > 1e-4f)
            throw Error::setting(
                "layer-tiling",
                "the height method generates one map repeating once per unit of uv: "
                "each tiling must be a whole number >= 1, got " +
                    shortest(tiling));
        if (sizes[i].x < 1 || sizes[i].y < 1)
            throw Error::setting("layers", "a layer has no texels");
        const long long whole = std::llround(tiling);
        size.x = int(std::min<long long>(std::max<long long>(size.x, sizes[i].x * whole),
                                         kMaxMixedMapSize + 1));
        size.y = int(std::min<long long>(std::max<long long>(size.y, sizes[i].y * whole),
                                         kMaxMixedMapSize + 1));
    }
    if (size.x > kMaxMixedMapSize || size.y > kMaxMixedMapSize)
        throw Error::setting("layers",
                             "the mixed map would exceed " + std::to_string(kMaxMixedMapSize) +
                                 " texels per side (layer size x tiling); use textures or "
                                 "approx for finely tiled layers");
    return size;
}

namespace {

// Texel index i modulo n, for any i.
int wrap_index(int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
}

// The bilinear value of channels [0, count) of a repeating image at uv (v up, texel values at
// texel centres), in the order the GPU reads them: rows counted from the bottom.
template <int count>
std::array<float, count> bilinear_repeat(const Image& image, glm::vec2 uv) {
    const float x = uv.x * float(image.width) - 0.5f;
    const float y = uv.y * float(image.height) - 0.5f;
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float fx = x - x0, fy = y - y0;
    std::array<float, count> out{};
    for (int corner = 0; corner < 4; ++corner) {
        const int dx = corner & 1, dy = corner >> 1;
        const float w = (dx ? fx : 1.0f - fx) * (dy ? fy : 1.0f - fy);
        const int column = wrap_index(int(x0) + dx, image.width);
        const int row_from_bottom = wrap_index(int(y0) + dy, image.height);
        const float* texel = image.row(image.height - 1 - row_from_bottom) +
                             std::size_t(column) * std::size_t(image.channels);
        for (int c = 0; c < count; ++c) out[std::size_t(c)] += w * texel[c];
    }
    return out;
}

}  // namespace

Image mix_slopes_at(std::span<const Image> slopes, const LayerBlend& blend,
                    std::span<const LayerPlacement> placements, const Image* weights, int width,
                    int height) {
    validate(blend);
    if (slopes.size() != blend.weights.size() || placements.size() != slopes.size())
        throw Error::setting("layers", "one slope image, weight and placement per layer");
    for (const Image& s : slopes)
        if (s.channels != 2 || s.empty())
            throw Error::setting("layers", "every layer needs 2-channel slopes");
    if (weights != nullptr && (weights->channels != 4 || weights->empty()))
        throw Error::setting("layers", "a weight map has 4 channels (t_0..t_3)");
    for (const LayerPlacement& p : placements)
        if (!std::isfinite(p.tiling) || !std::isfinite(p.offset.x) || !std::isfinite(p.offset.y))
            throw Error::setting("layers", "placements must be finite");
    if (width < 1 || height < 1 || width > kMaxMixedMapSize || height > kMaxMixedMapSize)
        throw Error::setting("layers", "the mixed map's size must be in [1, " +
                                           std::to_string(kMaxMixedMapSize) + "]");
    Image mixed(width, height, 2);
    for (int row = 0; row < height; ++row) {
        const int j = height - 1 - row;  // texel row counted from v = 0
        for (int x = 0; x < width; ++x) {
            const glm::vec2 uv((float(x) + 0.5f) / float(width), (float(j) + 0.5f) / float(height));
            std::array<float, 4> t{};
            if (weights != nullptr) t = bilinear_repeat<4>(*weights, uv);
            for (std::size_t i = 0; i < slopes.size(); ++i) {
                const float weight = weights != nullptr ? t[i] : blend.weights[i];
                const glm::vec2 layer_uv = uv * placements[i].tiling + placements[i].offset;
                const std::array<float, 2> b = bilinear_repeat<2>(slopes[i], layer_uv);
                const float f = weight * blend.strengths[i];
                float* out = mixed.row(row) + 2 * std::size_t(x);
                out[0] += f * b[0];
                out[1] += f * b[1];
            }
        }
    }
    return mixed;
}

std::vector<Image> build_cross_terms(const Image& slopes_i, const Image& slopes_j, int threads) {
    const Image pair[2] = {slopes_i, slopes_j};
    check_same_slopes(pair);
    Image products(slopes_i.width, slopes_i.height, 4);
    for (std::size_t t = 0; t < slopes_i.texel_count(); ++t) {
        const glm::vec2 bi(slopes_i.pixels[2 * t], slopes_i.pixels[2 * t + 1]);
        const glm::vec2 bj(slopes_j.pixels[2 * t], slopes_j.pixels[2 * t + 1]);
        const glm::vec4 p = shading::lf_cross_products(bi, bj);
        for (int c = 0; c < 4; ++c) products.pixels[4 * t + std::size_t(c)] = p[c];
    }
    return build_mip_chain(products, threads);
}

int pair_index(int i, int j, int layer_count) {
    if (!(0 <= i && i < j && j < layer_count))
        throw Error::setting("layers",
                             "no pair (" + std::to_string(i) + ", " + std::to_string(j) + ")");
    // Pairs before row i: (n-1) + (n-2) + ... + (n-i).
    return i * (2 * layer_count - i - 1) / 2 + (j - i - 1);
}

MomentLevel mix_layer_level(std::span<const LeanMap> layers,
                            std::span<const std::vector<Image>> cross, int level,
                            LayerMixing mixing, const LayerBlend& blend) {
    validate(blend);
    const int n = int(layers.size());
    if (std::size_t(n) != blend.weights.size())
        throw Error::setting("layers", std::to_string(n) + " maps for " +
                                           std::to_string(blend.weights.size()) + " weights");
    for (const LeanMap& m : layers) {
        if (level < 0 || level >= int(m.levels.size()) ||
            m.levels[std::size_t(level)].width != layers[0].levels[std::size_t(level)].width ||
            m.levels[std::size_t(level)].height != layers[0].levels[std::size_t(level)].height)
            throw Error::setting("layers", "the layers' maps must be aligned and of one size");
        if (m.roughness_baked)
            throw Error::setting("layers",
                                 "a layer's map has roughness baked in; the base roughness is "
                                 "added once, after mixing");
    }
    if (mixing == LayerMixing::Height)
        throw Error::setting("layers",
                             "the height method mixes the slopes before baking (mix_slopes, "
                             "then build_lean_map), not the maps");
    const std::size_t pairs = std::size_t(n * (n - 1) / 2);
    if (mixing == LayerMixing::Textures) {
        if (cross.size() != pairs)
            throw Error::setting("layers", "mixing textures needs " + std::to_string(pairs) +
                                               " cross-term chains, got " +
                                               std::to_string(cross.size()));
        for (const std::vector<Image>& chain : cross)
            if (level >= int(chain.size()) ||
                chain[std::size_t(level)].width != layers[0].levels[std::size_t(level)].width ||
                chain[std::size_t(level)].height != layers[0].levels[std::size_t(level)].height)
                throw Error::setting("layers",
                                     "a cross-term texture does not match the layers' size");
    }

    const MomentLevel& first = layers[0].levels[std::size_t(level)];
    MomentLevel out;
    out.width = first.width;
    out.height = first.height;
    const std::size_t count = std::size_t(first.width) * std::size_t(first.height);
    out.normal.resize(count);
    out.mean.resize(count);
    out.second.resize(count);
    for (std::size_t t = 0; t < count; ++t) {
        shading::LfMoments mixed = shading::lf_mix_start();
        shading::LfMoments scaled[kMaxLayers];
        for (int i = 0; i < n; ++i) {
            const MomentLevel& l = layers[std::size_t(i)].levels[std::size_t(level)];
            shading::LfMoments m;
            m.normal = l.normal[t];
            m.mean = l.mean[t];
            m.second = l.second[t];
            scaled[i] = shading::lf_layer_strength(m, blend.strengths[std::size_t(i)]);
            mixed = shading::lf_mix_layer(mixed, scaled[i], blend.weights[std::size_t(i)]);
        }
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) {
                glm::vec4 products;
                if (mixing == LayerMixing::Textures) {
                    const Image& c = cross[std::size_t(pair_index(i, j, n))][std::size_t(level)];
                    products = glm::vec4(c.pixels[4 * t], c.pixels[4 * t + 1], c.pixels[4 * t + 2],
                                         c.pixels[4 * t + 3]) *
                               (blend.strengths[std::size_t(i)] * blend.strengths[std::size_t(j)]);
                } else {
                    products = shading::lf_cross_products(scaled[i].mean, scaled[j].mean);
                }
                mixed = shading::lf_mix_pair(
                    mixed, products, blend.weights[std::size_t(i)] * blend.weights[std::size_t(j)]);
            }
        mixed = shading::lf_mix_end(mixed);
        out.normal[t] = mixed.normal;
        out.mean[t] = mixed.mean;
        out.second[t] = mixed.second;
    }
    return out;
}

}  // namespace leanfade
