#pragma once
// Small helpers shared by the core tests; test data is generated in code.
#include <cmath>
#include <functional>

#include "leanfade/core/image.hpp"

namespace leanfade::test {

// A 1-channel height map sampled from f(x, y) at texel centres (x right, y = row down).
inline Image height_from(int w, int h, const std::function<double(double, double)>& f) {
    Image img(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y) = float(f(x, y));
    return img;
}

}  // namespace leanfade::test
