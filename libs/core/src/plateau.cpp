// The plateau layer of two-lobe LEAN (leanfade/core/plateau.hpp, docs/math.md §10).
#include "leanfade/core/plateau.hpp"

#include <cmath>
#include <cstdlib>

#include "leanfade/core/error.hpp"

namespace leanfade {

Image plateau_texels(const Image& slopes, float epsilon) {
    if (!std::isfinite(epsilon) || epsilon <= 0.0f)
        throw Error("plateau_epsilon", "must be finite and > 0");
    if (slopes.channels != 2 || slopes.empty())
        throw Error("plateau", "needs a non-empty map of 2-channel slopes");
    const int w = slopes.width, h = slopes.height;
    Image layer(w, h, 4, 0.0f);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float bx = slopes.at(x, y, 0), by = slopes.at(x, y, 1);
            // The four neighbours of a repeating map.
            const int xs[4] = {(x + w - 1) % w, (x + 1) % w, x, x};
            const int ys[4] = {y, y, (y + h - 1) % h, (y + 1) % h};
            bool flat = true;
            for (int i = 0; i < 4 && flat; ++i)
                flat = std::abs(slopes.at(xs[i], ys[i], 0) - bx) < epsilon &&
                       std::abs(slopes.at(xs[i], ys[i], 1) - by) < epsilon;
            if (!flat) continue;
            layer.at(x, y, 0) = 1.0f;
            layer.at(x, y, 1) = bx;
            layer.at(x, y, 2) = by;
            layer.at(x, y, 3) = bx * bx + by * by;
        }
    }
    return layer;
}

std::vector<Image> plateau_mips(const Image& slopes, float epsilon, int threads) {
    return build_mip_chain(plateau_texels(slopes, epsilon), threads);
}

Image packed_top_slopes(const PackedLeanMap& map) {
    if (map.levels.empty()) throw Error("plateau", "the LEAN map has no levels");
    const PackedLevel& top = map.levels.front();
    Image slopes(top.width, top.height, 2);
    for (int y = 0; y < top.height; ++y) {
        for (int x = 0; x < top.width; ++x) {
            // lean2 = (0.5 B / sc + 0.5, ...) (docs/math.md §3).
            const glm::vec4 lean2 = fetch_packed_texel(map, 0, 1, x, y);
            slopes.at(x, y, 0) = (2.0f * lean2.x - 1.0f) * map.scale;
            slopes.at(x, y, 1) = (2.0f * lean2.y - 1.0f) * map.scale;
        }
    }
    return slopes;
}

}  // namespace leanfade
