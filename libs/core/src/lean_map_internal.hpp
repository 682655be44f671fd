#pragma once
// Pieces shared by the reference bake (lean_map.cpp, slopes.cpp) and the fused fast path
// (bake_packed.cpp), so that both follow one definition of the filter taps, of sc and of the
// input checks (docs/math.md §2-3).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/gtc/packing.hpp>
#include <glm/vec3.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade::detail {

// Area-weighted reduction from `src` to `dst` samples: destination i covers the source interval
// [i r, (i + 1) r), r = src / dst, each source texel weighted by its overlap / r. For even sizes
// this is the 2-tap box (weights exactly 0.5); for odd sizes 3 taps. The weights of every source
// texel sum to 1/r, so the mean is preserved exactly and, the filter being linear, moments stay
// linear (LEAN §3).
struct Tap {
    int index;
    double weight;
};
std::vector<std::vector<Tap>> reduction_taps(int src, int dst);
// One texel of a level made by the 2x2 box (both sizes halved, every weight 0.5): the mean of a0,
// a1 (row 2y) and c0, c1 (row 2y + 1), in float (docs/math.md §3: the MIP chain is built in float),
// summed in this order by the reference and by the fast path's kernels alike. The final + 0 turns
// the one possible -0 (four -0 inputs, e.g. Mxy = 0 * -By) into +0, so a printed zero has no sign.
inline float box4(float a0, float a1, float c0, float c1) {
    return ((a0 + c0) + (a1 + c1)) * 0.25f + 0.0f;
}

// docs/math.md §3 packing for UNORM storage (Q = 255 or 65535), each channel one multiply (and add)
// of the level's float values, then rounded to the nearest integer (ties to even) and clamped to
// [0, Q]:
//   lean1 = (n * Q/2 + Q/2 [rgb], Mxy * (Q/2)/sc^2 + Q/2 [a])
//         = Q (0.5 n + 0.5, 0.5 Mxy/sc^2 + 0.5)
//   lean2 = (B * (Q/2)/sc + Q/2 [rg], Mxx * Q/sc^2, Myy * Q/sc^2)
//         = Q (0.5 B/sc + 0.5, M/sc^2)
// sc2 is the float product sc * sc; the factors are rounded to float once per map. Every value
// is within [-128 Q, 16384 Q] (|n| <= 1, |B| <= 128 sc, M <= 16384 sc^2: choose_lean_scale),
// inside the int32 range, so SIMD conversions need no clamp before their saturating packs (the
// 8-bit store clamps to 255 before its signed 16-bit pack).
struct UnormPacking {
    float half = 0.0f;        // Q / 2 (exact)
    float b_factor = 0.0f;    // (Q / 2) / sc
    float mxy_factor = 0.0f;  // (Q / 2) / sc^2
    float m_factor = 0.0f;    // Q / sc^2
    float max = 0.0f;         // Q
};
// For Storage::Unorm8 or Unorm16 (Q = 255 or 65535).
inline UnormPacking unorm_packing(Storage storage, float sc, float sc2) {
    const float max_code = storage == Storage::Unorm8 ? 255.0f : 65535.0f;
    const float half = 0.5f * max_code;
    return {half, half / sc, half / sc2, max_code / sc2, max_code};
}
// Rounded and clamped code of one packed value (NaN -> 0).
inline std::uint16_t unorm_code(float value, float max_code) {
    if (!(value > 0.0f)) return 0;
    return std::uint16_t(std::min(std::nearbyint(value), max_code));
}
// The eight codes of one texel: lean1 rgba into l1, lean2 rgba into l2.
inline void unorm_texel(const UnormPacking& k, glm::vec3 n, glm::vec2 b, glm::vec3 m,
                        std::uint16_t* l1, std::uint16_t* l2) {
    l1[0] = unorm_code(n.x * k.half + k.half, k.max);
    l1[1] = unorm_code(n.y * k.half + k.half, k.max);
    l1[2] = unorm_code(n.z * k.half + k.half, k.max);
    l1[3] = unorm_code(m.z * k.mxy_factor + k.half, k.max);
    l2[0] = unorm_code(b.x * k.b_factor + k.half, k.max);
    l2[1] = unorm_code(b.y * k.b_factor + k.half, k.max);
    l2[2] = unorm_code(m.x * k.m_factor, k.max);
    l2[3] = unorm_code(m.y * k.m_factor, k.max);
}

// One texel's four codes, little-endian, at `texel` (4 bytes for Unorm8, 8 for Unorm16).
inline void store_unorm_texel(std::uint8_t* texel, const std::uint16_t* codes, Storage storage) {
    for (int c = 0; c < 4; ++c) {
        if (storage == Storage::Unorm8) {
            texel[c] = std::uint8_t(codes[c]);
        } else {
            texel[2 * c] = std::uint8_t(codes[c] & 0xFF);
            texel[2 * c + 1] = std::uint8_t(codes[c] >> 8);
        }
    }
}

