// Shared pieces of the reference bake and the fast path (see lean_map_internal.hpp).
#include "lean_map_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "leanfade/core/shading.hpp"

namespace leanfade::detail {

std::vector<std::vector<Tap>> reduction_taps(int src, int dst) {
    std::vector<std::vector<Tap>> taps(static_cast<std::size_t>(dst));
    for (int i = 0; i < dst; ++i) {
        // Work in integer units of 1/dst to keep the overlaps exact: [i*src, (i+1)*src).
        const std::int64_t lo = std::int64_t(i) * src, hi = std::int64_t(i + 1) * src;
        for (std::int64_t j = lo / dst; j * dst < hi; ++j) {
            const std::int64_t overlap = std::min(hi, (j + 1) * dst) - std::max(lo, j * dst);
            if (overlap > 0)
                taps[std::size_t(i)].push_back({int(j), double(overlap) / double(src)});
        }
    }
    return taps;
}

float lean_scale(double max_b, double max_m) {
    float scale = float(std::max({max_b, std::sqrt(max_m), 1e-4}));
    // Round sc up so that sc * sc >= max_m and sc >= max_b hold in float arithmetic too.
    while (double(scale) * double(scale) < max_m || double(scale) < max_b)
        scale = std::nextafter(scale, std::numeric_limits<float>::infinity());
    return scale;
}

ScaleChoice choose_lean_scale(const SlopeHistogram& histogram, double max_b, double max_m,
                              float inv_s) {
    const float exact = lean_scale(max_b, max_m);
    std::uint64_t total = 0;
    for (const std::uint64_t c : histogram.counts) total += c;
    const auto allowed = std::uint64_t(double(total) * kMaxFractionBeyondScale);
    // The percentile: the lowest bin p with at most `allowed` texels in the bins above it.
    int p = SlopeHistogram::kCount - 1;
    std::uint64_t above = 0;
    while (p > 0 && above + histogram.counts[p] <= allowed) above += histogram.counts[p--];
    // Outliers: the bins that start at kMinScaleGain times the percentile's edge or above. sc
    // covers the highest occupied bin below them (never below the maximum / kMaxScaleGain).
    const double outlier_start = kMinScaleGain * double(SlopeHistogram::upper_edge(p));
    const double lowest = double(exact) / kMaxScaleGain;
    int k = SlopeHistogram::kCount - 1;
    std::uint64_t beyond = 0;
    while (k > p && (histogram.counts[k] == 0 ||
                     double(SlopeHistogram::upper_edge(k - 1)) >= outlier_start))
        beyond += histogram.counts[k--];
    while (k + 1 < SlopeHistogram::kCount && double(SlopeHistogram::upper_edge(k)) < lowest)
        beyond -= histogram.counts[++k];
    if (beyond == 0) return {exact, 0};
    const double edge = SlopeHistogram::upper_edge(k);
    const float scale = lean_scale(edge, edge * edge + double(inv_s));
    if (double(scale) * kMinScaleGain > double(exact)) return {exact, 0};
    return {scale, beyond};
}

void summarize_coarsest(LeanMapSummary& s, glm::vec2 mean, glm::vec3 second) {
    s.coarsest_covariance = shading::lf_covariance(mean, second, 0.0f);
    const double a = s.coarsest_covariance.x, d = s.coarsest_covariance.y,
                 c = s.coarsest_covariance.z;
    const double mid = 0.5 * (a + d), rad = std::sqrt(0.25 * (a - d) * (a - d) + c * c);
    const double lmax = mid + rad, lmin = mid - rad;
    s.coarsest_anisotropy =
        lmin > 1e-12 ? float(std::sqrt(lmax / lmin)) : std::numeric_limits<float>::infinity();
}

}  // namespace leanfade::detail
