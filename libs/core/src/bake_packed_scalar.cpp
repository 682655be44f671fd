// The portable kernels of the fast bake (bake_packed_kernels.hpp): the reference arithmetic, one
// texel at a time. They also finish the rows of the AVX2 kernels (bake_packed_avx2.cpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "bake_packed_kernels.hpp"

namespace leanfade::bake_kernels::scalar {
namespace {

// lean1 = (g n + o, g Mxy / sc^2 + o), lean2 = (g B / sc + o, Mxx / sc^2, Myy / sc^2)
// (docs/math.md §3; g, o = 0.5, 0.5 or 1, 0 by the encoding), as pack_lean_map.
inline void lean_texel(const float* m, const PackScale& s, float* l1, float* l2) {
    l1[0] = s.gain * m[kNx] + s.offset;
    l1[1] = s.gain * m[kNy] + s.offset;
    l1[2] = s.gain * m[kNz] + s.offset;
    l1[3] = s.gain * m[kMxy] / s.sc2 + s.offset;
    l2[0] = s.gain * m[kBx] / s.sc + s.offset;
    l2[1] = s.gain * m[kBy] / s.sc + s.offset;
    l2[2] = m[kMxx] / s.sc2;
    l2[3] = m[kMyy] / s.sc2;
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

template <int Channels>
void top_range(const TopInput& in, int y, int x0, int x1, Planes out) {
    const float* row = in.row(y);
    for (int x = x0; x < x1; ++x) top_texel<Channels>(in, row, x, x0, out);
}

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
bool scan_row(const TopInput& in, int y, RowScan& r) {
    return scan_range<Channels>(in, y, 0, r);
}

}  // namespace

template <Storage S>
void pack_range(Planes p, int x0, int x1, const RowDest& d, const PackScale& s) {
    for (int x = x0; x < x1; ++x) {
        float m[kMoments];
        for (int c = 0; c < kMoments; ++c) m[c] = p[c][x];
        pack_texel<S>(m, s, d, x);
    }
}
template void pack_range<Storage::Unorm8>(Planes, int, int, const RowDest&, const PackScale&);
template void pack_range<Storage::Unorm16>(Planes, int, int, const RowDest&, const PackScale&);
template void pack_range<Storage::Float16>(Planes, int, int, const RowDest&, const PackScale&);
template void pack_range<Storage::Float32>(Planes, int, int, const RowDest&, const PackScale&);

template <int Channels>
bool scan_range(const TopInput& in, int y, int x0, RowScan& r) {
    const float* row = in.row(y);
    for (int x = x0; x < in.width; ++x)
        if (!scan_texel<Channels>(in, row, x, r)) return false;
    return true;
}
template bool scan_range<2>(const TopInput&, int, int, RowScan&);
template bool scan_range<3>(const TopInput&, int, int, RowScan&);
template bool scan_range<4>(const TopInput&, int, int, RowScan&);

// The 2x2 box of even sizes: detail::box4, in float.
void reduce_box(const float* a, const float* c, float* out, int x0, int x1) {
    for (int x = x0; x < x1; ++x)
        out[x] = detail::box4(a[2 * x], a[2 * x + 1], c[2 * x], c[2 * x + 1]);
}

// General vertical pass, literally the reference's: sum over taps of weight * source, from 0.
void vertical(const float* const* src, const double* w, int taps, int x0, int x1, double* out) {
    for (int x = x0; x < x1; ++x) {
        double acc = 0.0;
        for (int k = 0; k < taps; ++k) acc += w[k] * double(src[k][x]);
        out[x] = acc;
    }
}

// Horizontal pass. Pairs (sw = 2 dw, both weights exactly 0.5): (h0 + h1) + 0.0 equals the
// reference's (0.0 + h0) + h1 (they differ only in the sign of a zero sum). Otherwise literal.
void horizontal(const double* row, int sw, int dw, const TapTable& xtaps, int x0, float* out) {
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

void unorm_to_float(const std::uint16_t* samples, std::size_t count, float max, float* out) {
    for (std::size_t i = 0; i < count; ++i) out[i] = float(samples[i]) / max;
}

Kernels kernels(int channels, Storage storage) {
    Kernels k;
    k.top_range =
        with_channels(channels, [](auto c) -> TopFn { return top_range<decltype(c)::value>; });
    k.pack_range =
        with_storage(storage, [](auto s) -> PackFn { return pack_range<decltype(s)::value>; });
    k.scan_row =
        with_channels(channels, [](auto c) -> ScanFn { return scan_row<decltype(c)::value>; });
    k.reduce_box = reduce_box;
    k.vertical = vertical;
    k.horizontal = horizontal;
    k.unorm_to_float = unorm_to_float;
    return k;
}

}  // namespace leanfade::bake_kernels::scalar
