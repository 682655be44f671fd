// The plateau layer of two-lobe LEAN (leanfade/core/detail/plateau.hpp, docs/math.md §10).
#include "leanfade/core/detail/plateau.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iterator>
#include <limits>
#include <span>
#include <string>
#include <type_traits>

#include "lean_map_internal.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/memory.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/shading.hpp"
#include "plateau_internal.hpp"

namespace leanfade {
namespace {

// The levels the packed bake's plateau pass makes row block by row block (plateau_layer_to).
constexpr int kMaxStreamedLevels = 4;

void check_epsilon(float epsilon) {
    if (!std::isfinite(epsilon) || epsilon <= 0.0f)
        throw Error::setting("plateau_epsilon", "must be finite and > 0");
}

// Calls body(std::integral_constant<Storage, S>) for the storage S = `storage`, so that the
// per-channel loads and stores below are resolved at compile time.
template <typename Body>
void with_storage(Storage storage, Body&& body) {
    switch (storage) {
        case Storage::Unorm8: return body(std::integral_constant<Storage, Storage::Unorm8>{});
        case Storage::Unorm16: return body(std::integral_constant<Storage, Storage::Unorm16>{});
        case Storage::Float16: return body(std::integral_constant<Storage, Storage::Float16>{});
        case Storage::Float32: return body(std::integral_constant<Storage, Storage::Float32>{});
    }
}

// The slopes (2 floats per texel, slope units) of a finest-level lean2 row of w texels
// (docs/math.md §3: lean2 = (g B / sc + o, ...), B = ((1 + o) s - o) sc with o = `offset`).
void decode_slope_row(const std::uint8_t* lean2_row, int w, Storage storage, float sc, float offset,
                      float* out) {
    const float gain = 1.0f + offset;
    with_storage(storage, [&](auto s) {
        constexpr Storage S = decltype(s)::value;
        const std::size_t texel_bytes = std::size_t(bytes_per_texel(S));
        for (int x = 0; x < w; ++x) {
            const std::uint8_t* texel = lean2_row + std::size_t(x) * texel_bytes;
            out[2 * x] = (gain * detail::load_channel(texel, 0, S) - offset) * sc;
            out[2 * x + 1] = (gain * detail::load_channel(texel, 1, S) - offset) * sc;
        }
    });
}

// unorm_code (lean_map_internal.hpp) without a call to the C library's rounding: a value in
// (0, Q] plus 2^23 lies where floats are the integers, so the sum rounds it to the nearest
// integer, ties to even, as nearbyint does in the default rounding mode.
inline std::uint16_t plateau_code(float value, float max_code) {
    if (!(value > 0.0f)) return 0;
    constexpr float kIntegers = 8388608.0f;  // 2^23
    return std::uint16_t((std::min(value, max_code) + kIntegers) - kIntegers);
}

// One row of plateau texels (PlateauRule, plateau.hpp) from the 2-channel slopes of the row and
// of the rows at -1, +1, -radius_y and +radius_y (the map repeats) into 4 floats per texel. A
// texel is on a plateau when each component of its slope differs by less than rule.epsilon from
// each of the slopes 1 and radius texels away along both axes (with radius 1 those are the same
// four neighbours).
struct StencilRows {
    const float* row;
    const float* up;
    const float* down;
    const float* far_up;
    const float* far_down;
};

// Whether each component of the slope at texel `at` of row `r` is within epsilon of (bx, by).
inline bool near_slope(const float* r, int at, float bx, float by, float epsilon) {
    return std::abs(r[2 * at] - bx) < epsilon && std::abs(r[2 * at + 1] - by) < epsilon;
}

// No packing (the reference path packs its float levels afterwards).
struct NoPacker {
    static constexpr std::size_t kTexelBytes = 0;
    void pack_off(std::uint8_t*) const {}
    void pack_values(const float*, std::uint8_t*) const {}
};

// Whether texel x of the stencil's row lies on a plateau (PlateauRule).
inline bool on_plateau(const StencilRows& rows, int x, int left, int right, int far_left,
                       int far_right, float epsilon) {
    const float bx = rows.row[2 * x], by = rows.row[2 * x + 1];
    // Most texels of a bumpy map fail the first comparisons: tested in order, stopping there.
    return near_slope(rows.row, left, bx, by, epsilon) &&
           near_slope(rows.row, right, bx, by, epsilon) &&
           near_slope(rows.up, x, bx, by, epsilon) && near_slope(rows.down, x, bx, by, epsilon) &&
           near_slope(rows.row, far_left, bx, by, epsilon) &&
           near_slope(rows.row, far_right, bx, by, epsilon) &&
           near_slope(rows.far_up, x, bx, by, epsilon) &&
           near_slope(rows.far_down, x, bx, by, epsilon);
}

// One plateau texel, w (1, B, |B|^2) with the spike weight w (1 on a plateau, else the central
// window's), into `texel` (4 floats) and, packed by `packer`, into `packed`.
template <typename Packer>
inline void plateau_texel(const StencilRows& rows, int x, int left, int right, int far_left,
                          int far_right, const PlateauRule& rule, float* texel,
                          const Packer& packer, std::uint8_t* packed) {
    const float bx = rows.row[2 * x], by = rows.row[2 * x + 1];
    const float weight =
        rule.window.with_plateaus &&
                on_plateau(rows, x, left, right, far_left, far_right, rule.epsilon)
            ? 1.0f
            : spike_window_weight(rule.window, bx, by);
    if (!(weight > 0.0f)) {
        texel[0] = texel[1] = texel[2] = texel[3] = 0.0f;
        packer.pack_off(packed);
        return;
    }
    // w = 1 gives (1, Bx, By, |B|^2) bit for bit.
    texel[0] = weight;
    texel[1] = weight * bx;
    texel[2] = weight * by;
    texel[3] = weight * (bx * bx + by * by);
    packer.pack_values(texel, packed);
}

// A row of plateau texels (4 floats each) into `out` and, packed, into `packed` (the level's row
// in the storage; unused with NoPacker).
template <typename Packer = NoPacker>
void plateau_row(const StencilRows& rows, int w, const PlateauRule& rule, float* out,
                 const Packer& packer = {}, std::uint8_t* packed = nullptr) {
    const int rx = rule.radius_x % w;
    constexpr std::size_t bytes = Packer::kTexelBytes;
    // The texels whose neighbours (1 and rx away) need no wrap, without index arithmetic;
    // the others wrapped.
    const int margin = std::max(1, rx);
    const int first = std::min(margin, w), end = std::max(first, w - margin);
    auto wrapped = [&](int x) {
        const int left = x == 0 ? w - 1 : x - 1, right = x == w - 1 ? 0 : x + 1;
        plateau_texel(rows, x, left, right, (x - rx + w) % w, (x + rx) % w, rule, out + 4 * x,
                      packer, packed + std::size_t(x) * bytes);
    };
    for (int x = 0; x < first; ++x) wrapped(x);
    for (int x = first; x < end; ++x)
        plateau_texel(rows, x, x - 1, x + 1, x - rx, x + rx, rule, out + 4 * x, packer,
                      packed + std::size_t(x) * bytes);
    for (int x = end; x < w; ++x) wrapped(x);
}

// The slope rows of a map one thread walks down: row(y) for any y (the map repeats), decoded by
// `decode(y mod h, out)` once while it stays within the last `capacity` rows asked for.
class SlopeRowWindow {
public:
    template <typename Decode>
    SlopeRowWindow(int width, int height, int capacity, Decode decode)
        : width_(width), height_(height), decode_(std::move(decode)),
          rows_(std::size_t(capacity)), keys_(std::size_t(capacity), kNone) {
        for (auto& r : rows_) r.resize(2 * std::size_t(width_));
    }
    const float* row(long y) {
        const std::size_t slot = std::size_t(((y % long(rows_.size())) + long(rows_.size())) %
                                             long(rows_.size()));
        if (keys_[slot] != y) {
            decode_(int(((y % height_) + height_) % height_), rows_[slot].data());
            keys_[slot] = y;
        }
        return rows_[slot].data();
    }
    StencilRows stencil(int y, const PlateauRule& rule) {
        // Every row fetched before the first use: the window holds 2 radius_y + 3 rows at least.
        const float* far_up = row(long(y) - rule.radius_y);
        const float* up = row(long(y) - 1);
        const float* r = row(y);
        const float* down = row(long(y) + 1);
        const float* far_down = row(long(y) + rule.radius_y);
        return {r, up, down, far_up, far_down};
    }

private:
    static constexpr long kNone = std::numeric_limits<long>::min();
    int width_, height_;
    std::function<void(int, float*)> decode_;
    std::vector<std::vector<float>> rows_;
    std::vector<long> keys_;
};

// One texel of the next level of an even-sized level from its 2 x 2 children (rows a, b, texel
// x): build_mip_chain's area filter for even sizes.
inline void box_texel(const float* a, const float* b, int x, float* out) {
    for (int c = 0; c < 4; ++c)
        out[c] = 0.25f * ((a[8 * x + c] + a[8 * x + 4 + c]) + (b[8 * x + c] + b[8 * x + 4 + c]));
}

Image halved(const Image& level, int threads) {
    Image next(level.width / 2, level.height / 2, 4);
    parallel_for_rows(next.height, threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            const float* a = level.row(2 * y);
            const float* b = level.row(2 * y + 1);
            float* out = next.row(y);
            for (int x = 0; x < next.width; ++x) box_texel(a, b, x, out + 4 * x);
        }
    });
    return next;
}

