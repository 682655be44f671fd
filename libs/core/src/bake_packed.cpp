// Fast bake (docs/math.md §2-3): slopes -> top-level moments -> packing -> MIP chain, fused row by
// row, without the float MIP chain in memory. Every value is computed with the same float / double
// operations, in the same order, as the reference path (slopes.cpp, build_lean_map, pack_lean_map),
// so the packed bytes are identical; docs/perf.md has the design and the measurements.
//
//   pass 0  validate the input, find max |B| and max M (sc, docs/math.md §3, must be known
//           before the first texel can be packed) and take the summary's statistics of |B|;
//   pass 1  the rows of a "store level" S (64 rows for 4096^2), each to whichever thread is free.
//           A row is made by making the (2 or 3) rows of the level above that it filters,
//           recursively up to the top level, which is computed from the input in cache-sized
//           chunks (moments into L1-resident planes, then packed from them) and box-filtered
//           into level 1. Each level keeps
//           only its last 3 rows. A row is packed by the thread that makes it for its first
//           consumer, so exactly once, whatever the number of threads;
//   pass 2  the levels below S, serially, from the stored float rows of level S.
//
// Kernels: AVX2 (runtime-detected, GCC/Clang target attribute, no FMA so that no a * b + c is
// contracted) and portable C++; both give the same bytes.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include <glm/gtc/packing.hpp>

#include "lean_map_internal.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/memory.hpp"
#include "leanfade/core/parallel.hpp"

#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#define LEANFADE_AVX2_KERNELS 1
#include <immintrin.h>
#define LF_AVX2 __attribute__((target("avx2")))
#define LF_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
#define LF_AVX2_LAMBDA __attribute__((target("avx2"), always_inline))
#else
#define LEANFADE_AVX2_KERNELS 0
#endif

namespace leanfade {
namespace {

using detail::Tap;
using TapTable = std::vector<std::vector<Tap>>;

constexpr int kMoments = 8;  // n.xyz, B.xy, M.xx, M.yy, M.xy (the order of lean_map.cpp)
enum Moment { kNx, kNy, kNz, kBx, kBy, kMxx, kMyy, kMxy };
constexpr int kChunk = 256;        // top-level texels per chunk of the fused pass (fits L1)
constexpr int kMaxStoreLevel = 6;  // pass 1 ends at most here (64 rows of a 4096^2 map)
constexpr int kMinStoreRows = 16;  // ... and at a level with at least this many rows
constexpr int kScanGrain = 16;     // top rows per chunk of pass 0

std::atomic<bool> g_simd_enabled{true};

bool cpu_has_avx2() {
#if LEANFADE_AVX2_KERNELS
    static const bool has = __builtin_cpu_supports("avx2") != 0;
    return has;
#else
    return false;
#endif
}

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
};

// Where one row of one level is packed.
struct RowDest {
    std::uint8_t* lean1;
    std::uint8_t* lean2;
};

// The top level's source: an encoded normal map (3 or 4 channels) or slopes (2 channels), as
// floats or as integer samples (UnormImage) converted to floats row by row as they are read.
struct TopInput {
    const float* pixels = nullptr;         // float input, or
    const std::uint16_t* unorm = nullptr;  // integer samples, value = sample / unorm_max
    float unorm_max = 0.0f;
    bool avx2 = false;           // conversion kernels
    std::uint64_t bake_id = 0;   // tells this bake's converted rows from an earlier bake's
    int width = 0;
    int channels = 0;
    float green_sign = 1.0f;
    float inv_s = 0.0f;  // 1/s baked into M.xx, M.yy (LEAN eq. 6), else 0
    std::size_t row_values() const { return std::size_t(width) * std::size_t(channels); }
    const float* row(int y) const {
        if (unorm != nullptr) return converted_row(y);
        return pixels + std::size_t(y) * row_values();
    }
    const float* converted_row(int y) const;  // below the conversion kernels
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

// ---- Scalar kernels: the reference arithmetic, one texel at a time -------------------------

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

// lean1 = (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5), lean2 = (0.5 B / sc + 0.5, Mxx / sc^2,
// Myy / sc^2) (docs/math.md §3), as pack_lean_map.
inline void lean_texel(const float* m, const PackScale& s, float* l1, float* l2) {
    l1[0] = 0.5f * m[kNx] + 0.5f;
    l1[1] = 0.5f * m[kNy] + 0.5f;
    l1[2] = 0.5f * m[kNz] + 0.5f;
    l1[3] = 0.5f * m[kMxy] / s.sc2 + 0.5f;
    l2[0] = 0.5f * m[kBx] / s.sc + 0.5f;
    l2[1] = 0.5f * m[kBy] / s.sc + 0.5f;
    l2[2] = m[kMxx] / s.sc2;
    l2[3] = m[kMyy] / s.sc2;
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

template <Storage S>
inline void pack_texel(const float* m, const PackScale& s, const RowDest& d, int x) {
    if constexpr (S == Storage::Unorm8 || S == Storage::Unorm16) {
        std::uint16_t q1[4], q2[4];
        detail::unorm_texel(s.unorm, {m[kNx], m[kNy], m[kNz]}, {m[kBx], m[kBy]},
                            {m[kMxx], m[kMyy], m[kMxy]}, q1, q2);
        detail::store_unorm_texel(d.lean1 + std::size_t(x) * kTexelBytes<S>, q1, S);
        detail::store_unorm_texel(d.lean2 + std::size_t(x) * kTexelBytes<S>, q2, S);
    } else {
        float l1[4], l2[4];
        lean_texel(m, s, l1, l2);
        store_texel<S>(d.lean1 + std::size_t(x) * kTexelBytes<S>, l1);
        store_texel<S>(d.lean2 + std::size_t(x) * kTexelBytes<S>, l2);
    }
}

// One top-level texel: moments into the planes (indexed from x0).
template <int Channels>
inline void top_texel(const TopInput& in, const float* row, int x, int x0, Planes out) {
    float bx, by, m[kMoments];
    input_slope<Channels>(in, row, x, bx, by);
    texel_moments(bx, by, in.inv_s, m);
    for (int c = 0; c < kMoments; ++c) out[c][x - x0] = m[c];
}

template <int Channels>
void top_range_scalar(const TopInput& in, int y, int x0, int x1, Planes out) {
    const float* row = in.row(y);
    for (int x = x0; x < x1; ++x) top_texel<Channels>(in, row, x, x0, out);
}

template <Storage S>
void pack_range_scalar(Planes p, int x0, int x1, const RowDest& d, const PackScale& s) {
    for (int x = x0; x < x1; ++x) {
        float m[kMoments];
        for (int c = 0; c < kMoments; ++c) m[c] = p[c][x];
        pack_texel<S>(m, s, d, x);
    }
}

// The 2x2 box of even sizes: detail::box4, in float.
using detail::box4;

void reduce_box_scalar(const float* a, const float* c, float* out, int x0, int x1) {
    for (int x = x0; x < x1; ++x) out[x] = box4(a[2 * x], a[2 * x + 1], c[2 * x], c[2 * x + 1]);
}

// General vertical pass, literally the reference's: sum over taps of weight * source, from 0.
void vertical_scalar(const float* const* src, const double* w, int taps, int x0, int x1,
                     double* out) {
    for (int x = x0; x < x1; ++x) {
        double acc = 0.0;
        for (int k = 0; k < taps; ++k) acc += w[k] * double(src[k][x]);
        out[x] = acc;
    }
}

// Horizontal pass. Pairs (sw = 2 dw, both weights exactly 0.5): (h0 + h1) + 0.0 equals the
// reference's (0.0 + h0) + h1 (they differ only in the sign of a zero sum). Otherwise literal.
void horizontal_scalar(const double* row, int sw, int dw, const TapTable& xtaps, int x0,
                       float* out) {
    if (sw == 2 * dw) {
        for (int x = x0; x < dw; ++x)
            out[x] = float((0.5 * row[2 * x] + 0.5 * row[2 * x + 1]) + 0.0);
        return;
    }
    for (int x = x0; x < dw; ++x) {
        double acc = 0.0;
        for (const Tap& t : xtaps[std::size_t(x)]) acc += t.weight * row[t.index];
        out[x] = float(acc);
    }
}

// Pass 0 on one row: validation (as slopes_from_normals), the clamped count, max |B| and the
// summary statistics. max M and the steepness check follow from max |B| (see scan_input).
struct RowScan {
    float max_b = 0.0f;      // max |Bx|, |By|
    bool nan_slope = false;  // a NaN slope (max drops NaN): finite components near the float
                             // maximum overflow 2 n - 1 to infinity, and inf / inf is NaN
    std::uint32_t clamped = 0;
    int bad_x = -1;  // first NaN / Inf normal or normal with z <= -epsilon
    RowStats stats;  // summary: |B| = sqrt(Bx Bx + By By) in float
    detail::SlopeHistogram* histogram = nullptr;  // the worker's: max(|Bx|, |By|), for sc
};

// Returns false at a bad texel (scanning stops there: the reference throws at the first).
template <int Channels>
bool scan_texel(const TopInput& in, const float* row, int x, RowScan& r) {
    if constexpr (Channels > 2) {
        const float* t = row + std::size_t(x) * Channels;
        if (!std::isfinite(t[0]) || !std::isfinite(t[1]) || !std::isfinite(t[2]) ||
            2.0f * t[2] - 1.0f <= -kNormalZRejectEpsilon) {
            r.bad_x = x;
            return false;
        }
        if (2.0f * t[2] - 1.0f < kMinNormalZ) ++r.clamped;
    }
    float bx, by;
    input_slope<Channels>(in, row, x, bx, by);
    r.max_b = std::max({r.max_b, std::abs(bx), std::abs(by)});
    r.histogram->add(std::max(std::abs(bx), std::abs(by)));
    r.nan_slope = r.nan_slope || std::isnan(bx) || std::isnan(by);
    r.stats.add(x, std::sqrt(bx * bx + by * by));
    return true;
}

template <int Channels>
bool scan_range_scalar(const TopInput& in, int y, int x0, RowScan& r) {
    const float* row = in.row(y);
    for (int x = x0; x < in.width; ++x)
        if (!scan_texel<Channels>(in, row, x, r)) return false;
    return true;
}

template <int Channels>
bool scan_row_scalar(const TopInput& in, int y, RowScan& r) {
    return scan_range_scalar<Channels>(in, y, 0, r);
}

// ---- AVX2 kernels: the same operations on 8 texels (or 4 doubles) at a time ----------------
#if LEANFADE_AVX2_KERNELS

// r, g, b of 8 texels of 3 interleaved floats.
LF_AVX2_INLINE void load_rgb8(const float* p, __m256& r, __m256& g, __m256& b) {
    const __m256 v0 = _mm256_loadu_ps(p), v1 = _mm256_loadu_ps(p + 8), v2 = _mm256_loadu_ps(p + 16);
    r = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(v0, v1, 0x92), v2, 0x24),
                                 _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    g = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(v0, v1, 0x24), v2, 0x49),
                                 _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    b = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(v0, v1, 0x49), v2, 0x92),
                                 _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}

