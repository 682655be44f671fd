#include "leanfade/core/image.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "leanfade/core/detail/memory.hpp"

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

Image resampled(const Image& image, int w, int h) {
    if (image.width == w && image.height == h) return image;
    Image out(w, h, image.channels);
    const auto wrap = [](int v, int n) { return ((v % n) + n) % n; };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float fx = (float(x) + 0.5f) * float(image.width) / float(w) - 0.5f;
            const float fy = (float(y) + 0.5f) * float(image.height) / float(h) - 0.5f;
            const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
            const float tx = fx - float(x0), ty = fy - float(y0);
            for (int c = 0; c < image.channels; ++c) {
                const auto at = [&](int xi, int yi) {
                    return image.pixels[image.index(wrap(xi, image.width), wrap(yi, image.height), c)];
                };
                out.pixels[out.index(x, y, c)] =
                    (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
                    ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
            }
        }
    return out;
}

}  // namespace leanfade
