// Bump layers: slopes mixed for the "height" method, cross-term textures, and the moments of
// aligned layers mixed per texel with the shared header's formulas (leanfade/core/layers.hpp).
#include "leanfade/core/layers.hpp"

#include <cmath>

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
    throw Error(setting, "unknown mixing method '" + std::string(name) + "' (expected " + names +
                             ")");
}

void validate(const LayerBlend& blend) {
    const std::size_t n = blend.weights.size();
    if (n < 1 || n > std::size_t(kMaxLayers))
        throw Error("layer-weights", "1 to " + std::to_string(kMaxLayers) +
                                         " layers are supported, got " + std::to_string(n));
    if (blend.strengths.size() != n)
        throw Error("layer-strengths", "one strength per layer: " + std::to_string(n) +
                                           " layers, " + std::to_string(blend.strengths.size()) +
                                           " strengths");
    double sum = 0.0;
    for (float t : blend.weights) {
        if (!(t >= 0.0f && t <= 1.0f))
            throw Error("layer-weights", "weights must be in [0, 1], got " + std::to_string(t));
        sum += t;
    }
    if (!(std::abs(sum - 1.0) <= 1e-4))
        throw Error("layer-weights", "weights must sum to 1, got " + std::to_string(sum));
    for (float k : blend.strengths)
        if (!std::isfinite(k) || k == 0.0f || std::abs(k) > 1e3f)
            throw Error("layer-strengths",
                        "strengths must be finite, non-zero and at most 1000 in magnitude, got " +
                            std::to_string(k));
}

namespace {

void check_same_slopes(std::span<const Image> slopes) {
    for (const Image& s : slopes)
        if (s.channels != 2 || s.empty() || s.width != slopes[0].width ||
            s.height != slopes[0].height)
            throw Error("layers", "every layer needs 2-channel slopes of one size");
}

}  // namespace

Image mix_slopes(std::span<const Image> slopes, const LayerBlend& blend) {
    validate(blend);
    if (slopes.size() != blend.weights.size())
        throw Error("layers", std::to_string(slopes.size()) + " slope images for " +
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
        throw Error("layers", "no pair (" + std::to_string(i) + ", " + std::to_string(j) + ")");
    // Pairs before row i: (n-1) + (n-2) + ... + (n-i).
    return i * (2 * layer_count - i - 1) / 2 + (j - i - 1);
}

MomentLevel mix_layer_level(std::span<const LeanMap> layers,
                            std::span<const std::vector<Image>> cross, int level,
                            LayerMixing mixing, const LayerBlend& blend) {
    validate(blend);
    const int n = int(layers.size());
    if (std::size_t(n) != blend.weights.size())
        throw Error("layers", std::to_string(n) + " maps for " +
                                  std::to_string(blend.weights.size()) + " weights");
    for (const LeanMap& m : layers) {
        if (level < 0 || level >= int(m.levels.size()) ||
            m.levels[std::size_t(level)].width != layers[0].levels[std::size_t(level)].width ||
            m.levels[std::size_t(level)].height != layers[0].levels[std::size_t(level)].height)
            throw Error("layers", "the layers' maps must be aligned and of one size");
        if (m.roughness_baked)
            throw Error("layers",
                        "a layer's map has roughness baked in; the base roughness is "
                        "added once, after mixing");
    }
    if (mixing == LayerMixing::Height)
        throw Error("layers",
                    "the height method mixes the slopes before baking (mix_slopes, "
                    "then build_lean_map), not the maps");
    const std::size_t pairs = std::size_t(n * (n - 1) / 2);
    if (mixing == LayerMixing::Textures) {
        if (cross.size() != pairs)
            throw Error("layers", "mixing textures needs " + std::to_string(pairs) +
                                      " cross-term chains, got " + std::to_string(cross.size()));
        for (const std::vector<Image>& chain : cross)
            if (level >= int(chain.size()) ||
                chain[std::size_t(level)].width != layers[0].levels[std::size_t(level)].width ||
                chain[std::size_t(level)].height != layers[0].levels[std::size_t(level)].height)
                throw Error("layers", "a cross-term texture does not match the layers' size");
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