// Appends the levels below chain.back() down to 1 x 1: halved while both sides are even (any
// power-of-two map), then build_mip_chain's area filter for the rest.
void extend_chain(std::vector<Image>& chain, int threads) {
    while (chain.back().width % 2 == 0 && chain.back().height % 2 == 0)
        chain.push_back(halved(chain.back(), threads));
    if (chain.back().width > 1 || chain.back().height > 1) {
        std::vector<Image> rest = build_mip_chain(chain.back(), threads);
        chain.insert(chain.end(), std::make_move_iterator(rest.begin() + 1),
                     std::make_move_iterator(rest.end()));
    }
}

// The stored form of float plateau texels (f, f Bs, f |Bs|^2) in storage S
// (PackedLevel::plateau): UNORM codes are one multiply(-add) each, rounded and clamped as the
// moments' (lean_map_internal.hpp, unorm_code), with
//   f * Q,  f Bs * (Q/2)/sc + Q/2,  f |Bs|^2 * (Q/2)/sc^2;
// float storages (f, g f Bs / sc + o, g f |Bs|^2 / sc^2) with g, o = 0.5, 0.5 (offset = 1, the
// offset encoding) or 1, 0 (offset = 0, the signed encoding).
template <Storage S>
struct PlateauPacker {
    static constexpr std::size_t kTexelBytes =
        S == Storage::Unorm8 ? 4 : S == Storage::Float32 ? 16 : 8;  // bytes_per_texel(S)
    static constexpr bool kUnorm = S == Storage::Unorm8 || S == Storage::Unorm16;
    float factor[4] = {}, offset[4] = {}, max_code = 0.0f;  // UNORM
    float sc = 1.0f, sc2 = 1.0f, g = 1.0f, o = 0.0f;        // float storages
    // A texel off every plateau (f = 0, all four values 0) always packs to these bytes.
    std::uint8_t off_plateau[8] = {};

