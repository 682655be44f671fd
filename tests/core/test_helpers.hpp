#pragma once
// Small helpers shared by the core tests; test data is generated in code.
#include <cmath>
#include <functional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "leanfade/core/image.hpp"

namespace leanfade::test {

// The mean B and second moments M = (Mxx, Myy, Mxy) of 2-channel slopes over every texel, in
// double.
struct SlopeMoments {
    glm::dvec2 mean{0.0};
    glm::dvec3 second{0.0};
    // The covariance (xx, yy, xy): M - B B^T.
    glm::dvec3 covariance() const {
        return {second.x - mean.x * mean.x, second.y - mean.y * mean.y,
                second.z - mean.x * mean.y};
    }
};
inline SlopeMoments slope_moments(const Image& slopes) {
    SlopeMoments m;
    const double n = double(slopes.texel_count());
    for (std::size_t t = 0; t < slopes.texel_count(); ++t) {
        const double x = slopes.pixels[2 * t], y = slopes.pixels[2 * t + 1];
        m.mean += glm::dvec2(x, y) / n;
        m.second += glm::dvec3(x * x, y * y, x * y) / n;
    }
    return m;
}

// A 1-channel height map sampled from f(x, y) at texel centres (x right, y = row down).
inline Image height_from(int w, int h, const std::function<double(double, double)>& f) {
    Image img(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y) = float(f(x, y));
    return img;
}

}  // namespace leanfade::test
