// From bumps to projected slopes (docs/math.md §2).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "lean_map_internal.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/parallel.hpp"

namespace leanfade {
namespace {

int wrap_index(int i, int n, Wrap wrap) {
    if (wrap == Wrap::Clamp) return i < 0 ? 0 : (i >= n ? n - 1 : i);
    i %= n;
    return i < 0 ? i + n : i;
}

std::string texel_name(int x, int y) {
    return "texel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

void check_size(int width, int height, int channels, const std::string& source_name) {
    if (width <= 0 || height <= 0) throw Error(source_name, "image has zero size");
    if (channels < 1 || channels > 4)
        throw Error(source_name, "unsupported channel count " + std::to_string(channels));
}

void check_size(const Image& image, const std::string& source_name) {
    check_size(image.width, image.height, image.channels, source_name);
}

// Serially, so that the error names the first texel (rows top first) for any thread count.
void check_slopes(const Image& slopes, const std::string& source_name, const char* cause) {
    for (int y = 0; y < slopes.height; ++y) {
        for (int x = 0; x < slopes.width; ++x) {
            for (int c = 0; c < 2; ++c) {
                const float slope = slopes.at(x, y, c);
                if (std::abs(slope) <= kMaxSlope) continue;  // false for NaN too
                detail::throw_steep_slope(source_name, x, y, slope, cause);
            }
        }
    }
}

}  // namespace

namespace detail {

void check_normal_map_shape(int width, int height, int channels,
                            const std::string& source_name) {
    check_size(width, height, channels, source_name);
    if (channels < 3)
        throw Error(source_name, "a normal map needs 3 or 4 channels, this image has " +
                                     std::to_string(channels));
}

void check_normal_map_shape(const Image& normals, const std::string& source_name) {
    check_normal_map_shape(normals.width, normals.height, normals.channels, source_name);
}

void throw_non_finite_normal(const std::string& source_name, int x, int y) {
    throw Error(source_name, "NaN or Inf normal at " + texel_name(x, y));
}

void throw_steep_slope(const std::string& source_name, int x, int y, float slope,
                       const char* cause) {
    char value[32];
    std::snprintf(value, sizeof value, "%.3g", double(slope));
    throw Error(source_name, std::string("slope ") + value + " at " + texel_name(x, y) +
                                 " is steeper than the limit of 1e6 (" + cause + ")");
}

void throw_negative_normal_z(const std::string& source_name, int x, int y, float z) {
    // Reached only with strict_normals (the bakes repair such texels otherwise). A height map
    // stored as colour (not grey, or it would have been taken as one) fails here too.
    throw Error::file_mentioning(
        source_name,
        "normal with z <= 0 at " + texel_name(x, y) + " (z = " + std::to_string(z) +
            ") refused by 'strict_normals' (without it, (0, 0, 0) padding is taken as flat and "
            "z <= 0 raised; a height map stored as colour? read it with 'from' height)",
        {"strict_normals", "from"});
}

}  // namespace detail

namespace {

bool is_padding(float r, float g, float b) {
    return r == 0.0f && g == 0.0f && b == 0.0f;
}

bool needs_raising(float b) {
    return 2.0f * b - 1.0f <= -kNormalZRejectEpsilon;  // false for NaN: the bake refuses it
}

template <class Sample>
NormalRepairs count_repairs(const std::vector<Sample>& samples, int channels, float max_value) {
    NormalRepairs repairs;
    const auto step = std::size_t(channels);
    for (std::size_t i = 0; i + 2 < samples.size(); i += step) {
        const float r = float(samples[i]) / max_value, g = float(samples[i + 1]) / max_value,
                    b = float(samples[i + 2]) / max_value;
        if (is_padding(r, g, b))
            ++repairs.padding_texels;
        else if (needs_raising(b))
            ++repairs.raised_texels;
    }
    return repairs;
}

}  // namespace

NormalRepairs count_normal_repairs(const Image& normals) {
    if (normals.channels < 3) return {};
    return count_repairs(normals.pixels, normals.channels, 1.0f);
}

NormalRepairs count_normal_repairs(const UnormImage& normals) {
    if (normals.channels < 3) return {};
    // The same counts in integers: a sample decodes to 0 exactly when it is 0, and needs_raising
    // of float(s) / max only grows false as s grows (2 v - 1 is monotonic in v, v in s), so it
    // holds exactly for the samples below the first one where it fails.
    const float max_value = float(normals.max_value);
    std::uint32_t raise_below = 0;
    while (raise_below <= normals.max_value && needs_raising(float(raise_below) / max_value))
        ++raise_below;
    NormalRepairs repairs;
    const auto step = std::size_t(normals.channels);
    const std::vector<std::uint16_t>& samples = normals.samples;
    std::uint64_t padding = 0, raised = 0;
    for (std::size_t i = 0; i + 2 < samples.size(); i += step) {
        const bool pad = (samples[i] | samples[i + 1] | samples[i + 2]) == 0;
        padding += pad;
        raised += !pad && samples[i + 2] < raise_below;
    }
    repairs.padding_texels = padding;
    repairs.raised_texels = raised;
    return repairs;
}

Image repair_normal_map(const Image& normals) {
    Image repaired = normals;
    if (repaired.channels < 3) return repaired;
    const auto step = std::size_t(repaired.channels);
    for (std::size_t i = 0; i + 2 < repaired.pixels.size(); i += step) {
        float* t = &repaired.pixels[i];
        if (is_padding(t[0], t[1], t[2])) {
            t[0] = 0.5f;
            t[1] = 0.5f;
            t[2] = 1.0f;
        } else if (needs_raising(t[2])) {
            t[2] = 0.5f;  // z = 0, raised to kMinNormalZ by the bake
        }
    }
    return repaired;
}

SlopeResult slopes_from_height(const Image& height, const BakeOptions& options,
                               const std::string& source_name) {
    check_size(height, source_name);
    if (!std::isfinite(options.strength))
        throw Error(source_name, "strength is not a finite number");
    const int w = height.width, h = height.height;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (!std::isfinite(height.at(x, y)))
                throw Error(source_name, "NaN or Inf height at " + texel_name(x, y));

    SlopeResult result{Image(w, h, 2), 0};
    // Strength per texel spacing along u and v (BakeOptions::strength_unit).
    const bool per_uv = options.strength_unit == StrengthUnit::Uv;
    const double strength_u = double(options.strength) * (per_uv ? double(w) : 1.0);
    const double strength_v = double(options.strength) * (per_uv ? double(h) : 1.0);
    // Sobel / 8 gives the derivative per texel spacing. Rows run top to bottom, so +v (up) is
    // towards row y - 1. b~ = (-strength df/du, -strength df/dv) (docs/math.md §2).
    parallel_for_rows(h, options.threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            const int up = wrap_index(y - 1, h, options.wrap);
            const int down = wrap_index(y + 1, h, options.wrap);
            for (int x = 0; x < w; ++x) {
                const int left = wrap_index(x - 1, w, options.wrap);
                const int right = wrap_index(x + 1, w, options.wrap);
                auto f = [&](int xx, int yy) { return double(height.at(xx, yy)); };
                const double dfdu = ((f(right, up) + 2 * f(right, y) + f(right, down)) -
                                     (f(left, up) + 2 * f(left, y) + f(left, down))) / 8.0;
                const double dfdv = ((f(left, up) + 2 * f(x, up) + f(right, up)) -
                                     (f(left, down) + 2 * f(x, down) + f(right, down))) / 8.0;
                // Clamped to the float range so that the conversion cannot overflow;
                // check_slopes refuses anything past kMaxSlope, naming the value.
                const double huge = std::numeric_limits<float>::max();
                const double sx = -strength_u * dfdu, sy = -strength_v * dfdv;
                result.slopes.at(x, y, 0) = float(std::clamp(sx, -huge, huge));
                result.slopes.at(x, y, 1) = float(std::clamp(sy, -huge, huge));
            }
        }
    });
    check_slopes(result.slopes, source_name, "height steps times the strength are too large");
    return result;
}