    PlateauPacker(float scale, float encoding_offset) : sc(scale), sc2(scale * scale) {
        assert(int(kTexelBytes) == bytes_per_texel(S));
        if constexpr (kUnorm) {
            const detail::UnormPacking k = detail::unorm_packing(S, sc, sc2);
            // Per channel value * factor + offset (a + 0 changes no code: -0 and +0 are code 0).
            const float f[4] = {k.max, k.b_factor, k.b_factor, k.mxy_factor};
            const float a[4] = {0.0f, k.half, k.half, 0.0f};
            std::copy(f, f + 4, factor);
            std::copy(a, a + 4, offset);
            max_code = k.max;
            std::uint16_t codes[4];
            for (int c = 0; c < 4; ++c) codes[c] = plateau_code(offset[c], max_code);
            detail::store_unorm_texel(off_plateau, codes, S);
        } else {
            g = encoding_offset > 0.0f ? 0.5f : 1.0f;
            o = encoding_offset > 0.0f ? 0.5f : 0.0f;
            const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            pack_values(zero, off_plateau);
        }
    }
    void pack_values(const float* v, std::uint8_t* texel) const {
        if constexpr (kUnorm) {
            std::uint16_t codes[4];
            for (int c = 0; c < 4; ++c) codes[c] = plateau_code(v[c] * factor[c] + offset[c], max_code);
            detail::store_unorm_texel(texel, codes, S);
        } else {
            const float stored[4] = {v[0], g * v[1] / sc + o, g * v[2] / sc + o, g * v[3] / sc2};
            for (int c = 0; c < 4; ++c) detail::store_float_channel(texel, c, stored[c], S);
        }
    }
    void pack_off(std::uint8_t* texel) const { std::memcpy(texel, off_plateau, kTexelBytes); }
    void pack(const float* v, std::uint8_t* texel) const {
        if (v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f && v[3] == 0.0f)
            pack_off(texel);
        else
            pack_values(v, texel);
    }
};

void pack_plateau_texels(const float* values, std::size_t count, Storage storage, float sc,
                         float offset, std::uint8_t* out) {
    with_storage(storage, [&](auto s) {
        constexpr Storage S = decltype(s)::value;
        const PlateauPacker<S> packer(sc, offset);
        for (std::size_t i = 0; i < count; ++i)
            packer.pack(values + 4 * i, out + i * PlateauPacker<S>::kTexelBytes);
    });
}

void pack_plateau_level(const Image& level, Storage storage, float sc, float offset,
                        std::uint8_t* out, int threads) {
    const int texel_bytes = bytes_per_texel(storage);
    parallel_for_rows(level.height, threads, [&](int first, int end) {
        for (int y = first; y < end; ++y)
            pack_plateau_texels(
                level.row(y), std::size_t(level.width), storage, sc, offset,
                out + std::size_t(y) * std::size_t(level.width) * std::size_t(texel_bytes));
    });
}

Image slopes_of_lean2(const std::uint8_t* lean2, int width, int height, Storage storage, float sc,
                      float offset, int threads) {
    Image slopes(width, height, 2);
    const int texel_bytes = bytes_per_texel(storage);
    parallel_for_rows(height, threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            const std::uint8_t* row =
                lean2 + std::size_t(y) * std::size_t(width) * std::size_t(texel_bytes);
            decode_slope_row(row, width, storage, sc, offset, slopes.row(y));
        }
    });
    return slopes;
}

Image plateau_texels_with_rule(const Image& slopes, const PlateauRule& rule, int threads) {
    const int w = slopes.width, h = slopes.height;
    Image layer(w, h, 4, 0.0f);
    parallel_for_rows(h, threads, [&](int first, int end) {
        auto row_at = [&](long y) { return slopes.row(int(((y % h) + h) % h)); };
        for (int y = first; y < end; ++y)
            plateau_row({slopes.row(y), row_at(long(y) - 1), row_at(long(y) + 1),
                         row_at(long(y) - rule.radius_y), row_at(long(y) + rule.radius_y)},
                        w, rule, layer.row(y));
    });
    return layer;
}

// The mean f of a level of the float layer (the coarsest: the map's fraction on a plateau).
float mean_fraction(const Image& level) {
    double sum = 0.0;
    for (std::size_t i = 0; i < level.texel_count(); ++i) sum += level.pixels[4 * i];
    return float(std::clamp(sum / double(std::max<std::size_t>(level.texel_count(), 1)), 0.0, 1.0));
}

void check_slopes(const Image& slopes) {
    if (slopes.channels != 2 || slopes.empty())
        throw Error("plateau", "needs a non-empty map of 2-channel slopes");
}

