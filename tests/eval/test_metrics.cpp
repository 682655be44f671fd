// The metrics of `leanfade eval` on images with known answers: identical images, known
// perturbations, masks, SSIM's closed form on flat images, sRGB.
#include <gtest/gtest.h>

#include <cmath>

#include "leanfade/core/error.hpp"
#include "leanfade/eval/metrics.hpp"

namespace leanfade::eval {
namespace {

// A smooth, non-constant RGB test image (values 0.1 .. 0.9).
Image pattern(int w, int h) {
    Image image(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                image.at(x, y, c) =
                    0.5f + 0.4f * std::sin(0.37f * float(x) + 0.21f * float(y) + float(c));
    return image;
}

// A disc of radius r in the middle of a w x h mask.
Mask disc(int w, int h, float r) {
    Mask m(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float dx = float(x) + 0.5f - 0.5f * float(w);
            const float dy = float(y) + 0.5f - 0.5f * float(h);
            m.inside[std::size_t(y * w + x)] = dx * dx + dy * dy < r * r ? 1 : 0;
        }
    return m;
}

TEST(Metrics, IdenticalImagesHaveNoErrorAndSsimOne) {
    const Image a = pattern(40, 30);
    const Mask mask = disc(40, 30, 12.0f);
    EXPECT_EQ(relative_rmse(a, a, mask), 0.0);
    EXPECT_EQ(ssim(a, a, mask), 1.0);
    EXPECT_EQ(mean_absolute_difference(a, a, mask), 0.0);
    EXPECT_EQ(ssim(a, a, Mask(40, 30, true)), 1.0);
}

TEST(Metrics, ConstantOffsetGivesTheKnownRmse) {
    const Image reference = pattern(40, 30);
    const Mask mask = disc(40, 30, 12.0f);
    Image shifted = reference;
    for (float& v : shifted.pixels) v += 0.05f;
    // Every difference is 0.05 (up to float rounding of v + 0.05): RMSE = 0.05 / mean.
    const double mean = masked_mean(reference, mask);
    EXPECT_NEAR(relative_rmse(shifted, reference, mask), 0.05 / mean, 1e-6 / mean);
    EXPECT_NEAR(mean_absolute_difference(shifted, reference, mask), 0.05, 1e-6);
}

TEST(Metrics, CheckerPerturbationGivesTheKnownRmse) {
    Image reference(32, 32, 3, 0.25f);
    Image noisy = reference;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c) noisy.at(x, y, c) += ((x + y) % 2 == 0 ? 0.1f : -0.1f);
    const Mask all(32, 32, true);
    // RMS of +-0.1 is 0.1; the reference's mean is 0.25.
    EXPECT_NEAR(relative_rmse(noisy, reference, all), 0.1 / 0.25, 1e-6);
    // The mean is unchanged, so the energy ratio is 1.
    EXPECT_NEAR(masked_mean(noisy, all) / masked_mean(reference, all), 1.0, 1e-6);
}

TEST(Metrics, RmseOnlyCountsMaskedPixels) {
    Image reference(16, 16, 3, 0.5f);
    Image other = reference;
    other.at(0, 0, 0) = 100.0f;  // outside the mask
    Mask mask(16, 16, true);
    mask.inside[0] = 0;
    EXPECT_EQ(relative_rmse(other, reference, mask), 0.0);
    mask.inside[0] = 1;
    EXPECT_GT(relative_rmse(other, reference, mask), 1.0);
}

// On flat images (no variance) SSIM reduces to its luminance term (Wang et al. 2004, eq. 13):
// (2 mx my + C1) / (mx^2 + my^2 + C1).
TEST(Metrics, SsimOfFlatImagesIsTheLuminanceTerm) {
    const Image a(24, 24, 3, 0.4f), b(24, 24, 3, 0.6f);
    const double c1 = 0.01 * 0.01;
    const double expected = (2.0 * 0.4 * 0.6 + c1) / (0.4 * 0.4 + 0.6 * 0.6 + c1);
    EXPECT_NEAR(ssim(a, b, Mask(24, 24, true)), expected, 1e-6);
    EXPECT_NEAR(ssim(a, b, disc(24, 24, 6.0f)), expected, 1e-6);
}

TEST(Metrics, SsimDropsWithNoiseAndIsSymmetric) {
    const Image a = pattern(48, 48);
    Image b = a;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x)
            for (int c = 0; c < 3; ++c) b.at(x, y, c) += ((x * 7 + y * 3) % 5 - 2) * 0.04f;
    const Mask mask = disc(48, 48, 20.0f);
    const double s = ssim(a, b, mask);
    EXPECT_LT(s, 0.99);
    EXPECT_GT(s, 0.0);
    EXPECT_NEAR(ssim(b, a, mask), s, 1e-12);
}

// The window is restricted to the mask: what lies outside (the background, a silhouette) does not
// change the index.
TEST(Metrics, SsimIgnoresPixelsOutsideTheMask) {
    const Image a = pattern(48, 48);
    Image b = a;
    for (int c = 0; c < 3; ++c) b.at(24, 24, c) += 0.3f;
    const Mask mask = disc(48, 48, 20.0f);
    Image a_outside = a, b_outside = b;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x)
            if (!mask.at(x, y))
                for (int c = 0; c < 3; ++c) {
                    a_outside.at(x, y, c) = 0.0f;
                    b_outside.at(x, y, c) = 1.0f;
                }
    EXPECT_NEAR(ssim(a_outside, b_outside, mask), ssim(a, b, mask), 1e-12);
}