// r, g, b of 8 texels of 4 interleaved floats (alpha unused).
LF_AVX2_INLINE void load_rgba8(const float* p, __m256& r, __m256& g, __m256& b) {
    const __m256 v0 = _mm256_loadu_ps(p), v1 = _mm256_loadu_ps(p + 8);
    const __m256 v2 = _mm256_loadu_ps(p + 16), v3 = _mm256_loadu_ps(p + 24);
    const __m256 t0 = _mm256_unpacklo_ps(v0, v1), t1 = _mm256_unpackhi_ps(v0, v1);
    const __m256 t2 = _mm256_unpacklo_ps(v2, v3), t3 = _mm256_unpackhi_ps(v2, v3);
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    r = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t0, t2, 0x44), order);
    g = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t0, t2, 0xEE), order);
    b = _mm256_permutevar8x32_ps(_mm256_shuffle_ps(t1, t3, 0x44), order);
}

// x, y of 8 texels of 2 interleaved floats.
LF_AVX2_INLINE void load_xy8(const float* p, __m256& x, __m256& y) {
    const __m256 v0 = _mm256_loadu_ps(p), v1 = _mm256_loadu_ps(p + 8);
    x = _mm256_castpd_ps(
        _mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0x88)), 0xD8));
    y = _mm256_castpd_ps(
        _mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(v0, v1, 0xDD)), 0xD8));
}

LF_AVX2_INLINE void normal_slope8(__m256 r, __m256 g, __m256 b, float green_sign, __m256& bx,
                                  __m256& by) {
    const __m256 two = _mm256_set1_ps(2.0f), one = _mm256_set1_ps(1.0f);
    const __m256 nx = _mm256_sub_ps(_mm256_mul_ps(two, r), one);
    const __m256 ny =
        _mm256_mul_ps(_mm256_set1_ps(green_sign), _mm256_sub_ps(_mm256_mul_ps(two, g), one));
    const __m256 nz =
        _mm256_max_ps(_mm256_sub_ps(_mm256_mul_ps(two, b), one), _mm256_set1_ps(kMinNormalZ));
    bx = _mm256_div_ps(nx, nz);
    by = _mm256_div_ps(ny, nz);
}

template <int Channels>
LF_AVX2_INLINE void input_slope8(const TopInput& in, const float* row, int x, __m256& bx,
                                 __m256& by) {
    const float* p = row + std::size_t(x) * Channels;
    if constexpr (Channels == 2) {
        load_xy8(p, bx, by);
    } else {
        __m256 r, g, b;
        if constexpr (Channels == 3)
            load_rgb8(p, r, g, b);
        else
            load_rgba8(p, r, g, b);
        normal_slope8(r, g, b, in.green_sign, bx, by);
    }
}

LF_AVX2_INLINE void moments8(__m256 bx, __m256 by, float inv_s, __m256* m) {
    const __m256 one = _mm256_set1_ps(1.0f), s = _mm256_set1_ps(inv_s);
    const __m256 xx = _mm256_mul_ps(bx, bx), yy = _mm256_mul_ps(by, by);
    const __m256 len2 = _mm256_add_ps(xx, yy);
    const __m256 inv_len = _mm256_div_ps(one, _mm256_sqrt_ps(_mm256_add_ps(len2, one)));
    m[kNx] = _mm256_mul_ps(bx, inv_len);
    m[kNy] = _mm256_mul_ps(by, inv_len);
    m[kNz] = inv_len;
    m[kBx] = bx;
    m[kBy] = by;
    m[kMxx] = _mm256_add_ps(xx, s);
    m[kMyy] = _mm256_add_ps(yy, s);
    m[kMxy] = _mm256_mul_ps(bx, by);
}

