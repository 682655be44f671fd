// Image metrics: masks, relative RMSE, mean absolute change, masked SSIM, sRGB encoding.
#include "leanfade/eval/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "leanfade/core/error.hpp"

namespace leanfade::eval {
namespace {

void require_rgb(const Image& image, const char* what) {
    if (image.channels < 3) throw Error("image", std::string(what) + " needs 3 or 4 channels");
}

void require_same(const Image& a, const Image& b) {
    require_rgb(a, "a metric");
    require_rgb(b, "a metric");
    if (a.width != b.width || a.height != b.height)
        throw Error("image", "images of different sizes (" + std::to_string(a.width) + "x" +
                                 std::to_string(a.height) + " and " + std::to_string(b.width) +
                                 "x" + std::to_string(b.height) + ")");
}

void require_mask(const Image& image, const Mask& mask) {
    if (mask.width != image.width || mask.height != image.height)
        throw Error("mask", "the mask's size differs from the image's");
}

// Wang et al. 2004: 11 x 11 circular-symmetric Gaussian window, standard deviation 1.5 samples,
// normalised to unit sum (it is separable: the product of two 1-D windows).
constexpr int kSsimRadius = 5;
std::array<double, 2 * kSsimRadius + 1> ssim_window() {
    std::array<double, 2 * kSsimRadius + 1> w{};
    double sum = 0.0;
    for (int i = -kSsimRadius; i <= kSsimRadius; ++i) {
        w[std::size_t(i + kSsimRadius)] = std::exp(-0.5 * double(i * i) / (1.5 * 1.5));
        sum += w[std::size_t(i + kSsimRadius)];
    }
    for (double& v : w) v /= sum;
    return w;
}

// Separable convolution of `plane` (width x height) with the window, zero outside the image.
std::vector<double> blur(const std::vector<double>& plane, int width, int height) {
    static const auto window = ssim_window();
    std::vector<double> horizontal(plane.size(), 0.0), out(plane.size(), 0.0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double s = 0.0;
            for (int i = -kSsimRadius; i <= kSsimRadius; ++i) {
                const int xx = x + i;
                if (xx < 0 || xx >= width) continue;
                s += window[std::size_t(i + kSsimRadius)] *
                     plane[std::size_t(y) * std::size_t(width) + std::size_t(xx)];
            }
            horizontal[std::size_t(y) * std::size_t(width) + std::size_t(x)] = s;
        }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double s = 0.0;
            for (int i = -kSsimRadius; i <= kSsimRadius; ++i) {
                const int yy = y + i;
                if (yy < 0 || yy >= height) continue;
                s += window[std::size_t(i + kSsimRadius)] *
                     horizontal[std::size_t(yy) * std::size_t(width) + std::size_t(x)];
            }
            out[std::size_t(y) * std::size_t(width) + std::size_t(x)] = s;
        }
    return out;
}

}  // namespace

Mask::Mask(int w, int h, bool value)
    : width(w), height(h), inside(std::size_t(w) * std::size_t(h), value ? 1 : 0) {}

int Mask::count() const {
    return int(std::count_if(inside.begin(), inside.end(), [](std::uint8_t v) { return v != 0; }));
}

Mask covered_pixels(const Image& marked) {
    require_rgb(marked, "covered_pixels");
    Mask mask(marked.width, marked.height);
    for (int y = 0; y < marked.height; ++y)
        for (int x = 0; x < marked.width; ++x)
            mask.inside[std::size_t(y) * std::size_t(marked.width) + std::size_t(x)] =
                marked.at(x, y, 0) >= 0.0f && marked.at(x, y, 1) >= 0.0f &&
                marked.at(x, y, 2) >= 0.0f;
    return mask;
}

Mask erode(const Mask& mask) {
    Mask out(mask.width, mask.height);
    for (int y = 1; y + 1 < mask.height; ++y)
        for (int x = 1; x + 1 < mask.width; ++x) {
            bool all = true;
            for (int dy = -1; dy <= 1 && all; ++dy)
                for (int dx = -1; dx <= 1 && all; ++dx) all = mask.at(x + dx, y + dy);
            out.inside[std::size_t(y) * std::size_t(mask.width) + std::size_t(x)] = all ? 1 : 0;
        }
    return out;
}

Mask intersect(const Mask& a, const Mask& b) {
    if (a.width != b.width || a.height != b.height) throw Error("mask", "masks of different sizes");
    Mask out(a.width, a.height);
    for (std::size_t i = 0; i < a.inside.size(); ++i)
        out.inside[i] = (a.inside[i] != 0 && b.inside[i] != 0) ? 1 : 0;
    return out;
}

