// The plateau layer of two-lobe LEAN (leanfade/core/plateau.hpp, docs/math.md §10).
#include "leanfade/core/plateau.hpp"

#include <cmath>
#include <cstdlib>
#include <iterator>

#include "leanfade/core/error.hpp"
#include "leanfade/core/parallel.hpp"

namespace leanfade {

Image plateau_texels(const Image& slopes, float epsilon, int threads) {
    if (!std::isfinite(epsilon) || epsilon <= 0.0f)
        throw Error("plateau_epsilon", "must be finite and > 0");
    if (slopes.channels != 2 || slopes.empty())
        throw Error("plateau", "needs a non-empty map of 2-channel slopes");
    const int w = slopes.width, h = slopes.height;
    Image layer(w, h, 4, 0.0f);
    parallel_for_rows(h, threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            // The rows above and below, and the columns left and right, of a repeating map.
            const float* row = slopes.row(y);
            const float* up = slopes.row((y + h - 1) % h);
            const float* down = slopes.row((y + 1) % h);
            float* out = layer.row(y);
            for (int x = 0; x < w; ++x) {
                const float bx = row[2 * x], by = row[2 * x + 1];
                const int left = x == 0 ? w - 1 : x - 1, right = x == w - 1 ? 0 : x + 1;
                auto near = [&](const float* r, int at) {
                    return std::abs(r[2 * at] - bx) < epsilon && std::abs(r[2 * at + 1] - by) < epsilon;
                };
                if (!(near(row, left) && near(row, right) && near(up, x) && near(down, x))) continue;
                out[4 * x] = 1.0f;
                out[4 * x + 1] = bx;
                out[4 * x + 2] = by;
                out[4 * x + 3] = bx * bx + by * by;
            }
        }
    });
    return layer;
}

namespace {

// The next level of an even-sized level: each texel the mean of its 2 x 2 children, which is
// build_mip_chain's area filter for even sizes.
Image halved(const Image& level, int threads) {
    Image next(level.width / 2, level.height / 2, 4);
    parallel_for_rows(next.height, threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            const float* a = level.row(2 * y);
            const float* b = level.row(2 * y + 1);
            float* out = next.row(y);
            for (int x = 0; x < next.width; ++x)
                for (int c = 0; c < 4; ++c)
                    out[4 * x + c] = 0.25f * ((a[8 * x + c] + a[8 * x + 4 + c]) +
                                              (b[8 * x + c] + b[8 * x + 4 + c]));
        }
    });
    return next;
}

}  // namespace

std::vector<Image> plateau_mips(const Image& slopes, float epsilon, int threads) {
    std::vector<Image> chain{plateau_texels(slopes, epsilon, threads)};
    // Halve while both sides are even (any power-of-two map down to 1 x 1); an odd side goes to
    // build_mip_chain's area filter for the rest of the chain.
    while (chain.back().width % 2 == 0 && chain.back().height % 2 == 0)
        chain.push_back(halved(chain.back(), threads));
    if (chain.back().width > 1 || chain.back().height > 1) {
        std::vector<Image> rest = build_mip_chain(chain.back(), threads);
        chain.insert(chain.end(), std::make_move_iterator(rest.begin() + 1),
                     std::make_move_iterator(rest.end()));
    }
    return chain;
}

Image packed_top_slopes(const PackedLeanMap& map, int threads) {
    if (map.levels.empty()) throw Error("plateau", "the LEAN map has no levels");
    const PackedLevel& top = map.levels.front();
    Image slopes(top.width, top.height, 2);
    parallel_for_rows(top.height, threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            for (int x = 0; x < top.width; ++x) {
                // lean2 = (0.5 B / sc + 0.5, ...) (docs/math.md §3).
                const glm::vec4 lean2 = fetch_packed_texel(map, 0, 1, x, y);
                slopes.at(x, y, 0) = (2.0f * lean2.x - 1.0f) * map.scale;
                slopes.at(x, y, 1) = (2.0f * lean2.y - 1.0f) * map.scale;
            }
        }
    });
    return slopes;
}

}  // namespace leanfade