// detail::unorm_code before its clamp: v * factor (+ offset) rounded to the nearest int32, ties
// to even (the default rounding mode, as std::nearbyint). The saturating packs of store_codes8
// then clamp to [0, Q]; a NaN converts to INT_MIN and saturates to 0, as unorm_code's 0. The
// values are far inside the int32 range (detail::UnormPacking), so nothing else is needed.
LF_AVX2_INLINE __m256i code8(__m256 v, __m256 factor, __m256 offset) {
    return _mm256_cvtps_epi32(_mm256_add_ps(_mm256_mul_ps(v, factor), offset));
}
LF_AVX2_INLINE __m256i code8(__m256 v, __m256 factor) {
    return _mm256_cvtps_epi32(_mm256_mul_ps(v, factor));
}

LF_AVX2_INLINE void store32(std::uint8_t* d, __m256i v) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(d), v);
}

// One UNORM slice (the int32 codes of channels r, g, b, a) of 8 texels, little-endian RGBA.
template <Storage S>
LF_AVX2_INLINE void store_codes8(__m256i r, __m256i g, __m256i b, __m256i a, std::uint8_t* d) {
    if constexpr (S == Storage::Unorm8) {
        // Codes above 32767 (texels beyond sc, choose_lean_scale) would turn negative in the
        // signed 16-bit pack below: clamped to 255 first.
        const __m256i max_code = _mm256_set1_epi32(255);
        r = _mm256_min_epi32(r, max_code);
        g = _mm256_min_epi32(g, max_code);
        b = _mm256_min_epi32(b, max_code);
        a = _mm256_min_epi32(a, max_code);
    }
    // Saturating packs: [R0-3 B0-3 | R4-7 B4-7] and [G0-3 A0-3 | G4-7 A4-7] as uint16.
    const __m256i rb = _mm256_packus_epi32(r, b), ga = _mm256_packus_epi32(g, a);
    if constexpr (S == Storage::Unorm16) {
        // Interleaved to R G B A per texel.
        const __m256i rg = _mm256_unpacklo_epi16(rb, ga), ba = _mm256_unpackhi_epi16(rb, ga);
        const __m256i lo = _mm256_unpacklo_epi32(rg, ba), hi = _mm256_unpackhi_epi32(rg, ba);
        store32(d, _mm256_permute2x128_si256(lo, hi, 0x20));
        store32(d + 32, _mm256_permute2x128_si256(lo, hi, 0x31));
    } else {
        static_assert(S == Storage::Unorm8);
        // Saturating pack to [R0-3 B0-3 G0-3 A0-3 | R4-7 B4-7 G4-7 A4-7] bytes, then a byte
        // shuffle to R G B A per texel within each half.
        const __m256i bytes = _mm256_packus_epi16(rb, ga);
        const __m256i order =
            _mm256_setr_epi8(0, 8, 4, 12, 1, 9, 5, 13, 2, 10, 6, 14, 3, 11, 7, 15, 0, 8, 4, 12, 1,
                             9, 5, 13, 2, 10, 6, 14, 3, 11, 7, 15);
        store32(d, _mm256_shuffle_epi8(bytes, order));
    }
}

// One float slice (4 channel vectors) of 8 texels, little-endian RGBA.
template <Storage S>
LF_AVX2_INLINE void store_slice8(const __m256* l, std::uint8_t* d) {
    if constexpr (S == Storage::Float32) {
        const __m256 t0 = _mm256_unpacklo_ps(l[0], l[1]), t1 = _mm256_unpackhi_ps(l[0], l[1]);
        const __m256 t2 = _mm256_unpacklo_ps(l[2], l[3]), t3 = _mm256_unpackhi_ps(l[2], l[3]);
        const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xEE);
        const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xEE);
        store32(d, _mm256_castps_si256(_mm256_permute2f128_ps(u0, u1, 0x20)));
        store32(d + 32, _mm256_castps_si256(_mm256_permute2f128_ps(u2, u3, 0x20)));
        store32(d + 64, _mm256_castps_si256(_mm256_permute2f128_ps(u0, u1, 0x31)));
        store32(d + 96, _mm256_castps_si256(_mm256_permute2f128_ps(u2, u3, 0x31)));
    } else {  // Float16: glm's conversion, value by value
        static_assert(S == Storage::Float16);
        alignas(32) float v[4][8];
        for (int c = 0; c < 4; ++c) _mm256_store_ps(v[c], l[c]);
        for (int i = 0; i < 8; ++i) {
            const float texel[4] = {v[0][i], v[1][i], v[2][i], v[3][i]};
            store_texel<S>(d + 8 * i, texel);
        }
    }
}

// lean1, lean2 of 8 texels (docs/math.md §3): UNORM storages as detail::unorm_texel, float storages
// as lean_texel.
template <Storage S>
LF_AVX2_INLINE void pack8(const __m256* m, const PackScale& s, const RowDest& d, int x) {
    std::uint8_t* lean1 = d.lean1 + std::size_t(x) * kTexelBytes<S>;
    std::uint8_t* lean2 = d.lean2 + std::size_t(x) * kTexelBytes<S>;
    if constexpr (S == Storage::Unorm8 || S == Storage::Unorm16) {
        const __m256 half = _mm256_set1_ps(s.unorm.half);
        const __m256 b_factor = _mm256_set1_ps(s.unorm.b_factor);
        const __m256 mxy_factor = _mm256_set1_ps(s.unorm.mxy_factor);
        const __m256 m_factor = _mm256_set1_ps(s.unorm.m_factor);
        store_codes8<S>(code8(m[kNx], half, half), code8(m[kNy], half, half),
                        code8(m[kNz], half, half), code8(m[kMxy], mxy_factor, half), lean1);
        store_codes8<S>(code8(m[kBx], b_factor, half), code8(m[kBy], b_factor, half),
                        code8(m[kMxx], m_factor), code8(m[kMyy], m_factor), lean2);
    } else {
        const __m256 half = _mm256_set1_ps(0.5f);
        const __m256 sc = _mm256_set1_ps(s.sc), sc2 = _mm256_set1_ps(s.sc2);
        __m256 l1[4], l2[4];
        l1[0] = _mm256_add_ps(_mm256_mul_ps(half, m[kNx]), half);
        l1[1] = _mm256_add_ps(_mm256_mul_ps(half, m[kNy]), half);
        l1[2] = _mm256_add_ps(_mm256_mul_ps(half, m[kNz]), half);
        l1[3] = _mm256_add_ps(_mm256_div_ps(_mm256_mul_ps(half, m[kMxy]), sc2), half);
        l2[0] = _mm256_add_ps(_mm256_div_ps(_mm256_mul_ps(half, m[kBx]), sc), half);
        l2[1] = _mm256_add_ps(_mm256_div_ps(_mm256_mul_ps(half, m[kBy]), sc), half);
        l2[2] = _mm256_div_ps(m[kMxx], sc2);
        l2[3] = _mm256_div_ps(m[kMyy], sc2);
        store_slice8<S>(l1, lean1);
        store_slice8<S>(l2, lean2);
    }
}