void check_rule(const PlateauRule& rule) {
    check_epsilon(rule.epsilon);
    if (rule.radius_x < 1 || rule.radius_y < 1)
        throw Error("plateau", "the rule's radius must be at least 1 texel");
}


// --- The central window's fit (fit_spike_window, plateau.hpp) ---

constexpr long kFitMaxSamples = 65536;   // texels of the grid the fit measures on
constexpr int kFitBlocksPerSide = 16;    // the middle footprints: a 16th of the map's side
constexpr float kFitShininess[] = {128.0f, 1024.0f, 13777.0f};
// The half vectors probed around the mean slope: a plane near its mirror direction sees slopes
// within about this much of its mirror slope (slope units).
constexpr float kFitProbeRadius = 0.05f;
constexpr float kFitDiscRadii[] = {0.02f, 0.05f, 0.1f, 0.17f, 0.25f, 0.35f, 0.5f};  // x std dev
constexpr float kFitBiweightRadii[] = {0.5f, 1.0f, 1.5f, 2.0f, 2.5f};
// A probe's error is |ln((model + floor) / (truth + floor))| with floor this share of the truth's
// largest probe: half vectors where the truth has next to nothing light next to nothing.
constexpr double kFitFloor = 0.05;

struct SlopeSamples {
    int columns = 0, rows = 0;
    std::vector<float> slopes;       // 2 per sample, rows top first
    std::vector<std::uint8_t> flat;  // on a plateau (the rule's)
};

// The slopes and plateau flags of a regular grid of at most kFitMaxSamples texels of a w x h map
// (texel centres of every stride-th row and column), decode(y, out) giving row y's slopes.
template <typename Decode>
SlopeSamples sample_slopes(int w, int h, const PlateauRule& rule, Decode decode, int threads) {
    int stride = 1;
    while (long(w / stride) * long(h / stride) > kFitMaxSamples) ++stride;
    SlopeSamples samples;
    samples.columns = std::max(1, w / stride);
    samples.rows = std::max(1, h / stride);
    const std::size_t count = std::size_t(samples.columns) * std::size_t(samples.rows);
    samples.slopes.resize(2 * count);
    samples.flat.resize(count);
    const int rx = rule.radius_x % w, half = stride / 2;
    parallel_for_rows(samples.rows, threads, [&](int first, int end) {
        SlopeRowWindow window(w, h, 2 * rule.radius_y + 4, decode);
        for (int j = first; j < end; ++j) {
            const StencilRows rows = window.stencil(std::min(j * stride + half, h - 1), rule);
            for (int i = 0; i < samples.columns; ++i) {
                const int x = std::min(i * stride + half, w - 1);
                const std::size_t at = std::size_t(j) * std::size_t(samples.columns) + std::size_t(i);
                samples.slopes[2 * at] = rows.row[2 * x];
                samples.slopes[2 * at + 1] = rows.row[2 * x + 1];
                samples.flat[at] = on_plateau(rows, x, (x + w - 1) % w, (x + 1) % w,
                                              (x - rx + w) % w, (x + rx) % w, rule.epsilon);
            }
        }
    });
    return samples;
}

// The moments of a set of samples under a window: the LEAN map's (B, M) and the spike layer's
// (f, f Bs, f |Bs|^2), as sums.
struct FitSums {
    double n = 0, bx = 0, by = 0, mxx = 0, myy = 0, mxy = 0, f = 0, fbx = 0, fby = 0, fbb = 0;
    void add(float x, float y, float weight) {
        n += 1.0;
        bx += x;
        by += y;
        mxx += double(x) * x;
        myy += double(y) * y;
        mxy += double(x) * y;
        if (weight > 0.0f) {
            f += weight;
            fbx += double(weight) * x;
            fby += double(weight) * y;
            fbb += double(weight) * (double(x) * x + double(y) * y);
        }
    }
    // Two-lobe LEAN's density (lf_two_lobe_density) at each of the half vectors `probes`, added
    // to `out`, with the lobe the shaders set up (lf_lobe_setup) at Blinn-Phong's base roughness
    // `params` (1/s per axis).
    void add_density(std::span<const glm::vec2> probes, const shading::LfParams& params,
                     double* out) const {
        using namespace shading;
        LfMoments m;
        const double k = 1.0 / n;
        m.normal = vec3(0.0f, 0.0f, 1.0f);
        m.mean = vec2(float(bx * k), float(by * k));
        m.second = vec3(float(mxx * k), float(myy * k), float(mxy * k));
        m.plateau = vec4(float(f * k), float(fbx * k), float(fby * k), float(fbb * k));
        const LfLobe lobe = lf_lobe_setup(LF_TECHNIQUE_TWO_LOBE, m, params);
        for (std::size_t i = 0; i < probes.size(); ++i)
            out[i] += lf_two_lobe_density(lobe, vec3(probes[i].x, probes[i].y, 1.0f));
    }
};

