// Toksvig and CLEAN in the shared shading header (shaders/lean_shading.glsl as C++): their
// defining properties, and the fading inputs used by calibration.
#include <gtest/gtest.h>

#include <cmath>

#include "leanfade/core/shading.hpp"
#include "shading_test_params.hpp"

using namespace leanfade::shading;

namespace {

LfParams params(float s) {
    return leanfade::test::shading_test_params(s);
}

// Toksvig 2005: ft = |Na| / (|Na| + s (1 - |Na|)).
TEST(Toksvig, FactorFollowsThePaper) {
    EXPECT_EQ(lf_toksvig_factor(1.0f, 500.0f), 1.0f);
    EXPECT_NEAR(lf_toksvig_factor(0.9f, 100.0f), 0.9 / (0.9 + 100.0 * 0.1), 1e-6);
    EXPECT_EQ(lf_toksvig_factor(1.02f, 500.0f), 1.0f) << "quantisation can make |Na| > 1";
    EXPECT_GT(lf_toksvig_factor(0.0f, 500.0f), 0.0f);
}

// A unit normal (no filtering) gives exactly the baseline's lobe.
TEST(Toksvig, UnitNormalIsTheBaseline) {
    const vec3 n = normalize(vec3(0.2f, -0.1f, 1.0f));
    for (float s : {16.0f, 128.0f, 1024.0f}) {
        for (float a : {0.0f, 0.02f, 0.1f}) {
            const vec3 h = normalize(n + vec3(a, 0.5f * a, 0.0f));
            EXPECT_NEAR(lf_toksvig_lobe(n, h, s), lf_blinn_phong_lobe(n, h, s),
                        1e-5 * lf_blinn_phong_lobe(n, h, s) + 1e-9)
                << "s " << s << " a " << a;
        }
    }
}

// A shorter filtered normal widens the lobe: lower peak, more at an angle, and the energy
// factor keeps the lobe's integral over projected slopes about the same.
TEST(Toksvig, ShortNormalWidensTheLobeAndKeepsItsEnergy) {
    const float s = 256.0f;
    const vec3 n(0.0f, 0.0f, 1.0f);
    const vec3 short_n(0.0f, 0.0f, 0.99f);
    const vec3 h_peak(0.0f, 0.0f, 1.0f);
    const vec3 h_off = normalize(vec3(0.15f, 0.0f, 1.0f));
    EXPECT_LT(lf_toksvig_lobe(short_n, h_peak, s), lf_toksvig_lobe(n, h_peak, s));
    EXPECT_GT(lf_toksvig_lobe(short_n, h_off, s), lf_toksvig_lobe(n, h_off, s));
    // Integral over projected slopes (x, y) with H = normalize(x, y, 1).
    auto integral = [&](const vec3& normal) {
        double sum = 0.0;
        const int steps = 400;
        const double width = 1.5;
        const double cell = (2.0 * width / steps) * (2.0 * width / steps);
        for (int j = 0; j < steps; ++j)
            for (int i = 0; i < steps; ++i) {
                const float x = float(-width + (i + 0.5) * 2.0 * width / steps);
                const float y = float(-width + (j + 0.5) * 2.0 * width / steps);
                sum += lf_toksvig_lobe(normal, normalize(vec3(x, y, 1.0f)), s) * cell;
            }
        return sum;
    };
    const double full = integral(n), widened = integral(short_n);
    EXPECT_NEAR(widened / full, 1.0, 0.05) << full << " " << widened;
}

// CLEAN with a covariance that is isotropic already is LEAN.
TEST(Clean, IsotropicMomentsGiveLean) {
    const float sc = 0.5f;
    const vec2 b(0.1f, -0.05f);
    const float variance = 0.02f;
    // Pack M = B B^T + variance I (docs/math.md §3).
    const vec3 m(b.x * b.x + variance, b.y * b.y + variance, b.x * b.y);
    const vec4 lean1(0.5f * normalize(vec3(b, 1.0f)) * 0.98f + vec3(0.5f),
                     0.5f * m.z / (sc * sc) + 0.5f);
    const vec4 lean2(0.5f * b.x / sc + 0.5f, 0.5f * b.y / sc + 0.5f, m.x / (sc * sc),
                     m.y / (sc * sc));
    const vec3 light = normalize(vec3(-0.3f, 0.4f, 1.0f));
    const vec3 view(0.4f, -0.2f, 3.0f);
    const LfShade lean =
        lf_shade(LF_TECHNIQUE_LEAN, lf_unpack(lean1, lean2, sc, 1.0f), light, view, params(300.0f));
    const LfShade clean = lf_shade(LF_TECHNIQUE_CLEAN, lf_unpack(lean1, lean2, sc, 1.0f), light,
                                   view, params(300.0f));
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(clean.specular[c], lean.specular[c], 1e-4f * lean.specular[c]);
        EXPECT_EQ(clean.diffuse[c], lean.diffuse[c]);
    }
}

// CLEAN keeps LEAN's trace (total variance) but not its anisotropy.
TEST(Clean, KeepsTheTraceAndDropsTheAnisotropy) {
    const vec2 b(0.05f, 0.02f);
    const vec3 second(b.x * b.x + 0.04f, b.y * b.y + 0.01f, b.x * b.y + 0.005f);
    const vec3 lean = lf_covariance(b, second, 0.001f);
    const vec3 clean = lf_clean_covariance(b, second.x + second.y, 0.001f);
    EXPECT_NEAR(clean.x + clean.y, lean.x + lean.y, 1e-6f);
    EXPECT_EQ(clean.x, clean.y);
    EXPECT_EQ(clean.z, 0.0f);
}

// lf_fade_terms gives what lf_shade uses: faded specular = LEAN's x NdotL^(sf - 1).
TEST(FadeTerms, ExplainTheFadedSpecular) {
    const vec4 lean1(0.55f, 0.48f, 0.98f, 0.52f), lean2(0.6f, 0.45f, 0.05f, 0.04f);
    const vec3 light = normalize(vec3(-0.2f, 0.3f, 1.0f));
    const vec3 view(0.3f, 0.1f, 6.0f);
    LfParams p = params(200.0f);
    p.fade = 0.2f;
    p.pmax = 16.0f;
    const LfShade lean =
        lf_shade(LF_TECHNIQUE_LEAN, lf_unpack(lean1, lean2, 0.4f, 1.0f), light, view, p);
    const LfShade fade =
        lf_shade(LF_TECHNIQUE_FADE, lf_unpack(lean1, lean2, 0.4f, 1.0f), light, view, p);
    const vec2 terms = lf_fade_terms(lean1, light, view, p.fade_distance);
    EXPECT_NEAR(terms.y, 6.0f, 1e-6f);
    const float sf = lf_fade_factor(terms.y, p.fade, p.fade_exponent, p.pmax);
    EXPECT_NEAR(fade.specular.x, lean.specular.x * std::pow(terms.x, sf - 1.0f),
                1e-5f * lean.specular.x);
}

}  // namespace
