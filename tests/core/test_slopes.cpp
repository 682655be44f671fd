#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "test_helpers.hpp"

using namespace leanfade;

TEST(Slopes, HeightSlopesEqualAnalyticGradientOfSmoothField) {
    // A smooth periodic field: the Sobel/8 estimate of the gradient is second-order accurate,
    // so with wavelengths of >= 32 texels the error is below 1% of the slope amplitude.
    const int n = 128;
    const double k1 = 2 * std::numbers::pi / 64.0, k2 = 2 * std::numbers::pi / 32.0;
    const double a = 3.0, b = 1.5;
    auto f = [&](double x, double y) { return a * std::sin(k1 * x) + b * std::cos(k2 * y); };
    BakeOptions options;
    options.strength = 0.8f;
    const Image slopes = slopes_from_height(test::height_from(n, n, f), options).slopes;
    const double amplitude = 0.8 * std::max(a * k1, b * k2);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const double dfdx = a * k1 * std::cos(k1 * x);
            const double dfdrow = -b * k2 * std::sin(k2 * y);
            // +v is up, i.e. towards smaller row indices.
            EXPECT_NEAR(slopes.at(x, y, 0), -0.8 * dfdx, 0.01 * amplitude);
            EXPECT_NEAR(slopes.at(x, y, 1), -0.8 * -dfdrow, 0.01 * amplitude);
        }
    }
}

TEST(Slopes, LinearRampIsExactUnderClamp) {
    // A plane h = 2x - 3row: Sobel/8 is exact on linear fields away from a clamped border.
    const Image height = test::height_from(9, 7, [](double x, double y) { return 2 * x - 3 * y; });
    BakeOptions options;
    options.wrap = Wrap::Clamp;
    const Image s = slopes_from_height(height, options).slopes;
    for (int y = 1; y < 6; ++y)
        for (int x = 1; x < 8; ++x) {
            EXPECT_FLOAT_EQ(s.at(x, y, 0), -2.0f);
            EXPECT_FLOAT_EQ(s.at(x, y, 1), -3.0f);  // dh/dv = -dh/drow = 3
        }
}

TEST(Slopes, NormalMapAndHeightMapPathsAgree) {
    // Encode the height path's normals as a float normal map, then decode: same B.
    const int n = 64;
    const Image height = test::height_from(n, n, [](double x, double y) {
        return 4 * std::sin(x * 0.2) * std::cos(y * 0.15 + 0.3);
    });
    BakeOptions options;
    const Image from_height = slopes_from_height(height, options).slopes;
    Image normal_map(n, n, 3);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float bx = from_height.at(x, y, 0), by = from_height.at(x, y, 1);
            const float len = std::sqrt(bx * bx + by * by + 1);
            normal_map.at(x, y, 0) = 0.5f * bx / len + 0.5f;
            normal_map.at(x, y, 1) = 0.5f * by / len + 0.5f;
            normal_map.at(x, y, 2) = 0.5f / len + 0.5f;
        }
    const SlopeResult from_normals = slopes_from_normals(normal_map, options);
    EXPECT_EQ(from_normals.clamped_texels, 0u);
    for (std::size_t i = 0; i < from_height.pixels.size(); ++i)
        EXPECT_NEAR(from_normals.slopes.pixels[i], from_height.pixels[i], 2e-5f);
}

TEST(Slopes, DirectXConventionFlipsGreen) {
    Image normal_map(1, 1, 3);
    normal_map.pixels = {0.6f, 0.7f, 0.9f};
    BakeOptions gl, dx;
    dx.convention = NormalConvention::DirectX;
    const Image a = slopes_from_normals(normal_map, gl).slopes;
    const Image b = slopes_from_normals(normal_map, dx).slopes;
    EXPECT_FLOAT_EQ(a.at(0, 0, 0), b.at(0, 0, 0));
    EXPECT_FLOAT_EQ(a.at(0, 0, 1), -b.at(0, 0, 1));
    EXPECT_NEAR(a.at(0, 0, 0), 0.2f / 0.8f, 1e-6f);
}

TEST(Slopes, NormalsBelowHorizonAreRejectedAndGrazingOnesClamped) {
    Image bad(2, 1, 3);
    bad.pixels = {0.5f, 0.5f, 1.0f, 0.5f, 0.5f, 0.3f};  // second texel: z = -0.4
    try {
        slopes_from_normals(bad, {}, "bad.png");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "bad.png");
        EXPECT_NE(e.cause().find("z <= 0"), std::string::npos) << e.cause();
        EXPECT_NE(e.cause().find("(1, 0)"), std::string::npos) << e.cause();
    }
    Image grazing(1, 1, 3);
    grazing.pixels = {1.0f, 0.5f, 0.5f};  // z = 0 exactly: clamped to kMinNormalZ, counted
    const SlopeResult r = slopes_from_normals(grazing, {});
    EXPECT_EQ(r.clamped_texels, 1u);
    EXPECT_FLOAT_EQ(r.slopes.at(0, 0, 0), 1.0f / kMinNormalZ);
}

TEST(Slopes, NaNAndWrongChannelCountsAreErrors) {
    Image h = test::height_from(4, 4, [](double, double) { return 0.0; });
    h.at(2, 3) = std::nanf("");
    EXPECT_THROW(slopes_from_height(h, {}, "h.exr"), Error);
    Image two(4, 4, 2, 0.5f);
    EXPECT_THROW(slopes_from_normals(two, {}, "two.png"), Error);
    EXPECT_THROW(slopes_from_height(Image(), {}, "empty.png"), Error);
}

TEST(Slopes, ThreadCountDoesNotChangeResults) {
    const Image height = test::height_from(97, 61, [](double x, double y) {
        return std::sin(x * 0.31) * 5 + std::cos(y * 0.17 + x * 0.05) * 3;
    });
    BakeOptions one, two;
    one.threads = 1;
    two.threads = 2;
    EXPECT_EQ(slopes_from_height(height, one).slopes.pixels,
              slopes_from_height(height, two).slopes.pixels);
}