// Top-level texels [x0, x1) of row y: moments into the planes (indexed from x0). They are
// packed from the planes afterwards (pack_range): two short dependency chains overlap better
// than one long one (docs/perf.md).
template <int Channels>
LF_AVX2 void top_range_avx2(const TopInput& in, int y, int x0, int x1, Planes out) {
    const float* row = in.row(y);
    int x = x0;
    for (; x + 8 <= x1; x += 8) {
        __m256 bx, by, m[kMoments];
        input_slope8<Channels>(in, row, x, bx, by);
        moments8(bx, by, in.inv_s, m);
        for (int c = 0; c < kMoments; ++c) _mm256_storeu_ps(out[c] + (x - x0), m[c]);
    }
    for (; x < x1; ++x) top_texel<Channels>(in, row, x, x0, out);
}

template <Storage S>
LF_AVX2 void pack_range_avx2(Planes p, int x0, int x1, const RowDest& d, const PackScale& s) {
    int x = x0;
    for (; x + 8 <= x1; x += 8) {
        __m256 m[kMoments];
        for (int c = 0; c < kMoments; ++c) m[c] = _mm256_loadu_ps(p[c] + x);
        pack8<S>(m, s, d, x);
    }
    pack_range_scalar<S>(p, x, x1, d, s);
}

// Four floats (the low or high half of v) as doubles.
LF_AVX2_INLINE __m256d low_pd(__m256 v) {
    return _mm256_cvtps_pd(_mm256_castps256_ps128(v));
}
LF_AVX2_INLINE __m256d high_pd(__m256 v) {
    return _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1));
}

// box4 on 8 outputs per step: the vertical sums a + c of 16 columns, then hadd pairs them:
// ((a0 + c0) + (a1 + c1)), box4's order. hadd works within 128-bit lanes, so the outputs come
// out as 0 1 4 5 | 2 3 6 7 and are put in order by one 64-bit permute.
LF_AVX2 void reduce_box_avx2(const float* a, const float* c, float* out, int x0, int x1) {
    const __m256 quarter = _mm256_set1_ps(0.25f), zero = _mm256_setzero_ps();
    int x = x0;
    for (; x + 8 <= x1; x += 8) {
        const int i = 2 * x;
        const __m256 s0 = _mm256_add_ps(_mm256_loadu_ps(a + i), _mm256_loadu_ps(c + i));
        const __m256 s1 = _mm256_add_ps(_mm256_loadu_ps(a + i + 8), _mm256_loadu_ps(c + i + 8));
        const __m256d pairs = _mm256_castps_pd(_mm256_hadd_ps(s0, s1));
        const __m256 sums = _mm256_castpd_ps(_mm256_permute4x64_pd(pairs, 0xD8));
        _mm256_storeu_ps(out + x, _mm256_add_ps(_mm256_mul_ps(sums, quarter), zero));
    }
    reduce_box_scalar(a, c, out, x, x1);
}

LF_AVX2 void vertical_avx2(const float* const* src, const double* w, int taps, int x0, int x1,
                           double* out) {
    int x = x0;
    for (; x + 4 <= x1; x += 4) {
        __m256d acc = _mm256_setzero_pd();
        for (int k = 0; k < taps; ++k)
            acc = _mm256_add_pd(acc, _mm256_mul_pd(_mm256_set1_pd(w[k]),
                                                   _mm256_cvtps_pd(_mm_loadu_ps(src[k] + x))));
        _mm256_storeu_pd(out + x, acc);
    }
    vertical_scalar(src, w, taps, x, x1, out);
}

LF_AVX2 void horizontal_avx2(const double* row, int sw, int dw, const TapTable& xtaps, float* out) {
    int x = 0;
    if (sw == 2 * dw) {
        const __m256d half = _mm256_set1_pd(0.5), zero = _mm256_setzero_pd();
        for (; x + 4 <= dw; x += 4) {
            const __m256d lo = _mm256_mul_pd(half, _mm256_loadu_pd(row + 2 * x));
            const __m256d hi = _mm256_mul_pd(half, _mm256_loadu_pd(row + 2 * x + 4));
            const __m256d sums = _mm256_permute4x64_pd(_mm256_hadd_pd(lo, hi), 0xD8);
            _mm_storeu_ps(out + x, _mm256_cvtpd_ps(_mm256_add_pd(sums, zero)));
        }
    }
    horizontal_scalar(row, sw, dw, xtaps, x, out);
}

// Pass 0 on 8-texel blocks; at a block with a bad texel the scalar scan takes over, so that
// the first one in row-major order is reported.
template <int Channels>
LF_AVX2 bool scan_row_avx2(const TopInput& in, int y, RowScan& r) {
    const float* row = in.row(y);
    const __m256 sign = _mm256_set1_ps(-0.0f);
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    __m256 max_b = _mm256_setzero_ps(), max_len = _mm256_setzero_ps();
    __m256 nan = _mm256_setzero_ps();
    __m256d sum_lo = _mm256_setzero_pd(), sum_hi = _mm256_setzero_pd();
    int x = 0;
    for (; x + 8 <= in.width; x += 8) {
        __m256 bx, by;
        if constexpr (Channels > 2) {
            __m256 cr, cg, cb;
            if constexpr (Channels == 3)
                load_rgb8(row + std::size_t(x) * 3, cr, cg, cb);
            else
                load_rgba8(row + std::size_t(x) * 4, cr, cg, cb);
            const __m256 finite = _mm256_and_ps(
                _mm256_and_ps(_mm256_cmp_ps(_mm256_andnot_ps(sign, cr), inf, _CMP_LT_OQ),
                              _mm256_cmp_ps(_mm256_andnot_ps(sign, cg), inf, _CMP_LT_OQ)),
                _mm256_cmp_ps(_mm256_andnot_ps(sign, cb), inf, _CMP_LT_OQ));
            const __m256 z =
                _mm256_sub_ps(_mm256_mul_ps(_mm256_set1_ps(2.0f), cb), _mm256_set1_ps(1.0f));
            const __m256 ok = _mm256_andnot_ps(
                _mm256_cmp_ps(z, _mm256_set1_ps(-kNormalZRejectEpsilon), _CMP_LE_OQ), finite);
            if (_mm256_movemask_ps(ok) != 0xFF) break;  // the scalar scan finds and reports it
            r.clamped += std::uint32_t(std::popcount(unsigned(
                _mm256_movemask_ps(_mm256_cmp_ps(z, _mm256_set1_ps(kMinNormalZ), _CMP_LT_OQ)))));
            normal_slope8(cr, cg, cb, in.green_sign, bx, by);
        } else {
            load_xy8(row + std::size_t(x) * 2, bx, by);
        }
        const __m256 steepest =
            _mm256_max_ps(_mm256_andnot_ps(sign, bx), _mm256_andnot_ps(sign, by));
        max_b = _mm256_max_ps(max_b, steepest);
        alignas(32) float lanes[8];
        _mm256_store_ps(lanes, steepest);
        for (const float v : lanes) r.histogram->add(v);
        nan = _mm256_or_ps(nan, _mm256_cmp_ps(bx, by, _CMP_UNORD_Q));
        const __m256 len =
            _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(bx, bx), _mm256_mul_ps(by, by)));
        sum_lo = _mm256_add_pd(sum_lo, low_pd(len));
        sum_hi = _mm256_add_pd(sum_hi, high_pd(len));
        max_len = _mm256_max_ps(max_len, len);
    }
    _mm256_storeu_pd(r.stats.lanes, sum_lo);
    _mm256_storeu_pd(r.stats.lanes + 4, sum_hi);
    alignas(32) float lanes_b[8], lanes_len[8];
    _mm256_store_ps(lanes_b, max_b);
    _mm256_store_ps(lanes_len, max_len);
    for (int i = 0; i < 8; ++i) {
        r.max_b = std::max(r.max_b, lanes_b[i]);
        r.stats.max = std::max(r.stats.max, lanes_len[i]);
    }
    r.nan_slope = r.nan_slope || _mm256_movemask_ps(nan) != 0;
    return scan_range_scalar<Channels>(in, y, x, r);
}

