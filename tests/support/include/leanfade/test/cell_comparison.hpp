#pragma once
// A picture drawn by another API or program against `leanfade render`'s cell of the same view
// (tests/vulkan, tests/web): both converted as the figures are (linear radiance to 8-bit sRGB
// codes), compared code by code. Needs leanfade_eval.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/eval/metrics.hpp"

namespace leanfade::test {

// The conversion of the figures (and PNG cells) of `leanfade render`: linear radiance to 8-bit
// sRGB codes, RGB of each pixel in row order.
inline std::vector<int> srgb_codes(const Image& linear) {
    const Image encoded = eval::encode_srgb(linear);
    std::vector<int> codes;
    for (int y = 0; y < encoded.height; ++y)
        for (int x = 0; x < encoded.width; ++x)
            for (int c = 0; c < 3; ++c)
                codes.push_back(int(std::lround(
                    std::clamp(encoded.pixels[encoded.index(x, y, c)], 0.0f, 1.0f) * 255.0f)));
    return codes;
}

struct CellComparison {
    double rmse = 0.0;         // over every pixel, 8-bit codes
    double object_rmse = 0.0;  // over the pixels the object covers in either image
    int max_difference = 0;
    double covered = 0.0;      // fraction of the reference's pixels the object covers
    // Fraction of the pixels whose largest channel difference exceeds `far_codes` (where the two
    // rasterisers disagree on a silhouette pixel's coverage, the whole pixel differs).
    double far_fraction = 0.0;
};

// `image` against `reference` (the same size). The background is the top-left pixel's code (the
// object never reaches the corners of the views compared).
inline CellComparison compare_cells(const Image& image, const Image& reference, int far_codes = 8) {
    const std::vector<int> a = srgb_codes(image), b = srgb_codes(reference);
    auto background = [](const std::vector<int>& codes, std::size_t i) {
        return codes[i] == codes[0] && codes[i + 1] == codes[1] && codes[i + 2] == codes[2];
    };
    CellComparison c;
    double sum = 0.0, object_sum = 0.0;
    std::size_t covered = 0, object_pixels = 0, far = 0;
    for (std::size_t i = 0; i + 2 < a.size() && i + 2 < b.size(); i += 3) {
        double pixel = 0.0;
        int largest = 0;
        for (std::size_t k = i; k < i + 3; ++k) {
            const int d = a[k] - b[k];
            pixel += double(d) * double(d);
            largest = std::max(largest, std::abs(d));
        }
        c.max_difference = std::max(c.max_difference, largest);
        far += largest > far_codes;
        sum += pixel;
        covered += !background(b, i);
        if (!background(a, i) || !background(b, i)) {
            object_sum += pixel;
            ++object_pixels;
        }
    }
    const double pixels = double(b.size() / 3);
    c.rmse = std::sqrt(sum / double(b.size()));
    c.object_rmse = object_pixels > 0 ? std::sqrt(object_sum / double(3 * object_pixels)) : 0.0;
    c.covered = double(covered) / pixels;
    c.far_fraction = double(far) / pixels;
    return c;
}

}  // namespace leanfade::test
