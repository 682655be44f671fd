// The shared shading header (shaders/lean_shading.glsl) compiled as C++.
#include <gtest/gtest.h>

#include <cmath>

#include "leanfade/core/shading.hpp"
#include "shading_test_params.hpp"

using namespace leanfade::shading;

namespace {

LfParams default_params(float s) {
    return leanfade::test::shading_test_params(s);
}

// Relative L1 distance between the LEAN lobe (Sigma = I/s, mean b) and normalised Blinn-Phong on
// the normal n = normalize(b, 1), over half vectors on a grid of projected slopes around b.
double lobe_mismatch(vec2 b, float s) {
    const vec3 n = normalize(vec3(b.x, b.y, 1.0f));
    const vec3 sigma = vec3(1.0f / s, 1.0f / s, 0.0f);
    const double width = 6.0 / std::sqrt(double(s));
    double diff = 0.0, total = 0.0;
    const int steps = 200;
    for (int j = 0; j < steps; ++j)
        for (int i = 0; i < steps; ++i) {
            const vec2 slope = b + vec2(float(width * (2.0 * i / steps - 1.0)),
                                        float(width * (2.0 * j / steps - 1.0)));
            const vec3 h = normalize(vec3(slope.x, slope.y, 1.0f));
            const double lean = lf_lean_lobe(h, b, sigma);
            const double bp = lf_blinn_phong_lobe(n, h, s);
            diff += std::abs(lean - bp);
            total += bp;
        }
    return diff / total;
}

}  // namespace

TEST(Shading, LeanLobeWithRoughnessOnlyMatchesNormalisedBlinnPhong) {
    for (vec2 b : {vec2(0.0f), vec2(0.1f, -0.05f)}) {
        const double e64 = lobe_mismatch(b, 64), e256 = lobe_mismatch(b, 256),
                     e4096 = lobe_mismatch(b, 4096);
        EXPECT_LT(e256, e64) << b.x;
        EXPECT_LT(e4096, e256) << b.x;
        EXPECT_LT(e4096, 0.03) << b.x;
    }
    // Peaks agree exactly: s / (2 pi) at H = n.
    const vec3 n = normalize(vec3(0.1f, -0.05f, 1.0f));
    EXPECT_NEAR(lf_lean_lobe(n, vec2(0.1f, -0.05f), vec3(1 / 128.0f, 1 / 128.0f, 0)),
                128 / (2 * LF_PI), 1e-3);
    EXPECT_NEAR(lf_blinn_phong_lobe(n, n, 128.0f), 128 / (2 * LF_PI), 1e-3);
}

TEST(Shading, LeanLobeIsANormalisedGaussianOverSlopes) {
    // The errata normalisation 1/(2 pi sqrt(det)) integrates to 1 over the slope plane.
    const vec2 mean(0.2f, -0.1f);
    const vec3 sigma(0.02f, 0.01f, 0.005f);
    double integral = 0.0;
    const double range = 1.5, step = 0.005;
    for (double y = -range; y < range; y += step)
        for (double x = -range; x < range; x += step) {
            const vec3 h = normalize(vec3(float(x), float(y), 1.0f));
            integral += lf_lean_lobe(h, mean, sigma) * step * step;
        }
    EXPECT_NEAR(integral, 1.0, 1e-3);
}

TEST(Shading, FadeZeroIsExactlyLean) {
    LfParams p = default_params(300.0f);
    const vec4 lean1(0.55f, 0.45f, 0.98f, 0.51f), lean2(0.6f, 0.4f, 0.08f, 0.05f);
    const vec3 l = normalize(vec3(0.3f, 0.4f, 0.8f));
    for (float d : {0.5f, 3.0f, 50.0f, 400.0f}) {
        const vec3 v = d * normalize(vec3(-0.2f, 0.1f, 0.9f));
        const LfShade lean =
            lf_shade(LF_TECHNIQUE_LEAN, lf_unpack(lean1, lean2, 0.7f, 1.0f), l, v, p);
        const LfShade fade =
            lf_shade(LF_TECHNIQUE_FADE, lf_unpack(lean1, lean2, 0.7f, 1.0f), l, v, p);
        EXPECT_EQ(lean.specular, fade.specular);
        EXPECT_EQ(lean.diffuse, fade.diffuse);
    }
}

TEST(Shading, FadingOnlyLowersSpecularAndKeepsDiffuse) {
    LfParams p = default_params(300.0f);
    p.fade = 0.05f;
    const vec4 lean1(0.52f, 0.49f, 0.99f, 0.5f), lean2(0.52f, 0.49f, 0.05f, 0.05f);
    const vec3 l = normalize(vec3(0.2f, 0.1f, 0.95f));
    float previous = 1e30f;
    for (float d : {1.0f, 10.0f, 30.0f, 100.0f}) {
        const vec3 v = d * normalize(vec3(-0.1f, 0.0f, 1.0f));
        const LfShade lean =
            lf_shade(LF_TECHNIQUE_LEAN, lf_unpack(lean1, lean2, 0.5f, 1.0f), l, v, p);
        const LfShade fade =
            lf_shade(LF_TECHNIQUE_FADE, lf_unpack(lean1, lean2, 0.5f, 1.0f), l, v, p);
        EXPECT_EQ(lean.diffuse, fade.diffuse);
        EXPECT_LE(fade.specular.x, lean.specular.x);
        const float ratio = fade.specular.x / lean.specular.x;
        EXPECT_LT(ratio, previous);
        previous = ratio;
    }
}