#endif  // LEANFADE_AVX2_KERNELS

// ---- Integer input: rows converted to float as they are read ---------------------------------

// float(sample) / max, as UnormImage::to_float (and the PNG reader) compute it.
void unorm_to_float_scalar(const std::uint16_t* samples, std::size_t count, float max,
                           float* out) {
    for (std::size_t i = 0; i < count; ++i) out[i] = float(samples[i]) / max;
}

#if LEANFADE_AVX2_KERNELS
LF_AVX2 void unorm_to_float_avx2(const std::uint16_t* samples, std::size_t count, float max,
                                 float* out) {
    const __m256 divisor = _mm256_set1_ps(max);
    std::size_t i = 0;
    for (; i + 8 <= count; i += 8) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(samples + i));
        const __m256 f = _mm256_cvtepi32_ps(_mm256_cvtepu16_epi32(v));  // exact: < 2^24
        _mm256_storeu_ps(out + i, _mm256_div_ps(f, divisor));
    }
    unorm_to_float_scalar(samples + i, count - i, max, out + i);
}
#endif

// The last two rows this thread converted (pass 1 alternates between two top rows).
struct ConvertedRows {
    std::uint64_t bake_id = 0;
    int y[2] = {-1, -1};
    int next = 0;
    std::vector<float> rows[2];
};
thread_local ConvertedRows t_converted;
std::atomic<std::uint64_t> g_next_bake_id{1};

const float* TopInput::converted_row(int y) const {
    ConvertedRows& cache = t_converted;
    if (cache.bake_id != bake_id) cache = ConvertedRows{bake_id, {-1, -1}, 0, {}};
    for (int k = 0; k < 2; ++k)
        if (cache.y[k] == y) return cache.rows[k].data();
    const int k = cache.next;
    cache.next ^= 1;
    std::vector<float>& out = cache.rows[k];
    out.resize(row_values());
    const std::uint16_t* samples = unorm + std::size_t(y) * row_values();
#if LEANFADE_AVX2_KERNELS
    if (avx2) {
        unorm_to_float_avx2(samples, row_values(), unorm_max, out.data());
        cache.y[k] = y;
        return out.data();
    }
#endif
    unorm_to_float_scalar(samples, row_values(), unorm_max, out.data());
    cache.y[k] = y;
    return out.data();
}

// ---- Kernel selection ----------------------------------------------------------------------

using TopFn = void (*)(const TopInput&, int, int, int, Planes);
using PackFn = void (*)(Planes, int, int, const RowDest&, const PackScale&);
using ScanFn = bool (*)(const TopInput&, int, RowScan&);

TopFn select_top(int channels, bool avx2) {
#if LEANFADE_AVX2_KERNELS
    if (avx2) {
        if (channels == 2) return top_range_avx2<2>;
        if (channels == 3) return top_range_avx2<3>;
        return top_range_avx2<4>;
    }
#endif
    (void)avx2;
    if (channels == 2) return top_range_scalar<2>;
    if (channels == 3) return top_range_scalar<3>;
    return top_range_scalar<4>;
}

template <Storage S>
PackFn pack_fn(bool avx2) {
#if LEANFADE_AVX2_KERNELS
    if (avx2) return pack_range_avx2<S>;
#endif
    (void)avx2;
    return pack_range_scalar<S>;
}

PackFn select_pack(Storage storage, bool avx2) {
    switch (storage) {
        case Storage::Unorm8:
            return pack_fn<Storage::Unorm8>(avx2);
        case Storage::Unorm16:
            return pack_fn<Storage::Unorm16>(avx2);
        case Storage::Float16:
            return pack_fn<Storage::Float16>(avx2);
        case Storage::Float32:
            return pack_fn<Storage::Float32>(avx2);
    }
    throw std::invalid_argument("bake_packed: unknown storage");
}

ScanFn select_scan(int channels, bool avx2) {
#if LEANFADE_AVX2_KERNELS
    if (avx2) {
        if (channels == 2) return scan_row_avx2<2>;
        if (channels == 3) return scan_row_avx2<3>;
        return scan_row_avx2<4>;
    }
#endif
    (void)avx2;
    if (channels == 2) return scan_row_scalar<2>;
    if (channels == 3) return scan_row_scalar<3>;
    return scan_row_scalar<4>;
}

void reduce_box(bool avx2, const float* a, const float* c, float* out, int dw) {
#if LEANFADE_AVX2_KERNELS
    if (avx2) return reduce_box_avx2(a, c, out, 0, dw);
#endif
    reduce_box_scalar(a, c, out, 0, dw);
}

// ---- The plan and the row pipeline ---------------------------------------------------------

struct LevelPlan {
    int width = 0;
    int height = 0;
    std::size_t stride = 0;           // floats per plane in row buffers (width rounded up to 8)
    bool box = false;                 // made from the level above by the 2x2 box (even sizes)
    TapTable ytaps, xtaps;            // from the level above (levels > 0)
    std::vector<int> first_consumer;  // per row: the first row of the next level that filters it
};

struct Plan {
    TopInput top;
    std::vector<LevelPlan> levels;
    int store_level = 0;
    PackScale scale;
    bool avx2 = false;
    TopFn top_range = nullptr;
    PackFn pack_range = nullptr;
    int texel_bytes = 0;
    std::vector<PackedLevelTarget> targets;  // where each level's rows are packed
    std::vector<float> stored;  // the planes of every row of the store level

    Planes stored_row(int y) {
        const std::size_t stride = levels[std::size_t(store_level)].stride;
        return {stored.data() + std::size_t(y) * kMoments * stride, stride};
    }
    RowDest dest(int level, int y) const {
        const LevelPlan& lp = levels[std::size_t(level)];
        const PackedLevelTarget& out = targets[std::size_t(level)];
        const std::size_t offset =
            std::size_t(y) * std::size_t(lp.width) * std::size_t(texel_bytes);
        return {out.lean1 + offset, out.lean2 + offset};
    }
};

