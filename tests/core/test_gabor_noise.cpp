// Periodic Gabor noise (leanfade/core/detail/gabor_noise.hpp): deterministic, tiles exactly, its
// spectrum peaks at the chosen wave vector, its RMS slope is the one asked for.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/gabor_noise.hpp"
#include "leanfade/core/detail/procedural.hpp"

using namespace leanfade;

namespace {

// |H(ku, kv)|^2 of a square height image for integer frequencies (cycles per period) in
// [-size/2, size/2), indexed [(kv + size/2) * size + (ku + size/2)], with u = x and v the row
// counted from the bottom (v up, as the noise's wave vector).
std::vector<double> power_spectrum(const Image& h) {
    const int n = h.width;
    const double two_pi = 2.0 * std::numbers::pi;
    // Along u first: rows[v][ku].
    std::vector<std::complex<double>> rows(std::size_t(n) * std::size_t(n));
    for (int v = 0; v < n; ++v)
        for (int k = 0; k < n; ++k) {
            std::complex<double> sum = 0.0;
            for (int x = 0; x < n; ++x)
                sum += double(h.at(x, n - 1 - v)) * std::polar(1.0, -two_pi * (k - n / 2) * x / n);
            rows[std::size_t(v) * std::size_t(n) + std::size_t(k)] = sum;
        }
    std::vector<double> power(std::size_t(n) * std::size_t(n));
    for (int ku = 0; ku < n; ++ku)
        for (int k = 0; k < n; ++k) {
            std::complex<double> sum = 0.0;
            for (int v = 0; v < n; ++v)
                sum += rows[std::size_t(v) * std::size_t(n) + std::size_t(ku)] *
                       std::polar(1.0, -two_pi * (k - n / 2) * v / n);
            power[std::size_t(k) * std::size_t(n) + std::size_t(ku)] = std::norm(sum);
        }
    return power;
}

struct Peak {
    int ku, kv;
};

Peak spectrum_peak(const std::vector<double>& power, int n) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < power.size(); ++i)
        if (power[i] > power[best]) best = i;
    return {int(best % std::size_t(n)) - n / 2, int(best / std::size_t(n)) - n / 2};
}

double power_at(const std::vector<double>& power, int n, int ku, int kv) {
    return power[std::size_t(kv + n / 2) * std::size_t(n) + std::size_t(ku + n / 2)];
}

GaborNoiseSettings small_settings() {
    GaborNoiseSettings s;
    s.size = 64;
    s.cycles_u = 6;
    s.cycles_v = 2;
    return s;
}

}  // namespace

TEST(GaborNoise, IsDeterministicAndDependsOnTheSeed) {
    GaborNoiseSettings s = small_settings();
    const Image a = make_gabor_noise(s, 1);
    EXPECT_EQ(a.pixels, make_gabor_noise(s, 1).pixels);
    EXPECT_EQ(a.pixels, make_gabor_noise(s, 3).pixels);  // any thread count
    s.seed = 2;
    const Image b = make_gabor_noise(s, 1);
    double difference = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        difference += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    EXPECT_GT(difference / double(a.pixels.size()), 0.1);
}

TEST(GaborNoise, TilesExactly) {
    // The column after the right edge is the left column, the row above the top is the bottom
    // row, and the image samples the field at texel centres with one factor.
    GaborNoiseSettings s = small_settings();
    s.orientation_spread = 0.8f;  // kernels whose wave vectors are not on the lattice
    const GaborNoise noise(s);
    const Image image = noise.image(1);
    const int n = s.size;
    double largest = 0.0;
    for (int i = 0; i < n; ++i) {
        const double t = double(i) + 0.5;
        largest = std::max(largest, std::abs(noise.evaluate(t, 0.5)));
        EXPECT_NEAR(noise.evaluate(n + 0.5, t), noise.evaluate(0.5, t), 1e-9) << i;
        EXPECT_NEAR(noise.evaluate(t, n + 0.5), noise.evaluate(t, 0.5), 1e-9) << i;
        EXPECT_NEAR(noise.evaluate(-0.5, t), noise.evaluate(n - 0.5, t), 1e-9) << i;
        EXPECT_NEAR(noise.evaluate(t + 3.0 * n, t - 2.0 * n), noise.evaluate(t, t), 1e-8) << i;
    }
    ASSERT_GT(largest, 0.1);  // not trivially flat
    const double factor = double(image.at(0, 0)) / noise.evaluate(0.5, n - 0.5);
    for (int y = 0; y < n; y += 7)
        for (int x = 0; x < n; x += 5)
            EXPECT_NEAR(image.at(x, y), factor * noise.evaluate(x + 0.5, n - y - 0.5),
                        1e-5 * std::max(1.0, std::abs(double(image.at(x, y)))));
    // Across the seam the field is as smooth as inside: the largest second difference across
    // columns n-1 | 0 is no larger than 1.5 times the largest inside the tile.
    double inside = 0.0, seam = 0.0;
    for (int y = 0; y < n; ++y) {
        for (int x = 1; x + 1 < n; ++x)
            inside = std::max(inside, std::abs(double(image.at(x - 1, y)) - 2.0 * image.at(x, y) +
                                               image.at(x + 1, y)));
        seam = std::max(
            seam, std::abs(double(image.at(n - 1, y)) - 2.0 * image.at(0, y) + image.at(1, y)));
        seam = std::max(
            seam, std::abs(double(image.at(n - 2, y)) - 2.0 * image.at(n - 1, y) + image.at(0, y)));
    }
    EXPECT_LT(seam, 1.5 * inside);
}