TEST(Metrics, CoveredPixelsAndErosion) {
    Image marked(8, 6, 3, -1.0f);
    for (int y = 1; y <= 4; ++y)
        for (int x = 1; x <= 5; ++x)
            for (int c = 0; c < 3; ++c) marked.at(x, y, c) = 0.2f;
    const Mask covered = covered_pixels(marked);
    EXPECT_EQ(covered.count(), 20);
    const Mask interior = erode(covered);
    EXPECT_EQ(interior.count(), 2 * 3);  // x 2..4, y 2..3
    EXPECT_TRUE(interior.at(2, 2));
    EXPECT_FALSE(interior.at(1, 1));
    EXPECT_EQ(erode(Mask(5, 5, true)).count(), 9) << "image borders count as outside";
    EXPECT_EQ(intersect(covered, interior).count(), 6);
    const Image filled = fill_outside(marked, covered, 0.5f, 0.5f, 0.5f);
    EXPECT_EQ(filled.at(0, 0, 0), 0.5f);
    EXPECT_EQ(filled.at(2, 2, 1), 0.2f);
}

TEST(Metrics, SizeMismatchIsAnError) {
    const Image a(8, 8, 3), b(8, 9, 3);
    EXPECT_THROW(relative_rmse(a, b, Mask(8, 8, true)), Error);
    EXPECT_THROW(ssim(a, a, Mask(8, 9, true)), Error);
    EXPECT_THROW(intersect(Mask(8, 8), Mask(9, 8)), Error);
}

TEST(Metrics, SrgbEncoding) {
    EXPECT_EQ(encode_srgb(0.0f), 0.0f);
    EXPECT_NEAR(encode_srgb(1.0f), 1.0f, 1e-6);
    EXPECT_NEAR(encode_srgb(0.5f), 0.7354f, 1e-4);  // IEC 61966-2-1
    EXPECT_NEAR(encode_srgb(0.002f), 12.92f * 0.002f, 1e-7);
    EXPECT_EQ(encode_srgb(7.0f), encode_srgb(1.0f)) << "clamped";
    EXPECT_EQ(encode_srgb(-1.0f), 0.0f);
}

}  // namespace
}  // namespace leanfade::eval
