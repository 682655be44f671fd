#pragma once
// The row kernels of the fast bake (bake_packed.cpp, docs/perf.md): the types they share, the
// reference arithmetic of one texel that every instruction set's kernels use for their tails,
// and the kernel table the bake dispatches through. One table per instruction set:
//   bake_packed_scalar.cpp  portable C++, one texel at a time;
//   bake_packed_avx2.cpp    AVX2 (x86 with GCC or Clang: target attributes, no FMA, so that no
//                           a * b + c is contracted), 8 floats or 4 doubles at a time.
// Both give the same bytes.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include <glm/gtc/packing.hpp>

#include "lean_map_internal.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade::bake_kernels {

using detail::Tap;
using TapTable = std::vector<std::vector<Tap>>;

constexpr int kMoments = 8;  // n.xyz, B.xy, M.xx, M.yy, M.xy (the order of lean_map.cpp)
enum Moment { kNx, kNy, kNz, kBx, kBy, kMxx, kMyy, kMxy };

// The eight moment planes of one row: moment c of texel x at p[c * stride + x].
struct Planes {
    float* p = nullptr;
    std::size_t stride = 0;
    float* operator[](int c) const { return p + std::size_t(c) * stride; }
};

// sc, sc^2 (float storages) and the factors of the UNORM packing (detail::unorm_packing).
struct PackScale {
    float sc = 1.0f;
    float sc2 = 1.0f;
    detail::UnormPacking unorm;
    // Float storages: s = gain v + offset for n, B, Mxy (LeanEncoding: 0.5, 0.5 or 1, 0).
    float gain = 0.5f;
    float offset = 0.5f;
};

// Where one row of one level is packed.
struct RowDest {
    std::uint8_t* lean1;
    std::uint8_t* lean2;
};

// float(sample) / max of `count` samples, as UnormImage::to_float (and the PNG reader) compute it.
using UnormToFloatFn = void (*)(const std::uint16_t* samples, std::size_t count, float max,
                                float* out);

// The top level's source: an encoded normal map (3 or 4 channels) or slopes (2 channels), as
// floats or as integer samples (UnormImage) converted to floats row by row as they are read.
struct TopInput {
    const float* pixels = nullptr;         // float input, or
    const std::uint16_t* unorm = nullptr;  // integer samples, value = sample / unorm_max
    float unorm_max = 0.0f;
    UnormToFloatFn unorm_to_float = nullptr;  // the conversion kernel
    std::uint64_t bake_id = 0;  // tells this bake's converted rows from an earlier bake's
    int width = 0;
    int channels = 0;
    float green_sign = 1.0f;
    float inv_s = 0.0f;  // 1/s baked into M.xx, M.yy (LEAN eq. 6), else 0
    std::size_t row_values() const { return std::size_t(width) * std::size_t(channels); }
    const float* row(int y) const {
        if (unorm != nullptr) return converted_row(y);
        return pixels + std::size_t(y) * row_values();
    }
    const float* converted_row(int y) const;  // bake_packed.cpp
};

// Summary statistics of one top row, taken in pass 0: |B| of texel x accumulated in lane x % 8
// by the AVX2 and the scalar kernels alike, so that both give the same sums.
struct RowStats {
    double lanes[8] = {};
    float max = 0.0f;
    void add(int x, float length) {
        lanes[x & 7] += double(length);
        max = std::max(max, length);
    }
    double total() const {
        return ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) +
               ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
    }
};

// Pass 0 on one row: validation (as slopes_from_normals), the clamped count, max |B| and the
// summary statistics. max M and the steepness check follow from max |B| (bake_packed.cpp,
// scan_input).
struct RowScan {
    float max_b = 0.0f;      // max |Bx|, |By|
    bool nan_slope = false;  // a NaN slope (max drops NaN): finite components near the float
                             // maximum overflow 2 n - 1 to infinity, and inf / inf is NaN
    std::uint32_t clamped = 0;
    int bad_x = -1;  // first NaN / Inf normal or normal with z <= -epsilon
    RowStats stats;  // summary: |B| = sqrt(Bx Bx + By By) in float
    detail::SlopeHistogram* histogram = nullptr;  // the worker's: max(|Bx|, |By|), for sc
};

// ---- The reference arithmetic of one texel --------------------------------------------------

// B = n.xy / n.z of an encoded normal 0.5 n + 0.5 (docs/math.md §2), as slopes_from_normals.
inline void normal_slope(const float* t, float green_sign, float& bx, float& by) {
    const float nx = 2.0f * t[0] - 1.0f;
    const float ny = green_sign * (2.0f * t[1] - 1.0f);
    const float nz = std::max(2.0f * t[2] - 1.0f, kMinNormalZ);
    bx = nx / nz;
    by = ny / nz;
}

template <int Channels>
inline void input_slope(const TopInput& in, const float* row, int x, float& bx, float& by) {
    const float* t = row + std::size_t(x) * Channels;
    if constexpr (Channels == 2) {
        bx = t[0];
        by = t[1];
    } else {
        normal_slope(t, in.green_sign, bx, by);
    }
}

// Top-level moments (docs/math.md §2), as build_lean_map: n = normalize(B, 1), B,
// M = (Bx^2, By^2, Bx By) plus 1/s on the diagonal.
inline void texel_moments(float bx, float by, float inv_s, float* m) {
    const float inv_len = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
    m[kNx] = bx * inv_len;
    m[kNy] = by * inv_len;
    m[kNz] = inv_len;
    m[kBx] = bx;
    m[kBy] = by;
    m[kMxx] = bx * bx + inv_s;
    m[kMyy] = by * by + inv_s;
    m[kMxy] = bx * by;
}