SlopeResult slopes_from_normals(const Image& normals, const BakeOptions& options,
                                const std::string& source_name) {
    detail::check_normal_map_shape(normals, source_name);
    const int w = normals.width, h = normals.height;
    SlopeResult result{Image(w, h, 2), 0};
    const float green_sign = options.convention == NormalConvention::DirectX ? -1.0f : 1.0f;
    // Validate serially first so the error names the first bad texel, deterministically.
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c)
                if (!std::isfinite(normals.at(x, y, c)))
                    detail::throw_non_finite_normal(source_name, x, y);
            const float z = 2.0f * normals.at(x, y, 2) - 1.0f;
            if (z <= -kNormalZRejectEpsilon) detail::throw_negative_normal_z(source_name, x, y, z);
            if (z < kMinNormalZ) ++result.clamped_texels;
        }
    }
    parallel_for_rows(h, options.threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            for (int x = 0; x < w; ++x) {
                const float nx = 2.0f * normals.at(x, y, 0) - 1.0f;
                const float ny = green_sign * (2.0f * normals.at(x, y, 1) - 1.0f);
                const float nz = std::max(2.0f * normals.at(x, y, 2) - 1.0f, kMinNormalZ);
                result.slopes.at(x, y, 0) = nx / nz;  // B = n.xy / n.z (docs/math.md §2)
                result.slopes.at(x, y, 1) = ny / nz;
            }
        }
    });
    check_slopes(result.slopes, source_name, detail::kSteepNormalCause);
    return result;
}

}  // namespace leanfade