// The densest spot of the samples' slopes: the mean slope of the samples in the 3 x 3 bins of
// a histogram (bins of a 50th of the standard deviation, over 3 of them around the mean) that hold
// the most. On a map of flat faces, the faces' slope.
glm::vec2 slope_mode(const float* b, std::size_t count, glm::vec2 mean, float sd) {
    constexpr int kBins = 300;
    const float bin = sd / 50.0f;
    const glm::vec2 origin = mean - float(kBins / 2) * bin;
    std::vector<std::uint32_t> histogram(std::size_t(kBins) * kBins, 0);
    auto cell = [&](float x, float y, int& i, int& j) {
        i = int(std::floor((x - origin.x) / bin));
        j = int(std::floor((y - origin.y) / bin));
        return i >= 0 && j >= 0 && i < kBins && j < kBins;
    };
    for (std::size_t k = 0; k < count; ++k) {
        int i, j;
        if (cell(b[2 * k], b[2 * k + 1], i, j)) ++histogram[std::size_t(j) * kBins + std::size_t(i)];
    }
    std::uint64_t best = 0;
    int best_i = kBins / 2, best_j = kBins / 2;
    for (int j = 1; j + 1 < kBins; ++j)
        for (int i = 1; i + 1 < kBins; ++i) {
            std::uint64_t sum = 0;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di)
                    sum += histogram[std::size_t(j + dj) * kBins + std::size_t(i + di)];
            if (sum > best) {
                best = sum;
                best_i = i;
                best_j = j;
            }
        }
    double sx = 0, sy = 0, n = 0;
    for (std::size_t k = 0; k < count; ++k) {
        int i, j;
        if (cell(b[2 * k], b[2 * k + 1], i, j) && std::abs(i - best_i) <= 1 &&
            std::abs(j - best_j) <= 1) {
            sx += b[2 * k];
            sy += b[2 * k + 1];
            n += 1;
        }
    }
    return n > 0 ? glm::vec2(float(sx / n), float(sy / n)) : mean;
}

SpikeWindowFit fit_samples(const SlopeSamples& samples) {
    const std::size_t count = samples.flat.size();
    const float* b = samples.slopes.data();
    FitSums all;
    for (std::size_t i = 0; i < count; ++i) all.add(b[2 * i], b[2 * i + 1], 0.0f);
    const glm::vec2 mean(float(all.bx / all.n), float(all.by / all.n));
    const double variance = std::max(0.0, (all.mxx + all.myy) / all.n -
                                              double(mean.x) * mean.x - double(mean.y) * mean.y);
    const float sd = float(std::sqrt(variance));
    SpikeWindowFit result;
    std::size_t flat = 0;
    for (std::uint8_t v : samples.flat) flat += v;
    result.plateau_fraction = float(double(flat) / double(std::max<std::size_t>(count, 1)));
    const bool plateaus_found = flat > 0;
    if (!(sd > 0.0f)) return result;  // one slope everywhere: nothing to fit
    const glm::vec2 mode = slope_mode(b, count, mean, sd);

    // Probes: the mean slope, the densest slope, and rings of 6 around the mean at half and the
    // whole probe radius.
    std::vector<glm::vec2> probes{mean, mode};
    for (int ring = 1; ring <= 2; ++ring)
        for (int k = 0; k < 6; ++k) {
            const float angle = 1.04719755f * float(k) + (ring == 2 ? 0.52359878f : 0.0f);
            probes.push_back(mean + 0.5f * float(ring) * kFitProbeRadius *
                                        glm::vec2(std::cos(angle), std::sin(angle)));
        }
    const std::size_t probe_count = probes.size();
    // The truth: every sample's own lobe, averaged (the supersampled footprint's density), per
    // shininess and probe.
    constexpr std::size_t kShininesses = std::size(kFitShininess);
    std::vector<double> truth(kShininesses * probe_count, 0.0);
    double floor[kShininesses] = {};
    shading::LfParams params[kShininesses];
    for (std::size_t si = 0; si < kShininesses; ++si) {
        const float inv_s = 1.0f / kFitShininess[si];
        params[si] = shading::lf_default_params();
        params[si].shininess = kFitShininess[si];
        params[si].inv_s_shading = inv_s;
        const shading::vec3 sigma(inv_s, inv_s, 0.0f);
        double* t = &truth[si * probe_count];
        for (std::size_t i = 0; i < count; ++i) {
            const shading::vec2 bi(b[2 * i], b[2 * i + 1]);
            for (std::size_t k = 0; k < probe_count; ++k)
                t[k] += shading::lf_lean_lobe(shading::vec3(probes[k].x, probes[k].y, 1.0f), bi,
                                              sigma);
        }
        double peak = 0.0;
        for (std::size_t k = 0; k < probe_count; ++k) {
            t[k] /= double(count);
            peak = std::max(peak, t[k]);
        }
        floor[si] = kFitFloor * peak;
    }
    // A candidate's largest probe error over the shininesses, for the whole map and for the
    // middle footprints (their densities summed, as a picture's pixels sum them).
    const int block_columns = std::max(1, samples.columns / kFitBlocksPerSide);
    const int block_rows = std::max(1, samples.rows / kFitBlocksPerSide);
    const int blocks_x = samples.columns / block_columns, blocks_y = samples.rows / block_rows;
    std::vector<double> model(2 * probe_count);
    auto error_of = [&](const SpikeWindow& window) {
        std::vector<FitSums> blocks(std::size_t(blocks_x) * std::size_t(blocks_y));
        FitSums whole;
        for (int j = 0; j < samples.rows; ++j)
            for (int i = 0; i < samples.columns; ++i) {
                const std::size_t at = std::size_t(j) * std::size_t(samples.columns) + std::size_t(i);
                const float x = b[2 * at], y = b[2 * at + 1];
                const float weight = window.with_plateaus && samples.flat[at]
                                         ? 1.0f
                                         : spike_window_weight(window, x, y);
                whole.add(x, y, weight);
                const int bi = i / block_columns, bj = j / block_rows;
                if (bi < blocks_x && bj < blocks_y)
                    blocks[std::size_t(bj) * std::size_t(blocks_x) + std::size_t(bi)].add(x, y, weight);
            }
        double worst = 0.0;
        for (std::size_t si = 0; si < kShininesses; ++si) {
            std::fill(model.begin(), model.end(), 0.0);
            whole.add_density(probes, params[si], model.data());
            for (const FitSums& block : blocks)
                block.add_density(probes, params[si], model.data() + probe_count);
            const double* t = &truth[si * probe_count];
            for (std::size_t k = 0; k < probe_count; ++k) {
                const double got[2] = {model[k], model[probe_count + k] / double(blocks.size())};
                for (double g : got) {
                    const double ratio = (g + floor[si]) / (t[k] + floor[si]);
                    worst = std::max(worst, ratio > 0.0 && std::isfinite(ratio)
                                                ? std::abs(std::log(ratio))
                                                : std::numeric_limits<double>::infinity());
                }
            }
        }
        return worst;
    };
    SpikeWindow best;  // the plateaus alone
    double best_error = error_of(best);
    result.plateaus_error = float(best_error);
    auto consider = [&](SpikeWindowShape shape, glm::vec2 anchor, float radius_in_sd,
                        bool with_plateaus) {
        SpikeWindow window{shape, anchor, radius_in_sd * sd, with_plateaus};
        const double error = error_of(window);
        if (error < best_error) {
            best_error = error;
            best = window;
        }
    };
    for (glm::vec2 anchor : {mean, mode})
        for (bool with_plateaus : {true, false}) {
            if (with_plateaus && !plateaus_found) continue;  // the same as without
            for (float r : kFitDiscRadii) consider(SpikeWindowShape::Disc, anchor, r, with_plateaus);
            for (float r : kFitBiweightRadii)
                consider(SpikeWindowShape::Biweight, anchor, r, with_plateaus);
        }
    result.window = best;
    result.error = float(best_error);
    return result;
}

}  // namespace