// One top-level texel: moments into the planes (indexed from x0).
template <int Channels>
inline void top_texel(const TopInput& in, const float* row, int x, int x0, Planes out) {
    float bx, by, m[kMoments];
    input_slope<Channels>(in, row, x, bx, by);
    texel_moments(bx, by, in.inv_s, m);
    for (int c = 0; c < kMoments; ++c) out[c][x - x0] = m[c];
}

template <Storage S>
constexpr int kTexelBytes = S == Storage::Unorm8    ? 4
                            : S == Storage::Float32 ? 16
                                                    : 8;

// One RGBA texel of one slice of float storage, little-endian, as pack_lean_map's
// store_float_channel.
template <Storage S>
inline void store_texel(std::uint8_t* t, const float* v) {
    static_assert(S == Storage::Float16 || S == Storage::Float32);
    for (int c = 0; c < 4; ++c) {
        if constexpr (S == Storage::Float16) {
            const std::uint16_t q = glm::packHalf1x16(v[c]);
            t[2 * c] = std::uint8_t(q & 0xFF);
            t[2 * c + 1] = std::uint8_t(q >> 8);
        } else {
            std::memcpy(t + 4 * c, &v[c], 4);
        }
    }
}

// ---- The kernel table -------------------------------------------------------------------------

// Top-level texels [x0, x1) of row y: moments into the planes (indexed from x0).
using TopFn = void (*)(const TopInput& in, int y, int x0, int x1, Planes out);
// Texels [x0, x1) of one row's planes packed to d.
using PackFn = void (*)(Planes p, int x0, int x1, const RowDest& d, const PackScale& s);
// Pass 0 on top row y; false at a bad texel (r.bad_x).
using ScanFn = bool (*)(const TopInput& in, int y, RowScan& r);
// out[x] = detail::box4(a[2x], a[2x + 1], c[2x], c[2x + 1]) for x in [x0, x1).
using ReduceBoxFn = void (*)(const float* a, const float* c, float* out, int x0, int x1);
// The vertical pass of the general filter, the reference's: out[x] = sum over taps k of
// w[k] * src[k][x], from 0, for x in [x0, x1).
using VerticalFn = void (*)(const float* const* src, const double* w, int taps, int x0, int x1,
                            double* out);
// The horizontal pass from `sw` to `dw` columns, outputs [x0, dw).
using HorizontalFn = void (*)(const double* row, int sw, int dw, const TapTable& xtaps, int x0,
                              float* out);

struct Kernels {
    TopFn top_range = nullptr;    // for the input's channels
    PackFn pack_range = nullptr;  // for the storage
    ScanFn scan_row = nullptr;    // for the input's channels
    ReduceBoxFn reduce_box = nullptr;
    VerticalFn vertical = nullptr;
    HorizontalFn horizontal = nullptr;
    UnormToFloatFn unorm_to_float = nullptr;
};

// f(std::integral_constant<int, C>{}) for C = 2 (slopes), 3 or 4 (encoded normals).
template <typename F>
auto with_channels(int channels, F&& f) {
    if (channels == 2) return f(std::integral_constant<int, 2>{});
    if (channels == 3) return f(std::integral_constant<int, 3>{});
    return f(std::integral_constant<int, 4>{});
}

// f(std::integral_constant<Storage, S>{}) for the storage S.
template <typename F>
auto with_storage(Storage storage, F&& f) {
    switch (storage) {
        case Storage::Unorm8:
            return f(std::integral_constant<Storage, Storage::Unorm8>{});
        case Storage::Unorm16:
            return f(std::integral_constant<Storage, Storage::Unorm16>{});
        case Storage::Float16:
            return f(std::integral_constant<Storage, Storage::Float16>{});
        case Storage::Float32:
            return f(std::integral_constant<Storage, Storage::Float32>{});
    }
    throw std::invalid_argument("bake_packed: unknown storage");
}

namespace scalar {
// The portable kernels for `channels` of the top input and `storage`.
Kernels kernels(int channels, Storage storage);
// The ones other kernels finish their rows with.
template <Storage S>
void pack_range(Planes p, int x0, int x1, const RowDest& d, const PackScale& s);
template <int Channels>
bool scan_range(const TopInput& in, int y, int x0, RowScan& r);  // texels [x0, width)
void reduce_box(const float* a, const float* c, float* out, int x0, int x1);
void vertical(const float* const* src, const double* w, int taps, int x0, int x1, double* out);
void horizontal(const double* row, int sw, int dw, const TapTable& xtaps, int x0, float* out);
void unorm_to_float(const std::uint16_t* samples, std::size_t count, float max, float* out);
}  // namespace scalar

namespace avx2 {
// Whether the AVX2 kernels are compiled in and this CPU runs them (checked once, at run time).
bool supported();
// The AVX2 kernels; only where supported().
Kernels kernels(int channels, Storage storage);
}  // namespace avx2

// The AVX2 kernels when `avx2` (only where avx2::supported()), else the portable ones.
inline Kernels select_kernels(int channels, Storage storage, bool avx2) {
    return avx2 ? avx2::kernels(channels, storage) : scalar::kernels(channels, storage);
}

}  // namespace leanfade::bake_kernels
