// Two-lobe LEAN (docs/math.md §10) and geometric specular antialiasing (§11): the plateau layer
// (leanfade/core/detail/plateau.hpp) and the lobes of the shared shading header compiled as C++.
#include <gtest/gtest.h>

#include <cmath>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/shading.hpp"
#include "shading_test_params.hpp"

namespace leanfade {
namespace {

using namespace shading;

// A 16 x 16 map: flat ground (B = 0) on the left half, a tilted plateau (B = (0.3, -0.1)) in the
// top right quarter, and bumps (slopes changing by more than epsilon per texel) below it.
Image test_slopes() {
    Image s(16, 16, 2, 0.0f);
    for (int y = 0; y < 16; ++y)
        for (int x = 8; x < 16; ++x) {
            if (y < 8) {
                s.at(x, y, 0) = 0.3f;
                s.at(x, y, 1) = -0.1f;
            } else {
                s.at(x, y, 0) = 0.2f * std::sin(1.7f * float(x * 3 + y));
                s.at(x, y, 1) = 0.2f * std::cos(2.3f * float(x + 5 * y));
            }
        }
    return s;
}

TEST(Plateau, MarksFlatGroundAndTiltedPlateausButNotBumps) {
    const Image slopes = test_slopes();
    const Image layer = plateau_texels(slopes, 0.01f);
    // Inside the flat half and inside the tilted quarter: on a plateau with the texel's slope.
    EXPECT_EQ(layer.at(3, 12, 0), 1.0f);
    EXPECT_EQ(layer.at(3, 12, 1), 0.0f);
    EXPECT_EQ(layer.at(11, 3, 0), 1.0f);
    EXPECT_FLOAT_EQ(layer.at(11, 3, 1), 0.3f);
    EXPECT_FLOAT_EQ(layer.at(11, 3, 2), -0.1f);
    EXPECT_FLOAT_EQ(layer.at(11, 3, 3), 0.3f * 0.3f + 0.1f * 0.1f);
    // The bumps, and the texels next to another region (their neighbour's slope differs).
    for (int y = 9; y < 15; ++y)
        for (int x = 9; x < 15; ++x) EXPECT_EQ(layer.at(x, y, 0), 0.0f) << x << "," << y;
    EXPECT_EQ(layer.at(7, 3, 0), 0.0f);
    EXPECT_EQ(layer.at(8, 3, 0), 0.0f);
    // The map repeats: column 0's left neighbour is column 15 (the tilted plateau at the top).
    EXPECT_EQ(layer.at(0, 3, 0), 0.0f);
    EXPECT_EQ(layer.at(1, 3, 0), 1.0f);
    EXPECT_THROW(plateau_texels(slopes, 0.0f), Error);
    EXPECT_THROW(plateau_texels(slopes, std::nanf("")), Error);
    EXPECT_THROW(plateau_texels(Image(4, 4, 3), 0.01f), Error);
}

TEST(Plateau, FilteredLevelsHoldTheFootprintsFractionAndMoments) {
    // A MIP texel of the layer is (f, f Bs, f |Bs|^2) of the level-0 texels under it: the
    // fraction on a plateau and their summed slopes and squared slopes, over the footprint.
    const Image slopes = test_slopes();
    const Image top = plateau_texels(slopes, 0.01f);
    const std::vector<Image> chain = plateau_mips(slopes, 0.01f);
    ASSERT_EQ(chain.size(), 5u);
    for (std::size_t level = 1; level < chain.size(); ++level) {
        const int n = 1 << level;
        for (int y = 0; y < chain[level].height; ++y)
            for (int x = 0; x < chain[level].width; ++x)
                for (int c = 0; c < 4; ++c) {
                    double sum = 0.0;
                    for (int j = 0; j < n; ++j)
                        for (int i = 0; i < n; ++i) sum += top.at(x * n + i, y * n + j, c);
                    EXPECT_NEAR(chain[level].at(x, y, c), sum / (n * n), 1e-6)
                        << "level " << level << " texel " << x << "," << y << " channel " << c;
                }
    }
    // The coarsest texel: 3/4 of the map is plateau minus its borders; here, f is the share.
    EXPECT_GT(chain.back().at(0, 0, 0), 0.5f);
    EXPECT_LT(chain.back().at(0, 0, 0), 0.75f);
}

LfMoments moments_of(vec2 mean, vec3 second, vec4 plateau) {
    LfMoments m;
    m.normal = normalize(vec3(-mean.x, -mean.y, 1.0f));
    m.mean = mean;
    m.second = second;
    m.plateau = plateau;
    return m;
}

TEST(TwoLobe, NoPlateauIsLeanBitForBit) {
    LfParams p = test::shading_test_params(500.0f);
    const vec3 l = normalize(vec3(0.3f, 0.4f, 0.8f));
    const LfMoments m = moments_of(vec2(0.05f, -0.02f), vec3(0.01f, 0.006f, 0.001f), vec4(0.0f));
    for (int brdf : {LF_BRDF_BLINN_PHONG, LF_BRDF_COOK_TORRANCE}) {
        p.brdf = brdf;
        for (float d : {0.5f, 3.0f, 50.0f}) {
            const vec3 v = d * normalize(vec3(-0.2f, 0.1f, 0.9f));
            const LfShade lean = lf_shade(LF_TECHNIQUE_LEAN, m, l, v, p);
            const LfShade two = lf_shade(LF_TECHNIQUE_TWO_LOBE, m, l, v, p);
            EXPECT_EQ(lean.specular, two.specular) << brdf;
            EXPECT_EQ(lean.diffuse, two.diffuse) << brdf;
        }
    }
}

// The lobe's density over the slope plane: D of lf_shade's Blinn-Phong specular (Ks = 1, Fresnel
// 1, NdotL 1, light 1) at the half vector of slope x.
struct Lobe {
    int technique;
    LfMoments m;
    LfParams p;
    double at(double x, double y) const {
        const vec3 h = normalize(vec3(float(x), float(y), 1.0f));
        LfLobe lobe = lf_lobe_setup(technique, m, p);
        if (lobe.kind == LF_LOBE_TWO_LOBE)
            return lobe.spike_weight * lf_lean_lobe(h, lobe.spike_mean, lobe.spike_sigma) +
                   (1.0f - lobe.spike_weight) * lf_lean_lobe(h, lobe.mean, lobe.sigma);
        return lf_lean_lobe(h, lobe.mean, lobe.sigma);
    }
};

TEST(TwoLobe, KeepsTheMapsMomentsAndPutsTheSpikeOnThePlateau) {
    // 40 % of the footprint on a plateau of slope (0.1, 0) with a little spread, the rest bumps:
    // the mixture's mass, mean and second moments are the map's (plus the base roughness), and
    // its density at the plateau's slope is far above one Gaussian's.
    const float s = 2000.0f, f = 0.4f;
    LfParams p = test::shading_test_params(s);
    const vec2 bs(0.1f, 0.0f);
    const float spread = 1e-5f;  // per axis
    const vec2 halo_mean(-0.05f, 0.08f);
    const vec3 halo_cov(0.02f, 0.015f, 0.004f);
    const vec2 mean = f * bs + (1.0f - f) * halo_mean;
    const vec3 plateau_second(bs.x * bs.x + spread, bs.y * bs.y + spread, bs.x * bs.y);
    const vec3 halo_second(halo_cov.x + halo_mean.x * halo_mean.x,
                           halo_cov.y + halo_mean.y * halo_mean.y,
                           halo_cov.z + halo_mean.x * halo_mean.y);
    const vec3 second = f * plateau_second + (1.0f - f) * halo_second;
    const vec4 plateau(f, f * bs.x, f * bs.y, f * (dot(bs, bs) + 2.0f * spread));
    const Lobe two{LF_TECHNIQUE_TWO_LOBE, moments_of(mean, second, plateau), p};
    const Lobe lean{LF_TECHNIQUE_LEAN, moments_of(mean, second, plateau), p};
    double mass = 0, mx = 0, my = 0, mxx = 0, myy = 0, mxy = 0;
    const double range = 1.2, step = 0.002;
    for (double y = -range; y < range; y += step)
        for (double x = -range; x < range; x += step) {
            // Densities over projected slopes: lf_lean_lobe is one at slope (x, y).
            const double d = two.at(x, y) * step * step;
            mass += d;
            mx += d * x;
            my += d * y;
            mxx += d * x * x;
            myy += d * y * y;
            mxy += d * x * y;
        }
    EXPECT_NEAR(mass, 1.0, 2e-3);
    EXPECT_NEAR(mx, mean.x, 1e-3);
    EXPECT_NEAR(my, mean.y, 1e-3);
    EXPECT_NEAR(mxx, second.x + 1.0 / s, 2e-3 * second.x);
    EXPECT_NEAR(myy, second.y + 1.0 / s, 2e-3 * second.y);
    EXPECT_NEAR(mxy, second.z, 2e-3 * second.x);
    // The spike: f / (2 pi (spread + 1/s)) at Bs plus a little of the halo, where LEAN's one
    // Gaussian of the same moments is about 12.
    const double spike_peak = f / (2.0 * LF_PI * (spread + 1.0 / s));
    EXPECT_GT(two.at(bs.x, bs.y), spike_peak);
    EXPECT_LT(two.at(bs.x, bs.y), 1.05 * spike_peak);
    EXPECT_GT(two.at(bs.x, bs.y), 5.0 * lean.at(bs.x, bs.y));
}

TEST(TwoLobe, AllPlateauIsTheSpikeAlone) {
    LfParams p = test::shading_test_params(1000.0f);
    const vec2 bs(0.02f, -0.01f);
    const vec3 second(bs.x * bs.x, bs.y * bs.y, bs.x * bs.y);
    const vec4 plateau(1.0f, bs.x, bs.y, dot(bs, bs));
    const LfLobe lobe = lf_lobe_setup(LF_TECHNIQUE_TWO_LOBE, moments_of(bs, second, plateau), p);
    EXPECT_EQ(lobe.kind, LF_LOBE_TWO_LOBE);
    EXPECT_EQ(lobe.spike_weight, 1.0f);
    EXPECT_NEAR(lobe.spike_mean.x, bs.x, 1e-7);
    EXPECT_NEAR(lobe.spike_sigma.x, 1e-3, 1e-7);
    EXPECT_TRUE(std::isfinite(lobe.sigma.x) && std::isfinite(lobe.mean.x));
}

TEST(GeometricAa, FootprintIsTheFilteredDerivativesClampedAtKappa) {
    const vec3 small = lf_footprint_covariance(vec2(0.01f, 0.0f), vec2(0.0f, 0.02f), 0.18f);
    EXPECT_NEAR(small.x, 0.15915494 * 1e-4, 1e-9);
    EXPECT_NEAR(small.y, 0.15915494 * 4e-4, 1e-9);
    EXPECT_EQ(small.z, 0.0f);
    // alpha^2 = 2 Sigma is clamped at kappa per axis.
    const vec3 large = lf_footprint_covariance(vec2(3.0f, 0.0f), vec2(0.0f, 3.0f), 0.18f);
    EXPECT_FLOAT_EQ(large.x, 0.09f);
    EXPECT_FLOAT_EQ(large.y, 0.09f);
    EXPECT_EQ(lf_footprint_covariance(vec2(3.0f), vec2(3.0f), 0.0f), vec3(0.0f));
}

// The bound of docs/math.md §11: full trust up to the vertex's change per pixel (and always
// without one), (S / c)^4 beyond, c the larger axis's change.
TEST(GeometricAa, TrustIsOneUpToTheMeshsChangeAndFallsAsTheFourthPowerBeyond) {
    EXPECT_EQ(lf_footprint_trust(vec2(5.0f, 0.0f), vec2(0.0f, 5.0f), 0.0f), 1.0f);
    EXPECT_EQ(lf_footprint_trust(vec2(0.1f, 0.0f), vec2(0.0f, 0.2f), 0.2f), 1.0f);
    EXPECT_NEAR(lf_footprint_trust(vec2(0.4f, 0.0f), vec2(0.0f, 0.1f), 0.2f), 1.0 / 16.0, 1e-6);
    EXPECT_NEAR(lf_footprint_trust(vec2(0.3f, 0.4f), vec2(0.0f), 0.25f), 1.0 / 16.0, 1e-6);
    // Monotone: a larger change per pixel is trusted less.
    float previous = 1.0f;
    for (float c = 0.05f; c < 2.0f; c += 0.05f) {
        const float w = lf_footprint_trust(vec2(c, 0.0f), vec2(0.0f), 0.3f);
        EXPECT_LE(w, previous);
        previous = w;
    }
}

TEST(GeometricAa, WidensEveryTechniquesLobe) {
    LfParams p = test::shading_test_params(800.0f);
    const vec3 l = normalize(vec3(0.3f, 0.1f, 0.9f));
    const vec3 v = 4.0f * normalize(vec3(-0.3f, -0.1f, 0.9f));  // the mirror direction
    LfMoments m = moments_of(vec2(0.0f), vec3(0.002f, 0.002f, 0.0f),
                             vec4(0.5f, 0.0f, 0.0f, 0.0f));
    m.normal = vec3(0.0f, 0.0f, 0.97f);
    for (int brdf : {LF_BRDF_BLINN_PHONG, LF_BRDF_COOK_TORRANCE}) {
        p.brdf = brdf;
        for (int technique = 0; technique < LF_TECHNIQUE_COUNT; ++technique) {
            LfMoments without = m;
            without.footprint = vec3(0.0f);
            LfMoments with = m;
            with.footprint = vec3(0.004f, 0.004f, 0.0f);
            const float peak0 = lf_shade(technique, without, l, v, p).specular.x;
            const float peak1 = lf_shade(technique, with, l, v, p).specular.x;
            // At the lobe's peak, a wider lobe is lower.
            EXPECT_LT(peak1, 0.95f * peak0) << "technique " << technique << " brdf " << brdf;
            EXPECT_GT(peak1, 0.0f) << "technique " << technique << " brdf " << brdf;
        }
    }
}

}  // namespace
}  // namespace leanfade