const char* to_string(SpikeWindowShape shape) {
    switch (shape) {
        case SpikeWindowShape::Disc: return "disc";
        case SpikeWindowShape::Biweight: return "biweight";
        case SpikeWindowShape::None: break;
    }
    return "none";
}

const char* to_string(SpikeFit fit) { return fit == SpikeFit::Auto ? "auto" : "plateaus"; }

const std::vector<std::string>& spike_fit_names() {
    static const std::vector<std::string> names{to_string(SpikeFit::Auto),
                                                to_string(SpikeFit::Plateaus)};
    return names;
}

SpikeFit parse_spike_fit(const std::string& name, const std::string& setting) {
    for (SpikeFit fit : {SpikeFit::Auto, SpikeFit::Plateaus})
        if (name == to_string(fit)) return fit;
    throw Error::setting(setting, "'" + name + "' is not one of auto, plateaus");
}

SpikeWindowFit fit_spike_window(const Image& slopes, const PlateauRule& rule, int threads) {
    check_rule(rule);
    check_slopes(slopes);
    return fit_samples(sample_slopes(
        slopes.width, slopes.height, rule,
        [&](int y, float* out) {
            std::memcpy(out, slopes.row(y), 2 * sizeof(float) * std::size_t(slopes.width));
        },
        threads));
}

PlateauRule plateau_rule(int width, int height, float epsilon, float quantisation_step) {
    check_epsilon(epsilon);
    if (width < 1 || height < 1) throw Error("plateau", "needs a map of at least 1 x 1 texels");
    PlateauRule rule;
    rule.epsilon = epsilon;
    auto radius = [](int texels) {
        return std::max(1, int(std::lround(double(texels) / kPlateauReferenceTexels)));
    };
    rule.radius_x = radius(width);
    rule.radius_y = radius(height);
    rule.quantisation_step =
        std::isfinite(quantisation_step) ? std::max(quantisation_step, 0.0f) : 0.0f;
    const float floor = kPlateauQuantisationSteps * rule.quantisation_step;
    if (floor > epsilon) {
        // A quantised map: its noise on flat ground is a step or so between neighbours, which a
        // ramp of one step per texel also is; at 2 texels apart the ramp has moved 2 steps.
        rule.epsilon = floor;
        rule.radius_x = std::max(rule.radius_x, 2);
        rule.radius_y = std::max(rule.radius_y, 2);
    }
    return rule;
}

float source_slope_step(BakeSource source, int unorm_max, float strength) {
    if (unorm_max <= 0) return 0.0f;
    // A normal map: one code of a normal component, 2 / max, is that much slope where the
    // surface is flat (B = -n.xy / n.z, n.z = 1). A height map: one code of a neighbour's height,
    // 1 / max, moves the Sobel slope by 2/8 of it, times the strength (docs/math.md §2).
    const float code = 1.0f / float(unorm_max);
    return source == BakeSource::Normal ? 2.0f * code : 0.25f * code * std::abs(strength);
}