// Makes rows of any level on demand, keeping the last 3 rows of each level.
class RowMaker {
  public:
    // from_stored: the store level's rows are read from plan.stored (pass 2); otherwise the top
    // level is computed from the input and the store level's rows are written to plan.stored.
    RowMaker(Plan& plan, bool from_stored)
        : plan_(plan),
          from_stored_(from_stored),
          rings_(plan.levels.size()),
          ring_rows_(plan.levels.size(), std::array<int, 3>{-1, -1, -1}) {}

    // Row y of `level`; packs it (and the rows it is made from that it is the first consumer
    // of) when `owned`. The planes stay valid until the next 3 rows of that level are made.
    Planes row(int level, int y, bool owned) {
        const LevelPlan& lp = plan_.levels[std::size_t(level)];
        if (level == plan_.store_level) {
            if (from_stored_) return plan_.stored_row(y);
            const Planes out = plan_.stored_row(y);
            make(level, y, owned, out);
            return out;
        }
        std::vector<float>& ring = rings_[std::size_t(level)];
        if (ring.empty()) ring.resize(3 * kMoments * lp.stride);
        const int slot = y % 3;
        const Planes out{ring.data() + std::size_t(slot) * kMoments * lp.stride, lp.stride};
        int& cached = ring_rows_[std::size_t(level)][std::size_t(slot)];
        if (cached == y) return out;
        make(level, y, owned, out);
        cached = y;
        return out;
    }

  private:
    void make(int level, int y, bool owned, Planes out) {
        const LevelPlan& lp = plan_.levels[std::size_t(level)];
        if (level == 0) {
            make_top(y, 0, lp.width, out, owned);
            return;
        }
        if (level == 1 && lp.box && !from_stored_) {
            make_first_box(y, out, owned);
            return;
        }
        const LevelPlan& up = plan_.levels[std::size_t(level - 1)];
        const auto& taps = lp.ytaps[std::size_t(y)];
        const int count = int(taps.size());
        if (count > 3) throw std::logic_error("bake_packed: more than 3 filter taps");
        Planes src[3];
        double weights[3];
        for (int k = 0; k < count; ++k) {
            const int s = taps[std::size_t(k)].index;
            src[k] = row(level - 1, s, owned && up.first_consumer[std::size_t(s)] == y);
            weights[k] = taps[std::size_t(k)].weight;
        }
        if (lp.box) {
            for (int c = 0; c < kMoments; ++c)
                reduce_box(plan_.avx2, src[0][c], src[1][c], out[c], lp.width);
        } else {
            if (vertical_.size() < std::size_t(up.width)) vertical_.resize(std::size_t(up.width));
            for (int c = 0; c < kMoments; ++c) {
                const float* rows[3] = {src[0][c], count > 1 ? src[1][c] : nullptr,
                                        count > 2 ? src[2][c] : nullptr};
                filter_channel(rows, weights, count, up.width, lp, out[c]);
            }
        }
        if (owned) {
            const RowDest d = plan_.dest(level, y);
            plan_.pack_range(out, 0, lp.width, d, plan_.scale);
        }
    }

    void filter_channel(const float* const* rows, const double* weights, int count, int sw,
                        const LevelPlan& lp, float* out) {
#if LEANFADE_AVX2_KERNELS
        if (plan_.avx2) {
            vertical_avx2(rows, weights, count, 0, sw, vertical_.data());
            horizontal_avx2(vertical_.data(), sw, lp.width, lp.xtaps, out);
            return;
        }
#endif
        vertical_scalar(rows, weights, count, 0, sw, vertical_.data());
        horizontal_scalar(vertical_.data(), sw, lp.width, lp.xtaps, 0, out);
    }

    // Top-level texels [x0, x1) of row y into planes indexed from x0.
    void make_top(int y, int x0, int x1, Planes out, bool owned) {
        plan_.top_range(plan_.top, y, x0, x1, out);
        if (owned) {
            const RowDest row = plan_.dest(0, y);
            const std::size_t offset = std::size_t(x0) * std::size_t(plan_.texel_bytes);
            plan_.pack_range(out, 0, x1 - x0, RowDest{row.lean1 + offset, row.lean2 + offset},
                             plan_.scale);
        }
    }

    // Level 1 row y from top rows 2y, 2y + 1 (even sizes), chunk by chunk so that the top
    // moments never leave L1: compute, pack, box-filter.
    void make_first_box(int y, Planes out, bool owned) {
        const int w0 = plan_.levels[0].width;
        if (chunk_.empty()) chunk_.resize(2 * kMoments * std::size_t(kChunk));
        const Planes a{chunk_.data(), kChunk}, c{chunk_.data() + kMoments * kChunk, kChunk};
        for (int x0 = 0; x0 < w0; x0 += kChunk) {
            const int x1 = std::min(w0, x0 + kChunk);
            make_top(2 * y, x0, x1, a, owned);
            make_top(2 * y + 1, x0, x1, c, owned);
            for (int m = 0; m < kMoments; ++m)
                reduce_box(plan_.avx2, a[m], c[m], out[m] + x0 / 2, (x1 - x0) / 2);
        }
        if (owned) {
            const RowDest d = plan_.dest(1, y);
            plan_.pack_range(out, 0, plan_.levels[1].width, d, plan_.scale);
        }
    }

    Plan& plan_;
    bool from_stored_;
    std::vector<std::vector<float>> rings_;
    std::vector<std::array<int, 3>> ring_rows_;
    std::vector<float> chunk_;
    std::vector<double> vertical_;
};

std::vector<LevelPlan> plan_levels(int width, int height) {
    const int count = mip_level_count(width, height);
    std::vector<LevelPlan> levels(static_cast<std::size_t>(count));
    for (int l = 0; l < count; ++l) {
        LevelPlan& lp = levels[std::size_t(l)];
        lp.width = width;
        lp.height = height;
        lp.stride = (std::size_t(width) + 7) / 8 * 8;
        if (l > 0) {
            const LevelPlan& up = levels[std::size_t(l - 1)];
            lp.box = up.width == 2 * width && up.height == 2 * height;
            lp.ytaps = detail::reduction_taps(up.height, height);
            lp.xtaps = detail::reduction_taps(up.width, width);
        }
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
    }
    for (int l = 0; l + 1 < count; ++l) {
        LevelPlan& lp = levels[std::size_t(l)];
        lp.first_consumer.assign(std::size_t(lp.height), -1);
        const TapTable& taps = levels[std::size_t(l + 1)].ytaps;
        for (std::size_t r = 0; r < taps.size(); ++r)
            for (const Tap& t : taps[r])
                if (lp.first_consumer[std::size_t(t.index)] < 0)
                    lp.first_consumer[std::size_t(t.index)] = int(r);
    }
    return levels;
}

int choose_store_level(const std::vector<LevelPlan>& levels) {
    int store = 0;
    for (int l = 1; l < int(levels.size()) && l <= kMaxStoreLevel; ++l)
        if (levels[std::size_t(l)].height >= kMinStoreRows) store = l;
    return store;
}

// Pass 0: validation as slopes_from_normals (first bad texel in row-major order; every NaN and
// z check before any slope check), the clamped count and the maxima for sc.
struct ScanTotals {
    double max_b = 0.0, max_m = 0.0;
    std::size_t clamped = 0;
    double sum_slope = 0.0;  // sum of |B|, row by row in order
    float max_slope = 0.0f;  // max |B|
    detail::SlopeHistogram histogram;  // of max(|Bx|, |By|), every texel
};