TEST(GaborNoise, SpectrumPeaksAtTheChosenWaveVector) {
    // Without spread every kernel's wave vector is F = (6, 2) cycles per period: the spectrum's
    // peak is at +-F within one bin, and the perpendicular direction holds almost nothing.
    GaborNoiseSettings s = small_settings();
    s.orientation_spread = 0.0f;
    s.kernel_wavelengths = 3.0f;
    const std::vector<double> power = power_spectrum(make_gabor_noise(s, 1));
    const int n = s.size;
    const Peak peak = spectrum_peak(power, n);
    const Peak wanted = peak.ku > 0 ? Peak{6, 2} : Peak{-6, -2};
    EXPECT_LE(std::abs(peak.ku - wanted.ku), 1) << peak.ku << "," << peak.kv;
    EXPECT_LE(std::abs(peak.kv - wanted.kv), 1) << peak.ku << "," << peak.kv;
    const double top = power_at(power, n, peak.ku, peak.kv);
    EXPECT_LT(power_at(power, n, -2, 6), 0.02 * top);
    EXPECT_LT(power_at(power, n, 2, -6), 0.02 * top);
    EXPECT_LT(power_at(power, n, 0, 0), 0.02 * top);

    // Another direction and wavelength moves the peak with it.
    s.cycles_u = -3;
    s.cycles_v = 9;
    const Peak other = spectrum_peak(power_spectrum(make_gabor_noise(s, 1)), n);
    const Peak wanted_other = other.kv > 0 ? Peak{-3, 9} : Peak{3, -9};
    EXPECT_LE(std::abs(other.ku - wanted_other.ku), 1) << other.ku << "," << other.kv;
    EXPECT_LE(std::abs(other.kv - wanted_other.kv), 1) << other.ku << "," << other.kv;
}

TEST(GaborNoise, SpreadKeepsThePeakDirection) {
    // With a spread of 0.6 rad the energy-weighted mean direction of the spectrum (its half with
    // ku > 0, folded) stays within 0.1 rad of F's, and its mean frequency within 15% of |F|.
    GaborNoiseSettings s = small_settings();
    s.orientation_spread = 0.6f;
    s.cycles_u = 8;
    s.cycles_v = 0;
    const int n = s.size;
    const std::vector<double> power = power_spectrum(make_gabor_noise(s, 1));
    double total = 0.0, angle = 0.0, radius = 0.0;
    for (int kv = -n / 2; kv < n / 2; ++kv)
        for (int ku = 1; ku < n / 2; ++ku) {
            const double p = power_at(power, n, ku, kv);
            total += p;
            angle += p * std::atan2(double(kv), double(ku));
            radius += p * std::hypot(double(ku), double(kv));
        }
    EXPECT_NEAR(angle / total, 0.0, 0.1);
    EXPECT_NEAR(radius / total, 8.0, 0.15 * 8.0);
}

TEST(GaborNoise, HasTheRequestedRmsSlope) {
    GaborNoiseSettings s = small_settings();
    s.slope_rms = 0.2f;
    const Image h = make_gabor_noise(s, 1);
    const int n = s.size;
    double sum = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double gx = 0.5 * (h.at((x + 1) % n, y) - h.at((x + n - 1) % n, y));
            const double gy = 0.5 * (h.at(x, (y + 1) % n) - h.at(x, (y + n - 1) % n));
            sum += gx * gx + gy * gy;
        }
    EXPECT_NEAR(std::sqrt(sum / double(n * n)), 0.2, 1e-4);
}

TEST(GaborNoise, RefusesSettingsOutsideTheirRanges) {
    auto refused = [](GaborNoiseSettings s, const std::string& setting) {
        try {
            GaborNoise noise(s);
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), setting);
            return;
        }
        ADD_FAILURE() << "accepted, expected an error on " << setting;
    };
    GaborNoiseSettings s = small_settings();
    s.size = 2;
    refused(s, "size");
    s = small_settings();
    s.cycles_u = 0;
    s.cycles_v = 0;
    refused(s, "cycles");
    s = small_settings();
    s.cycles_u = 33;  // shorter than 2 texels per wavelength
    refused(s, "cycles");
    s = small_settings();
    s.kernel_wavelengths = 10.0f;  // radius 10 * 64 / 6.3 texels > half the period
    refused(s, "kernel-wavelengths");
    s = small_settings();
    s.kernel_wavelengths = std::nanf("");
    refused(s, "kernel-wavelengths");
    s = small_settings();
    s.orientation_spread = -0.1f;
    refused(s, "orientation-spread");
    s = small_settings();
    s.impulses_per_kernel = 0.0f;
    refused(s, "impulses-per-kernel");
    s = small_settings();
    s.slope_rms = INFINITY;
    refused(s, "slope-rms");
}

TEST(GaborNoise, IsABuiltInBumpSet) {
    // "gabor" among the procedural sets: tileable waves along a dominant direction.
    const Image h = make_builtin_height("gabor", 128, 7);
    ASSERT_EQ(h.width, 128);
    EXPECT_EQ(h.pixels, make_builtin_height("gabor", 128, 7).pixels);
}