float storage_slope_step(Storage storage, float sc) {
    // lean2 = 0.5 B / sc + 0.5: one code of B is 2 sc / max. The float storages round relative
    // to the value (no fixed step).
    switch (storage) {
        case Storage::Unorm8: return 2.0f * sc / 255.0f;
        case Storage::Unorm16: return 2.0f * sc / 65535.0f;
        default: return 0.0f;
    }
}

PlateauRule plateau_rule_for(const Image& slopes, float epsilon) {
    check_slopes(slopes);
    return plateau_rule(slopes.width, slopes.height, epsilon);
}

Image plateau_texels(const Image& slopes, const PlateauRule& rule, int threads) {
    check_rule(rule);
    check_slopes(slopes);
    return plateau_texels_with_rule(slopes, rule, threads);
}

Image plateau_texels(const Image& slopes, float epsilon, int threads) {
    check_epsilon(epsilon);
    return plateau_texels(slopes, plateau_rule_for(slopes, epsilon), threads);
}

std::vector<Image> plateau_mips(const Image& slopes, const PlateauRule& rule, int threads) {
    std::vector<Image> chain{plateau_texels(slopes, rule, threads)};
    extend_chain(chain, threads);
    return chain;
}

std::vector<Image> plateau_mips(const Image& slopes, float epsilon, int threads) {
    check_epsilon(epsilon);
    return plateau_mips(slopes, plateau_rule_for(slopes, epsilon), threads);
}

Image packed_top_slopes(const PackedLeanMap& map, int threads) {
    if (map.levels.empty()) throw Error("plateau", "the LEAN map has no levels");
    const PackedLevel& top = map.levels.front();
    const std::size_t bytes =
        std::size_t(top.width) * std::size_t(top.height) * std::size_t(bytes_per_texel(map.storage));
    if (top.lean2.size() != bytes) throw Error("plateau", "the LEAN map's finest level is not packed");
    return slopes_of_lean2(top.lean2.data(), top.width, top.height, map.storage, map.scale,
                           lean_offset(map.encoding), threads);
}

void add_plateau_layer(PackedLeanMap& map, float epsilon, int threads, float source_step,
                       SpikeFit fit) {
    check_epsilon(epsilon);
    const Image slopes = packed_top_slopes(map, threads);
    PlateauRule rule =
        plateau_rule(slopes.width, slopes.height, epsilon,
                     std::max(source_step, storage_slope_step(map.storage, map.scale)));
    if (fit == SpikeFit::Auto) rule.window = fit_spike_window(slopes, rule, threads).window;
    set_plateau_layer(map, plateau_mips(slopes, rule, threads), epsilon, threads);
}

void set_plateau_layer(PackedLeanMap& map, const std::vector<Image>& chain, float epsilon,
                       int threads) {
    check_epsilon(epsilon);
    if (chain.size() != map.levels.size())
        throw Error("plateau", "the LEAN map's MIP chain is not complete");
    const int texel_bytes = bytes_per_texel(map.storage);
    for (std::size_t l = 0; l < chain.size(); ++l) {
        PackedLevel& level = map.levels[l];
        if (chain[l].width != level.width || chain[l].height != level.height ||
            chain[l].channels != 4)
            throw Error("plateau", "the plateau layer's levels do not match the LEAN map's");
        level.plateau.assign(
            std::size_t(level.width) * std::size_t(level.height) * std::size_t(texel_bytes), 0);
        pack_plateau_level(chain[l], map.storage, map.scale, lean_offset(map.encoding),
                           level.plateau.data(), threads);
    }
    map.plateau_epsilon = epsilon;
}

glm::vec4 decode_plateau_texel(glm::vec4 stored, float sc, float offset) {
    if (!(stored.x > 0.0f)) return glm::vec4(0.0f);  // off every plateau: exactly 0
    const float gain = 1.0f + offset;
    return {std::min(stored.x, 1.0f), (gain * stored.y - offset) * sc,
            (gain * stored.z - offset) * sc, gain * stored.w * (sc * sc)};
}

float plateau_fraction(const PackedLeanMap& map) {
    if (!map.has_plateau() || map.levels.empty()) return 0.0f;
    const PackedLevel& coarsest = map.levels.back();
    if (coarsest.plateau.size() < std::size_t(bytes_per_texel(map.storage)))
        throw Error("plateau", "the plateau layer's levels do not match the LEAN map's");
    // The mean of f over the map: every texel of the coarsest level (1 x 1 for any chain that
    // ends there; a mean over the texels otherwise).
    double sum = 0.0;
    const std::size_t texels = std::size_t(coarsest.width) * std::size_t(coarsest.height);
    for (std::size_t i = 0; i < texels; ++i)
        sum += detail::load_channel(coarsest.plateau.data() + i * std::size_t(bytes_per_texel(map.storage)),
                                    0, map.storage);
    return float(std::clamp(sum / double(texels), 0.0, 1.0));
}

void remove_plateau_layer(PackedLeanMap& map) {
    for (PackedLevel& level : map.levels) level.plateau = {};
    map.plateau_epsilon = 0.0f;
}