ScanTotals scan_input(const TopInput& in, int height, int threads, bool avx2,
                      const std::string& source_name, const char* steep_cause) {
    std::vector<RowScan> rows(static_cast<std::size_t>(height));
    std::vector<detail::SlopeHistogram> histograms(
        static_cast<std::size_t>(resolve_thread_count(threads)));
    const ScanFn scan = select_scan(in.channels, avx2);
    // Chunks are handed out in increasing order, so once a bad texel is found every row before
    // it has been (or is being) scanned and no further chunk is needed.
    std::atomic<bool> bad{false};
    parallel_for_dynamic(height, threads, kScanGrain, [&](int worker, int first, int end) {
        if (bad.load(std::memory_order_relaxed)) return;
        for (int y = first; y < end; ++y) {
            rows[std::size_t(y)].histogram = &histograms[std::size_t(worker)];
            if (!scan(in, y, rows[std::size_t(y)])) {
                bad = true;
                return;
            }
        }
    });
    for (int y = 0; y < height; ++y) {
        const RowScan& r = rows[std::size_t(y)];
        if (r.bad_x < 0) continue;
        const float* t = in.row(y) + std::size_t(r.bad_x) * std::size_t(in.channels);
        if (!std::isfinite(t[0]) || !std::isfinite(t[1]) || !std::isfinite(t[2]))
            detail::throw_non_finite_normal(source_name, r.bad_x, y);
        detail::throw_negative_normal_z(source_name, r.bad_x, y, 2.0f * t[2] - 1.0f);
    }
    ScanTotals totals;
    float max_b = 0.0f;
    bool nan_slope = false;
    for (const RowScan& r : rows) {
        max_b = std::max(max_b, r.max_b);
        nan_slope = nan_slope || r.nan_slope;
        totals.clamped += r.clamped;
        totals.sum_slope += r.stats.total();
        totals.max_slope = std::max(totals.max_slope, r.stats.max);
    }
    // A slope steeper than the limit, or NaN (n is finite, but 2 n - 1 may overflow; found by
    // fuzz_image_bake), exists exactly when max |B| exceeds it or a row saw a NaN; then find the
    // first one.
    if (!(max_b <= kMaxSlope) || nan_slope) {
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < in.width; ++x) {
                float bx, by;
                const float* t = in.row(y) + std::size_t(x) * std::size_t(in.channels);
                if (in.channels == 2) {
                    bx = t[0];
                    by = t[1];
                } else {
                    normal_slope(t, in.green_sign, bx, by);
                }
                if (!(std::abs(bx) <= kMaxSlope))
                    detail::throw_steep_slope(source_name, x, y, bx, steep_cause);
                if (!(std::abs(by) <= kMaxSlope))
                    detail::throw_steep_slope(source_name, x, y, by, steep_cause);
            }
    }
    // build_lean_map takes max M over Mxx = fl(Bx * Bx + 1/s) and Myy; that is non-decreasing
    // in |B| (each rounding is monotonic), so max M = fl(max|B| * max|B| + 1/s), exactly.
    totals.max_b = double(max_b);
    totals.max_m = double(max_b * max_b + in.inv_s);
    for (const detail::SlopeHistogram& h : histograms) totals.histogram.merge(h);
    return totals;
}

// Resizes one output slice. A new vector's bytes are zero-filled by resize, which faults every
// page in: a new buffer is advised to use huge pages first (assign_large, docs/perf.md). Reused
// buffers are left as they are.
void size_slice(std::vector<std::uint8_t>& slice, std::size_t bytes) {
    if (slice.capacity() < bytes) {
        assign_large(slice, bytes, std::uint8_t(0));
        return;
    }
    slice.resize(bytes);
}

// Sizes the slices of the output levels (whose width and height are set); lean1 and lean2 by
// different threads, sharing the first touch.
void size_output(PackedLeanMap& packed, int texel_bytes, int threads) {
    const std::size_t count = packed.levels.size();
    parallel_for_rows(int(2 * count), std::min(threads, 2), [&](int first, int end) {
        for (int job = first; job < end; ++job) {
            const std::size_t l = std::size_t(job) % count;
            PackedLevel& out = packed.levels[l];
            const std::size_t bytes =
                std::size_t(out.width) * std::size_t(out.height) * std::size_t(texel_bytes);
            size_slice(std::size_t(job) < count ? out.lean1 : out.lean2, bytes);
        }
    });
}

}  // namespace

bool set_bake_simd(bool enabled) {
    return g_simd_enabled.exchange(enabled);
}

bool bake_simd_active() {
    return cpu_has_avx2() && g_simd_enabled.load();
}