// One channel of a float-storage texel (UNORM storages are packed by unorm_texel), IEEE
// little-endian.
inline void store_float_channel(std::uint8_t* texel, int channel, float value, Storage storage) {
    switch (storage) {
        case Storage::Unorm8:
        case Storage::Unorm16: break;
        case Storage::Float16: {
            const std::uint16_t q = glm::packHalf1x16(value);
            texel[2 * channel] = std::uint8_t(q & 0xFF);
            texel[2 * channel + 1] = std::uint8_t(q >> 8);
            break;
        }
        case Storage::Float32: std::memcpy(texel + 4 * channel, &value, 4); break;
    }
}

// One channel of a texel of any storage, decoded (UNORM codes / Q).
inline float load_channel(const std::uint8_t* texel, int channel, Storage storage) {
    switch (storage) {
        case Storage::Unorm8: return float(texel[channel]) / 255.0f;
        case Storage::Unorm16:
            return float(std::uint16_t(texel[2 * channel] | (texel[2 * channel + 1] << 8))) /
                   65535.0f;
        case Storage::Float16:
            return glm::unpackHalf1x16(
                std::uint16_t(texel[2 * channel] | (texel[2 * channel + 1] << 8)));
        case Storage::Float32: {
            float v;
            std::memcpy(&v, texel + 4 * channel, 4);
            return v;
        }
    }
    return 0.0f;
}


// sc (docs/math.md §3, LEAN §5) from the top level's max |Bx|, |By| and max Mxx, Myy: the smallest
// float with |B| <= sc and M.xx, M.yy <= sc^2, with a floor that avoids a zero scale for a flat
// map.
float lean_scale(double max_b, double max_m);

// How many top-level texels have their steepest slope component max(|Bx|, |By|) in each of
// 4 bins per octave (the float's exponent and first two mantissa bits), from 2^-16 (bin 0 holds
// everything below) to 2^21 (kMaxSlope is below 2^20). Both bakes fill it from the same floats,
// so they choose the same sc (choose_lean_scale).
struct SlopeHistogram {
    static constexpr int kShift = 21;                   // float bits >> 21: 4 bins per octave
    static constexpr int kFirst = (127 - 16) << 2;      // the bin of 2^-16
    static constexpr int kCount = (21 + 16) << 2;       // up to 2^21
    std::uint64_t counts[kCount] = {};
    static int bin(float steepest) {
        std::uint32_t bits;
        std::memcpy(&bits, &steepest, sizeof bits);
        const int b = int(bits >> kShift) - kFirst;
        return std::clamp(b, 0, kCount - 1);
    }
    void add(float steepest) { ++counts[bin(steepest)]; }
    void merge(const SlopeHistogram& other) {
        for (int i = 0; i < kCount; ++i) counts[i] += other.counts[i];
    }
    // The smallest value of bin i + 1: every value of bins <= i is below it.
    static float upper_edge(int i) {
        const std::uint32_t bits = std::uint32_t(i + kFirst + 1) << kShift;
        float value;
        std::memcpy(&value, &bits, sizeof value);
        return value;
    }
};

// Outliers (docs/ktx2.md, "Choosing storage and sc"): texels at least kMinScaleGain times as
// steep as the (1 - kMaxFractionBeyondScale) percentile of the map, so at most that fraction of
// them ...
inline constexpr double kMaxFractionBeyondScale = 1e-3;
inline constexpr double kMinScaleGain = 2.0;
// ... and sc is never below the maximum divided by this (B/sc <= 128 and M/sc^2 <= 16384 stay
// far inside the half-float range).
inline constexpr double kMaxScaleGain = 128.0;

struct ScaleChoice {
    float scale = 1.0f;
    std::uint64_t beyond = 0;  // top-level texels whose steepest slope component exceeds sc
};
// sc from the histogram of the top level (inv_s: the baked 1/s, 0 when not baked). p = the
// upper edge of the bin of the 99.9th percentile of max(|Bx|, |By|); the bins starting at 2 p or
// above hold the outliers. Without outliers sc is the maximum (lean_scale(max_b, max_m)); with
// them, sc covers every other texel (the upper edge of the highest occupied bin below 2 p, at
// least the maximum / kMaxScaleGain) and the outliers are counted, unless that would not make
// sc kMinScaleGain times smaller. UNORM storages clamp the outliers' values to [0, 1]; float
// storages keep them.
ScaleChoice choose_lean_scale(const SlopeHistogram& histogram, double max_b, double max_m,
                              float inv_s);

// The summary fields taken from the 1x1 level: covariance M - B B^T and its anisotropy.
void summarize_coarsest(LeanMapSummary& summary, glm::vec2 mean, glm::vec3 second);

// Input checks and messages of slopes_from_normals (slopes.cpp), shared so that the fast path
// refuses the same inputs with the same words, naming the same (first, row-major) texel.
void check_normal_map_shape(const Image& normals, const std::string& source_name);
void check_normal_map_shape(int width, int height, int channels, const std::string& source_name);
[[noreturn]] void throw_non_finite_normal(const std::string& source_name, int x, int y);
[[noreturn]] void throw_negative_normal_z(const std::string& source_name, int x, int y, float z);
// A slope component steeper than kMaxSlope (or NaN) at texel (x, y); `cause` names the input.
[[noreturn]] void throw_steep_slope(const std::string& source_name, int x, int y, float slope,
                                    const char* cause);
inline constexpr const char* kSteepNormalCause = "normal components far outside [0, 1]";

}  // namespace leanfade::detail