TEST(Shading, FadeFactorObeysItsClamps) {
    EXPECT_EQ(lf_fade_factor(0.0f, 1.0f, 2.0f, 10.0f), 1.0f);
    EXPECT_EQ(lf_fade_factor(5.0f, 0.0f, 2.0f, 10.0f), 1.0f);
    EXPECT_FLOAT_EQ(lf_fade_factor(2.0f, 0.5f, 2.0f, 10.0f), 2.0f);   // 1 + (2 * 0.5)^2
    EXPECT_FLOAT_EQ(lf_fade_factor(2.0f, 1.0f, 3.0f, 100.0f), 9.0f);  // 1 + 2^3
    EXPECT_EQ(lf_fade_factor(1000.0f, 1.0f, 2.0f, 6.0f), 6.0f);       // Pmax
    EXPECT_EQ(lf_fade_factor(1000.0f, 1.0f, 2.0f, 0.5f), 1.0f);       // Pmax < 1 acts as 1
    EXPECT_EQ(lf_fade_factor(-4.0f, 1.0f, 2.0f, 6.0f), 1.0f);         // behind the plane
    float previous = 0.0f;
    for (float d = 0.0f; d < 50.0f; d += 0.5f) {
        const float sf = lf_fade_factor(d, 0.1f, 2.0f, 20.0f);
        EXPECT_GE(sf, previous);
        EXPECT_GE(sf, 1.0f);
        EXPECT_LE(sf, 20.0f);
        previous = sf;
    }
}

TEST(Shading, FadeDistanceModes) {
    const vec3 vt(3.0f, 4.0f, 12.0f);
    EXPECT_EQ(lf_fade_distance(vt, LF_FADE_DISTANCE_TANGENT_Z), 12.0f);
    EXPECT_EQ(lf_fade_distance(vt, LF_FADE_DISTANCE_EYE), 13.0f);
}

TEST(Shading, FogFactorsFollowTheLectureFormulas) {
    EXPECT_EQ(lf_fog_factor(7.0f, LF_FOG_NONE, 0, 10, 1), 1.0f);
    EXPECT_FLOAT_EQ(lf_fog_factor(7.0f, LF_FOG_LINEAR, 2.0f, 12.0f, 0), 0.5f);
    EXPECT_EQ(lf_fog_factor(20.0f, LF_FOG_LINEAR, 2.0f, 12.0f, 0), 0.0f);
    EXPECT_FLOAT_EQ(lf_fog_factor(2.0f, LF_FOG_EXP, 0, 0, 0.3f), std::exp(-0.6f));
    EXPECT_FLOAT_EQ(lf_fog_factor(2.0f, LF_FOG_EXP2, 0, 0, 0.3f), std::exp(-0.36f));
    const vec3 c = lf_apply_fog(vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f), 0.25f);
    EXPECT_FLOAT_EQ(c.x, 0.25f);
    EXPECT_FLOAT_EQ(c.z, 0.75f);
}

TEST(Shading, FresnelIsClampedSchlick) {
    const vec3 n(0, 0, 1);
    EXPECT_FLOAT_EQ(lf_fresnel(n, n, 0.1f, 0.9f), 0.1f);
    EXPECT_FLOAT_EQ(lf_fresnel(n, vec3(1, 0, 0), 0.1f, 0.9f), 1.0f);
    EXPECT_EQ(lf_fresnel(n, vec3(1, 0, 0), 0.5f, 0.9f), 1.0f);
}

// The same moments in both encodings (offset 1: s = 0.5 v + 0.5; offset 0: s = v) unpack alike.
TEST(Shading, UnpackDecodesTheOffsetAndTheSignedEncodingAlike) {
    const vec3 n(0.25f, -0.5f, 0.8125f);
    const vec2 b_over_sc(0.375f, -0.75f);
    const float mxy_over_sc2 = -0.125f, sc = 2.0f;
    const LfMoments offset = lf_unpack(vec4(0.5f * n + vec3(0.5f), 0.5f * mxy_over_sc2 + 0.5f),
                                       vec4(0.5f * b_over_sc + vec2(0.5f), 0.5f, 0.25f), sc, 1.0f);
    const LfMoments signed_values =
        lf_unpack(vec4(n, mxy_over_sc2), vec4(b_over_sc, 0.5f, 0.25f), sc, 0.0f);
    EXPECT_EQ(offset.normal, n);
    EXPECT_EQ(signed_values.normal, n);
    EXPECT_EQ(offset.mean, b_over_sc * sc);
    EXPECT_EQ(signed_values.mean, b_over_sc * sc);
    EXPECT_EQ(offset.second, vec3(2.0f, 1.0f, -0.5f));
    EXPECT_EQ(signed_values.second, vec3(2.0f, 1.0f, -0.5f));
}

TEST(Shading, UnpackAppliesScaleFactor) {
    const LfMoments m =
        lf_unpack(vec4(0.5f, 0.5f, 1.0f, 0.75f), vec4(1.0f, 0.25f, 0.5f, 0.25f), 2.0f, 1.0f);
    EXPECT_EQ(m.normal, vec3(0, 0, 1));
    EXPECT_EQ(m.mean, vec2(2.0f, -1.0f));
    EXPECT_EQ(m.second, vec3(2.0f, 1.0f, 2.0f));
}