namespace {

// Fills `packed` with the metadata and the level sizes and returns where each level goes.
using TargetProvider =
    std::function<std::vector<PackedLevelTarget>(PackedLeanMap& packed, int threads)>;

// The input: a float image, or integer samples (exactly one of the two is set).
struct BakeInput {
    const Image* floats = nullptr;
    const UnormImage* unorm = nullptr;
    int width() const { return floats != nullptr ? floats->width : unorm->width; }
    int height() const { return floats != nullptr ? floats->height : unorm->height; }
    int channels() const { return floats != nullptr ? floats->channels : unorm->channels; }
};

// The first channel of integer samples as floats (UnormImage::to_float's values).
Image first_channel(const UnormImage& input) {
    Image height(input.width, input.height, 1);
    const auto channels = std::size_t(input.channels);
    const float scale = float(input.max_value);
    for (std::size_t i = 0; i < height.pixels.size(); ++i)
        height.pixels[i] = float(input.samples[i * channels]) / scale;
    return height;
}

void bake_repaired(PackedBakeResult& result, const BakeInput& input, BakeSource source,
                   const BakeOptions& options, Storage storage, const std::string& generator,
                   const std::string& source_name, const TargetProvider& provide_targets,
                   const NormalRepairs& repairs) {
    result.source = source;
    result.clamped_texels = 0;
    const bool avx2 = bake_simd_active();

    Plan plan;
    plan.avx2 = avx2;
    plan.top.green_sign = options.convention == NormalConvention::DirectX ? -1.0f : 1.0f;
    plan.top.inv_s =
        options.bake_roughness_shininess > 0.0f ? 1.0f / options.bake_roughness_shininess : 0.0f;
//  Pass 0. Height maps go through the reference slope filter (Sobel in double, docs/math.md §2),
    // which also validates them; normal maps are decoded on the fly in pass 1.
    Image slopes;
    ScanTotals totals;
    const int width = input.width(), height = input.height();
    if (result.source == BakeSource::Normal) {
        detail::check_normal_map_shape(width, height, input.channels(), source_name);
        if (input.floats != nullptr) {
            plan.top.pixels = input.floats->pixels.data();
        } else {
            plan.top.unorm = input.unorm->samples.data();
            plan.top.unorm_max = float(input.unorm->max_value);
            plan.top.avx2 = avx2;
            plan.top.bake_id = g_next_bake_id.fetch_add(1);
        }
        plan.top.width = width;
        plan.top.channels = input.channels();
        totals = scan_input(plan.top, height, options.threads, avx2, source_name,
                            detail::kSteepNormalCause);
        result.clamped_texels = totals.clamped;
    } else {
        // Integer samples: only the first channel (the height) as floats.
        slopes = input.floats != nullptr
                     ? slopes_from_height(*input.floats, options, source_name).slopes
                     : slopes_from_height(first_channel(*input.unorm), options, source_name).slopes;
        plan.top.pixels = slopes.pixels.data();
        plan.top.width = slopes.width;
        plan.top.channels = 2;
        totals = scan_input(plan.top, slopes.height, options.threads, avx2, source_name,
                            "height steps times the strength are too large");
    }
    const detail::ScaleChoice scale =
        options.scale_excludes_outliers
            ? detail::choose_lean_scale(totals.histogram, totals.max_b, totals.max_m,
                                        plan.top.inv_s)
            : detail::ScaleChoice{detail::lean_scale(totals.max_b, totals.max_m), 0};
    result.texels_beyond_scale = scale.beyond;
    result.median_steepness = detail::median_steepness(totals.histogram);
    const float sc = scale.scale;
    plan.scale.sc = sc;
    plan.scale.sc2 = sc * sc;
    plan.scale.unorm = detail::unorm_packing(storage, plan.scale.sc, plan.scale.sc2);

    const int texel_bytes = bytes_per_texel(storage);
    plan.texel_bytes = texel_bytes;
    plan.levels = plan_levels(width, height);
    plan.store_level = choose_store_level(plan.levels);
    plan.top_range = select_top(plan.top.channels, avx2);
    plan.pack_range = select_pack(storage, avx2);
    const LevelPlan& store = plan.levels[std::size_t(plan.store_level)];
    plan.stored.resize(std::size_t(store.height) * kMoments * store.stride);

    PackedLeanMap& packed = result.packed;
    packed.storage = storage;
    packed.scale = sc;
    packed.roughness_baked = plan.top.inv_s > 0.0f;
    packed.baked_shininess = packed.roughness_baked ? options.bake_roughness_shininess : 0.0f;
    packed.source_convention = options.convention;
    packed.normal_repairs = repairs;
    packed.generator = generator;
    packed.levels.assign(plan.levels.size(), PackedLevel{});
    for (std::size_t l = 0; l < plan.levels.size(); ++l) {
        packed.levels[l].width = plan.levels[l].width;
        packed.levels[l].height = plan.levels[l].height;
    }
    plan.targets = provide_targets(packed, resolve_thread_count(options.threads));
    if (plan.targets.size() != plan.levels.size())
        throw std::invalid_argument("bake_packed_to: one output target per level expected");

    // Pass 1: the store level's rows (and everything above them), one at a time to whichever
    // thread is free. Which thread makes a row changes nothing in it.
    std::vector<std::unique_ptr<RowMaker>> makers(
        static_cast<std::size_t>(resolve_thread_count(options.threads)));
    parallel_for_dynamic(store.height, options.threads, 1, [&](int worker, int first, int end) {
        auto& maker = makers[std::size_t(worker)];
        if (!maker) maker = std::make_unique<RowMaker>(plan, false);
        for (int y = first; y < end; ++y) maker->row(plan.store_level, y, true);
    });
    // Pass 2: the small levels below, from the stored rows.
    RowMaker maker(plan, true);
    const int last = int(plan.levels.size()) - 1;
    const Planes coarsest = maker.row(last, 0, true);

    LeanMapSummary& s = result.summary;
    s = LeanMapSummary{};
    s.width = width;
    s.height = height;
    s.levels = int(plan.levels.size());
    s.scale = sc;
    s.max_slope = totals.max_slope;
    s.mean_slope = float(totals.sum_slope / (double(width) * double(height)));
    detail::summarize_coarsest(s, {coarsest[kBx][0], coarsest[kBy][0]},
                               {coarsest[kMxx][0], coarsest[kMyy][0], coarsest[kMxy][0]});
}

// The bake of a normal map's repaired copy where it has texels to repair (NormalRepairs), else of
// the input as it is.
void bake(PackedBakeResult& result, const BakeInput& input, BakeSource source,
          const BakeOptions& options, Storage storage, const std::string& generator,
          const std::string& source_name, const TargetProvider& provide_targets) {
    const BakeSource resolved = input.floats != nullptr
                                    ? resolve_bake_source(source, *input.floats)
                                    : resolve_bake_source(source, *input.unorm);
    NormalRepairs repairs;
    if (resolved == BakeSource::Normal && !options.strict_normals) {
        repairs = input.floats != nullptr ? count_normal_repairs(*input.floats)
                                          : count_normal_repairs(*input.unorm);
    }
    if (!repairs.any()) {
        bake_repaired(result, input, resolved, options, storage, generator, source_name,
                      provide_targets, repairs);
        return;
    }
    const Image repaired = repair_normal_map(input.floats != nullptr ? *input.floats
                                                                     : input.unorm->to_float());
    bake_repaired(result, BakeInput{&repaired, nullptr}, resolved, options, storage, generator,
                  source_name, provide_targets, repairs);
}

}  // namespace

void bake_packed_into(PackedBakeResult& result, const Image& input, BakeSource source,
                      const BakeOptions& options, Storage storage, const std::string& generator,
                      const std::string& source_name) {
    // Keep the buffers of a previous result: baking a map of the same size and storage again
    // allocates nothing.
    std::vector<PackedLevel> previous = std::move(result.packed.levels);
    bake(result, BakeInput{&input, nullptr}, source, options, storage, generator, source_name,
         [&](PackedLeanMap& packed, int threads) {
             for (std::size_t l = 0; l < std::min(previous.size(), packed.levels.size()); ++l) {
                 packed.levels[l].lean1 = std::move(previous[l].lean1);
                 packed.levels[l].lean2 = std::move(previous[l].lean2);
             }
             size_output(packed, bytes_per_texel(storage), threads);
             std::vector<PackedLevelTarget> targets;
             for (PackedLevel& level : packed.levels)
                 targets.push_back({level.lean1.data(), level.lean2.data()});
             return targets;
         });
}

PackedBakeResult bake_packed_to(const PackedOutputOpener& open_output, const Image& input,
                                BakeSource source, const BakeOptions& options, Storage storage,
                                const std::string& generator, const std::string& source_name) {
    PackedBakeResult result;
    bake(result, BakeInput{&input, nullptr}, source, options, storage, generator, source_name,
         [&](PackedLeanMap& packed, int) { return open_output(packed); });
    return result;
}

PackedBakeResult bake_packed_to(const PackedOutputOpener& open_output, const UnormImage& input,
                                BakeSource source, const BakeOptions& options, Storage storage,
                                const std::string& generator, const std::string& source_name) {
    PackedBakeResult result;
    bake(result, BakeInput{nullptr, &input}, source, options, storage, generator, source_name,
         [&](PackedLeanMap& packed, int) { return open_output(packed); });
    return result;
}

PackedBakeResult bake_packed(const Image& input, BakeSource source, const BakeOptions& options,
                             Storage storage, const std::string& generator,
                             const std::string& source_name) {
    PackedBakeResult result;
    bake_packed_into(result, input, source, options, storage, generator, source_name);
    return result;
}

}  // namespace leanfade
