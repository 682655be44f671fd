#include "leanfade/core/image.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "leanfade/core/memory.hpp"

namespace leanfade {

Image::Image(int w, int h, int c, float fill) : width(w), height(h), channels(c) {
    if (w < 0 || h < 0 || c < 0 || c > 4) throw std::invalid_argument("Image: bad dimensions");
    assign_large(pixels, std::size_t(w) * std::size_t(h) * std::size_t(c), fill);
}

UnormImage::UnormImage(int w, int h, int c, std::uint16_t max)
    : width(w), height(h), channels(c), max_value(max) {
    if (w < 0 || h < 0 || c < 0 || c > 4 || max == 0)
        throw std::invalid_argument("UnormImage: bad dimensions");
    assign_large(samples, std::size_t(w) * std::size_t(h) * std::size_t(c), std::uint16_t(0));
}

Image UnormImage::to_float() const {
    Image image(width, height, channels);
    const float max = float(max_value);
    for (std::size_t i = 0; i < samples.size(); ++i) image.pixels[i] = float(samples[i]) / max;
    return image;
}

int UnormImage::effective_max_code(int channels_used) const {
    if (samples.empty() || channels <= 0) return 0;
    const int used = channels_used <= 0 ? channels : std::min(channels_used, channels);
    unsigned divisor = max_value;
    const std::size_t stride = std::size_t(channels);
    for (std::size_t i = 0; i < samples.size() && divisor > 1; i += stride)
        for (int c = 0; c < used && divisor > 1; ++c) divisor = std::gcd(divisor, unsigned(samples[i + std::size_t(c)]));
    return divisor == 0 ? int(max_value) : int(max_value / divisor);
}

}  // namespace leanfade