Image fill_outside(const Image& image, const Mask& mask, float r, float g, float b) {
    require_rgb(image, "fill_outside");
    require_mask(image, mask);
    Image out = image;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (!mask.at(x, y)) {
                out.at(x, y, 0) = r;
                out.at(x, y, 1) = g;
                out.at(x, y, 2) = b;
            }
    return out;
}

double masked_mean(const Image& image, const Mask& mask) {
    require_rgb(image, "masked_mean");
    require_mask(image, mask);
    double sum = 0.0;
    std::size_t n = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (mask.at(x, y)) {
                for (int c = 0; c < 3; ++c) sum += double(image.at(x, y, c));
                n += 3;
            }
    return n == 0 ? 0.0 : sum / double(n);
}

double relative_rmse(const Image& image, const Image& reference, const Mask& mask) {
    require_same(image, reference);
    require_mask(image, mask);
    double squares = 0.0, sum = 0.0;
    std::size_t n = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (mask.at(x, y))
                for (int c = 0; c < 3; ++c) {
                    const double d = double(image.at(x, y, c)) - double(reference.at(x, y, c));
                    squares += d * d;
                    sum += double(reference.at(x, y, c));
                    ++n;
                }
    if (n == 0 || squares == 0.0) return 0.0;
    const double mean = sum / double(n);
    if (!(mean > 0.0)) return std::numeric_limits<double>::infinity();
    return std::sqrt(squares / double(n)) / mean;
}

double mean_absolute_difference(const Image& a, const Image& b, const Mask& mask) {
    require_same(a, b);
    require_mask(a, mask);
    double sum = 0.0;
    std::size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (mask.at(x, y))
                for (int c = 0; c < 3; ++c) {
                    sum += std::abs(double(a.at(x, y, c)) - double(b.at(x, y, c)));
                    ++n;
                }
    return n == 0 ? 0.0 : sum / double(n);
}

double ssim(const Image& a, const Image& b, const Mask& mask) {
    require_same(a, b);
    require_mask(a, mask);
    const int w = a.width, h = a.height;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    if (mask.count() == 0) return 1.0;
    constexpr double kC1 = (0.01 * 1.0) * (0.01 * 1.0);  // (K1 L)^2
    constexpr double kC2 = (0.03 * 1.0) * (0.03 * 1.0);  // (K2 L)^2

    std::vector<double> m(n);
    for (std::size_t i = 0; i < n; ++i) m[i] = mask.inside[i] != 0 ? 1.0 : 0.0;
    const std::vector<double> weight = blur(m, w, h);

    double total = 0.0;
    std::size_t count = 0;
    std::vector<double> px(n), py(n), pxx(n), pyy(n), pxy(n);
    for (int c = 0; c < 3; ++c) {
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                const double vx = m[i] * double(a.at(x, y, c));
                const double vy = m[i] * double(b.at(x, y, c));
                px[i] = vx;
                py[i] = vy;
                pxx[i] = vx * vx;
                pyy[i] = vy * vy;
                pxy[i] = vx * vy;
            }
        const std::vector<double> sx = blur(px, w, h), sy = blur(py, w, h);
        const std::vector<double> sxx = blur(pxx, w, h), syy = blur(pyy, w, h);
        const std::vector<double> sxy = blur(pxy, w, h);
        for (std::size_t i = 0; i < n; ++i) {
            if (m[i] == 0.0) continue;
            const double wi = weight[i];
            const double mx = sx[i] / wi, my = sy[i] / wi;
            const double vx = sxx[i] / wi - mx * mx;
            const double vy = syy[i] / wi - my * my;
            const double cxy = sxy[i] / wi - mx * my;
            total += ((2.0 * mx * my + kC1) * (2.0 * cxy + kC2)) /
                     ((mx * mx + my * my + kC1) * (vx + vy + kC2));
            ++count;
        }
    }
    return total / double(count);
}

float encode_srgb(float linear) {
    const float v = std::clamp(linear, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

Image encode_srgb(const Image& linear) {
    Image out = linear;
    for (std::size_t i = 0; i < out.pixels.size(); ++i)
        if (out.channels < 4 || i % std::size_t(out.channels) != 3)
            out.pixels[i] = encode_srgb(out.pixels[i]);
    return out;
}

}  // namespace leanfade::eval
