// Typed bump sources and bump layers, and their checks (leanfade/core/detail/bump_source.hpp).
#include "leanfade/core/detail/bump_source.hpp"

#include <algorithm>
#include <cmath>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/detail/text.hpp"

namespace leanfade {

void check_texture_size(int texture_size, int max_size, bool builtin, const std::string& setting) {
    const int largest =
        builtin ? std::min(max_size, kDefaultMaxImageDimension) : kDefaultMaxImageDimension;
    if (texture_size < kMinTextureSize || texture_size > largest)
        throw Error::setting(setting,
                             "must be in [" + std::to_string(kMinTextureSize) + ", " +
                                 std::to_string(largest) + "]" +
                                 (largest < kDefaultMaxImageDimension ? " ('max_size')" : "") +
                                 ", got " + std::to_string(texture_size),
                             {"max_size"});
}

namespace {

// `values` when given, else n times `fallback`.
template <typename T>
std::vector<T> per_layer(const std::vector<T>& values, std::size_t n, T fallback) {
    return values.empty() ? std::vector<T>(n, fallback) : values;
}

std::string joined(const std::vector<std::string>& names) {
    std::string text;
    for (std::size_t i = 0; i < names.size(); ++i) text += (i > 0 ? "," : "") + names[i];
    return text;
}

void check_count(std::size_t values, std::size_t layers, const std::string& setting,
                 const std::string& what) {
    if (values != 0 && values != layers)
        throw Error::setting(setting, "one " + what + " per layer: " + std::to_string(layers) +
                                          " layers, " + std::to_string(values) + " values");
}

}  // namespace

LayerBlend layer_blend(const LayerSettings& layers) {
    const std::size_t n = layers.sources.size();
    LayerBlend blend;
    blend.weights = per_layer(layers.weights, n, n == 0 ? 1.0f : 1.0f / float(n));
    blend.strengths = per_layer(layers.strengths, n, 1.0f);
    return blend;
}

std::vector<float> layer_tilings(const LayerSettings& layers) {
    return per_layer(layers.tiling, layers.sources.size(), 1.0f);
}

std::vector<glm::vec2> layer_velocities(const LayerSettings& layers) {
    return per_layer(layers.velocity, layers.sources.size(), glm::vec2(0.0f));
}

void validate(const LayerSettings& layers) {
    if (layers.empty()) return;
    const std::size_t n = layers.sources.size();
    if (n < 2 || n > std::size_t(kMaxLayers))
        throw Error::setting("layers", "2 to " + std::to_string(kMaxLayers) + " sources, got " +
                                           std::to_string(n) +
                                           " (a single map is the bump source, not a layer)");
    for (std::size_t i = 0; i < n; ++i)
        if (layers.sources[i].empty())
            throw Error::setting("layers", "source " + std::to_string(i + 1) + " of " +
                                               std::to_string(n) + " is empty ('" +
                                               escape_text(joined(layers.sources)) + "')");
    check_count(layers.weights.size(), n, "layer-weights", "value");
    check_count(layers.strengths.size(), n, "layer-strengths", "value");
    check_count(layers.tiling.size(), n, "layer-tiling", "value");
    check_count(layers.velocity.size(), n, "layer-velocity", "U:V");
    // A texture offset of velocity times time: bounded as the tiling is, so that it stays finite.
    for (const glm::vec2& v : layers.velocity)
        if (!(std::abs(v.x) <= kMaxTiling) || !(std::abs(v.y) <= kMaxTiling))
            throw Error::setting(
                "layer-velocity",
                "each component must be in [-1e+06, 1e+06] uv units per second, got " +
                    shortest_text(v.x) + ":" + shortest_text(v.y));
    validate(layer_blend(layers));
    for (float t : layers.tiling)
        if (!(t > 0.0f) || !(t <= kMaxTiling))
            throw Error::setting(
                "layer-tiling",
                "each tiling must be in (0, 1e+06], as 'tiling', got " + shortest_text(t),
                {"tiling"});
}

}  // namespace leanfade
