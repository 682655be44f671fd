// The AVX2 kernels of the fast bake (bake_packed_kernels.hpp): the scalar kernels' operations on 8
// texels (or 4 doubles) at a time, giving the same bytes. Compiled for x86 with GCC or Clang, each
// function with the avx2 target attribute (no FMA, so that no a * b + c is contracted) and chosen
// at run time where the CPU has AVX2; rows end with the scalar kernels (bake_packed_scalar.cpp).
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "bake_packed_kernels.hpp"

#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#define LEANFADE_AVX2_KERNELS 1
#include <immintrin.h>
#define LF_AVX2 __attribute__((target("avx2")))
#define LF_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
#else
#define LEANFADE_AVX2_KERNELS 0
#endif

namespace leanfade::bake_kernels::avx2 {

#if LEANFADE_AVX2_KERNELS
namespace {

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
        // s = g v + o for n, B, Mxy (the encoding's g, o), as the scalar lean_texel.
        const __m256 gain = _mm256_set1_ps(s.gain), offset = _mm256_set1_ps(s.offset);
        const __m256 sc = _mm256_set1_ps(s.sc), sc2 = _mm256_set1_ps(s.sc2);
        __m256 l1[4], l2[4];
        l1[0] = _mm256_add_ps(_mm256_mul_ps(gain, m[kNx]), offset);
        l1[1] = _mm256_add_ps(_mm256_mul_ps(gain, m[kNy]), offset);
        l1[2] = _mm256_add_ps(_mm256_mul_ps(gain, m[kNz]), offset);
        l1[3] = _mm256_add_ps(_mm256_div_ps(_mm256_mul_ps(gain, m[kMxy]), sc2), offset);
        l2[0] = _mm256_add_ps(_mm256_div_ps(_mm256_mul_ps(gain, m[kBx]), sc), offset);
        l2[1] = _mm256_add_ps(_mm256_div_ps(_mm256_mul_ps(gain, m[kBy]), sc), offset);
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
    scalar::pack_range<S>(p, x, x1, d, s);
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
    scalar::reduce_box(a, c, out, x, x1);
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
    scalar::vertical(src, w, taps, x, x1, out);
}

LF_AVX2 void horizontal_avx2(const double* row, int sw, int dw, const TapTable& xtaps, int x0,
                             float* out) {
    int x = x0;
    if (sw == 2 * dw) {
        const __m256d half = _mm256_set1_pd(0.5), zero = _mm256_setzero_pd();
        for (; x + 4 <= dw; x += 4) {
            const __m256d lo = _mm256_mul_pd(half, _mm256_loadu_pd(row + 2 * x));
            const __m256d hi = _mm256_mul_pd(half, _mm256_loadu_pd(row + 2 * x + 4));
            const __m256d sums = _mm256_permute4x64_pd(_mm256_hadd_pd(lo, hi), 0xD8);
            _mm_storeu_ps(out + x, _mm256_cvtpd_ps(_mm256_add_pd(sums, zero)));
        }
    }
    scalar::horizontal(row, sw, dw, xtaps, x, out);
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
    return scalar::scan_range<Channels>(in, y, x, r);
}

LF_AVX2 void unorm_to_float_avx2(const std::uint16_t* samples, std::size_t count, float max,
                                 float* out) {
    const __m256 divisor = _mm256_set1_ps(max);
    std::size_t i = 0;
    for (; i + 8 <= count; i += 8) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(samples + i));
        const __m256 f = _mm256_cvtepi32_ps(_mm256_cvtepu16_epi32(v));  // exact: < 2^24
        _mm256_storeu_ps(out + i, _mm256_div_ps(f, divisor));
    }
    scalar::unorm_to_float(samples + i, count - i, max, out + i);
}

}  // namespace

bool supported() {
    static const bool has = __builtin_cpu_supports("avx2") != 0;
    return has;
}

Kernels kernels(int channels, Storage storage) {
    Kernels k;
    k.top_range =
        with_channels(channels, [](auto c) -> TopFn { return top_range_avx2<decltype(c)::value>; });
    k.pack_range =
        with_storage(storage, [](auto s) -> PackFn { return pack_range_avx2<decltype(s)::value>; });
    k.scan_row =
        with_channels(channels, [](auto c) -> ScanFn { return scan_row_avx2<decltype(c)::value>; });
    k.reduce_box = reduce_box_avx2;
    k.vertical = vertical_avx2;
    k.horizontal = horizontal_avx2;
    k.unorm_to_float = unorm_to_float_avx2;
    return k;
}

#else  // no AVX2 kernels for this target or compiler

bool supported() {
    return false;
}

Kernels kernels(int, Storage) {
    throw std::logic_error("bake_packed: no AVX2 kernels in this build");
}

#endif  // LEANFADE_AVX2_KERNELS

}  // namespace leanfade::bake_kernels::avx2