std::vector<Image> unpack_plateau_layer(const PackedLeanMap& map, int threads) {
    std::vector<Image> chain;
    if (!map.has_plateau()) return chain;
    const int texel_bytes = bytes_per_texel(map.storage);
    for (const PackedLevel& level : map.levels) {
        if (level.plateau.size() !=
            std::size_t(level.width) * std::size_t(level.height) * std::size_t(texel_bytes))
            throw Error("plateau", "the plateau layer's levels do not match the LEAN map's");
        Image out(level.width, level.height, 4, 0.0f);
        parallel_for_rows(level.height, threads, [&](int first, int end) {
            for (int y = first; y < end; ++y) {
                float* row = out.row(y);
                for (int x = 0; x < level.width; ++x) {
                    const std::uint8_t* texel =
                        level.plateau.data() +
                        (std::size_t(y) * std::size_t(level.width) + std::size_t(x)) *
                            std::size_t(texel_bytes);
                    glm::vec4 stored;
                    for (int c = 0; c < 4; ++c)
                        stored[c] = detail::load_channel(texel, c, map.storage);
                    const glm::vec4 v =
                        decode_plateau_texel(stored, map.scale, lean_offset(map.encoding));
                    for (int c = 0; c < 4; ++c) row[4 * x + c] = v[c];
                }
            }
        });
        chain.push_back(std::move(out));
    }
    return chain;
}

detail::PlateauOutcome detail::pack_plateau_layer_to(const PackedLeanMap& layout, const std::uint8_t* lean2_top,
                                   const std::vector<PackedLevelTarget>& targets, float epsilon,
                                   float source_step, SpikeFit fit, int threads) {
    check_epsilon(epsilon);
    const PackedLevel& top = layout.levels.front();
    const int w = top.width, h = top.height;
    const Storage storage = layout.storage;
    const float sc = layout.scale;
    const float offset = lean_offset(layout.encoding);
    const int texel_bytes = bytes_per_texel(storage);
    const std::size_t row_bytes = std::size_t(w) * std::size_t(texel_bytes);
    auto decode = [&](int y, float* out) {
        decode_slope_row(lean2_top + std::size_t(y) * row_bytes, w, storage, sc, offset, out);
    };
    PlateauRule rule =
        plateau_rule(w, h, epsilon, std::max(source_step, storage_slope_step(storage, sc)));
    SpikeWindowFit fitted;
    if (fit == SpikeFit::Auto) {
        fitted = fit_samples(sample_slopes(w, h, rule, decode, threads));
        rule.window = fitted.window;
    }
    std::vector<Image> chain;
    if (w % 2 != 0 || h % 2 != 0) {
        // Odd sizes: the reference's chain (area filter of odd sizes from the finest level).
        chain = plateau_mips(slopes_of_lean2(lean2_top, w, h, storage, sc, offset, threads), rule,
                             threads);
        for (std::size_t l = 0; l < chain.size(); ++l)
            pack_plateau_level(chain[l], storage, sc, offset, targets[l].plateau, threads);
        return {rule, mean_fraction(chain.back()), fitted};
    }
    // Even sizes: levels 0 to `depth` made block by block (2^depth rows of the finest level,
    // from which each level's rows of the block are box-filtered, packed as they are made), with
    // no float image but level `depth`'s (at most a 256th of the finest level's floats); then the
    // reference's chain below it. Each thread keeps the slope rows its stencil reaches
    // (2 radius_y + 4 rows) and two float rows per level of the block.
    int depth = 0;
    while (depth < kMaxStreamedLevels && (w >> depth) % 2 == 0 && (h >> depth) % 2 == 0) ++depth;
    chain.emplace_back();
    Image& stored = chain.front();
    stored.width = w >> depth;
    stored.height = h >> depth;
    stored.channels = 4;
    stored.pixels.resize(stored.texel_count() * 4);
    with_storage(storage, [&](auto s) {
        constexpr Storage S = decltype(s)::value;
        constexpr std::size_t bytes = PlateauPacker<S>::kTexelBytes;
        const PlateauPacker<S> packer(sc, offset);
        parallel_for_rows(stored.height, threads, [&](int first, int end) {
            SlopeRowWindow window(w, h, 2 * rule.radius_y + 4, decode);
            std::vector<float> pairs[kMaxStreamedLevels][2];
            for (int l = 0; l < depth; ++l)
                for (auto& row : pairs[l]) row.resize(4 * std::size_t(w >> l));
            // Row y of level l into `out` (4 floats per texel) and, packed, into its target.
            const auto make_row = [&](const auto& self, int l, int y, float* out) -> void {
                const int width = w >> l;
                std::uint8_t* packed = targets[std::size_t(l)].plateau +
                                       std::size_t(y) * std::size_t(width) * bytes;
                if (l == 0) {
                    plateau_row(window.stencil(y, rule), w, rule, out, packer, packed);
                    return;
                }
                float* a = pairs[l - 1][0].data();
                float* b = pairs[l - 1][1].data();
                self(self, l - 1, 2 * y, a);
                self(self, l - 1, 2 * y + 1, b);
                for (int x = 0; x < width; ++x) {
                    box_texel(a, b, x, out + 4 * x);
                    packer.pack(out + 4 * x, packed + std::size_t(x) * bytes);
                }
            };
            for (int y = first; y < end; ++y) make_row(make_row, depth, y, stored.row(y));
        });
    });
    extend_chain(chain, threads);
    for (std::size_t l = 1; l < chain.size(); ++l)
        pack_plateau_level(chain[l], storage, sc, offset, targets[std::size_t(depth) + l].plateau,
                           threads);
    return {rule, mean_fraction(chain.back()), fitted};
}

}  // namespace leanfade
