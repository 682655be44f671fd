// The fade-calibration model and fit on synthetic samples (no GL): the model is fading paper
// eq. 6-7, the fit recovers known parameters, the targets follow their definitions.
#include <gtest/gtest.h>

#include <cmath>

#include "leanfade/core/error.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/eval/calibration.hpp"

namespace leanfade::eval {
namespace {

// Pixels of a highlight at camera distance `d`: NdotL between 0.6 and 1, the fading distance
// (tangent z) between 0.5 d and d, specular weights varying.
FadeSamples synthetic(float d) {
    FadeSamples s;
    s.camera_distance = d;
    for (int i = 0; i < 200; ++i) {
        const float t = float(i) / 199.0f;
        s.specular.push_back(0.2f + std::sin(7.0f * t) * std::sin(7.0f * t));
        s.n_dot_l.push_back(0.6f + 0.4f * t);
        s.fade_distance.push_back(d * (0.5f + 0.5f * std::fmod(3.7f * t, 1.0f)));
    }
    return s;
}

TEST(FadeModel, FadeZeroIsExactlyLean) {
    const FadeSamples s = synthetic(10.0f);
    EXPECT_EQ(fade_energy_ratio(s, 0.0f, 16.0f, 2.0f), 1.0);
    EXPECT_EQ(fade_energy_ratio(FadeSamples{}, 0.3f, 16.0f, 2.0f), 1.0) << "no energy";
}

TEST(FadeModel, IsEquationSevenPixelByPixel) {
    FadeSamples one;
    one.specular = {2.0f};
    one.n_dot_l = {0.8f};
    one.fade_distance = {5.0f};
    const float sf = shading::lf_fade_factor(5.0f, 0.3f, 2.0f, 16.0f);  // 1 + 1.5^2 = 3.25
    EXPECT_NEAR(sf, 3.25f, 1e-6f);
    EXPECT_NEAR(fade_energy_ratio(one, 0.3f, 16.0f, 2.0f), std::pow(0.8, 2.25), 1e-6);
    // Pmax clamps sf: with Pmax 2 the ratio is NdotL^(2 - 1).
    EXPECT_NEAR(fade_energy_ratio(one, 0.3f, 2.0f, 2.0f), 0.8, 1e-6);
}

TEST(FadeModel, RatioFallsWithFadeAndDistance) {
    double previous = 1.0;
    for (float fade : {0.01f, 0.05f, 0.1f, 0.2f, 0.5f}) {
        const double r = fade_energy_ratio(synthetic(8.0f), fade, 1000.0f, 2.0f);
        EXPECT_LT(r, previous) << "Fade " << fade;
        previous = r;
    }
    previous = 1.0;
    for (float d : {2.0f, 4.0f, 8.0f, 16.0f}) {
        const double r = fade_energy_ratio(synthetic(d), 0.1f, 1000.0f, 2.0f);
        EXPECT_LT(r, previous) << "distance " << d;
        previous = r;
    }
}

TEST(FadeFitTest, RecoversAKnownFade) {
    std::vector<FadeSamples> samples;
    std::vector<double> target;
    for (float d : {2.0f, 4.0f, 8.0f, 16.0f, 32.0f}) {
        samples.push_back(synthetic(d));
        target.push_back(fade_energy_ratio(samples.back(), 0.07f, 16.0f, 2.0f));
    }
    FadeFitOptions options;
    options.pmax = 16.0f;
    const FadeFit fit = fit_fade(samples, target, options);
    EXPECT_NEAR(fit.fade, 0.07f, 0.07f * 1e-3f);
    EXPECT_EQ(fit.pmax, 16.0f);
    EXPECT_LT(fit.residual, 1e-6);
    ASSERT_EQ(fit.model.size(), target.size());
}

TEST(FadeFitTest, RecoversFadeAndPmax) {
    std::vector<FadeSamples> samples;
    std::vector<double> target;
    for (float d : {1.5f, 3.0f, 6.0f, 12.0f, 24.0f, 48.0f, 96.0f}) {
        samples.push_back(synthetic(d));
        target.push_back(fade_energy_ratio(samples.back(), 0.12f, 6.0f, 2.0f));
    }
    FadeFitOptions options;
    options.fit_pmax = true;
    const FadeFit fit = fit_fade(samples, target, options);
    EXPECT_NEAR(fit.fade, 0.12f, 0.12f * 0.01f);
    EXPECT_NEAR(fit.pmax, 6.0f, 6.0f * 0.01f);
    EXPECT_LT(fit.residual, 1e-4);
}

TEST(FadeFitTest, NoAttenuationGivesFadeZero) {
    std::vector<FadeSamples> samples{synthetic(2.0f), synthetic(20.0f)};
    const FadeFit fit = fit_fade(samples, {1.0, 1.0}, FadeFitOptions{});
    EXPECT_EQ(fit.fade, 0.0f);
    EXPECT_EQ(fit.residual, 0.0);
}

TEST(FadeFitTest, RejectsMismatchedSizes) {
    EXPECT_THROW(fit_fade({synthetic(2.0f)}, {1.0, 0.5}, FadeFitOptions{}), Error);
    EXPECT_THROW(fit_fade({}, {}, FadeFitOptions{}), Error);
}

TEST(FadeTargets, ParseAndEvaluate) {
    const FadeTarget e = parse_fade_target("exp:0.05");
    EXPECT_EQ(e.kind, FadeTarget::Kind::Exponential);
    EXPECT_FLOAT_EQ(e.sigma, 0.05f);
    EXPECT_EQ(to_string(e), "exp:0.05");
    const std::vector<double> v = target_attenuation(e, {2.0f, 20.0f}, ShadingSettings{});
    EXPECT_NEAR(v[0], std::exp(-0.1), 1e-6);
    EXPECT_NEAR(v[1], std::exp(-1.0), 1e-6);

    EXPECT_EQ(parse_fade_target("fog").kind, FadeTarget::Kind::Fog);
    EXPECT_THROW(target_attenuation(parse_fade_target("fog"), {2.0f}, ShadingSettings{}), Error)
        << "fog without fog";
    ShadingSettings fog;
    fog.fog = FogMode::Exp;
    fog.fog_density = 0.04f;
    const std::vector<double> f = target_attenuation(parse_fade_target("fog"), {10.0f}, fog);
    EXPECT_NEAR(f[0], std::exp(-0.4), 1e-6);

    const FadeTarget truth = parse_fade_target("reference");
    EXPECT_EQ(truth.kind, FadeTarget::Kind::Reference);
    EXPECT_EQ(to_string(truth), "reference");
    EXPECT_THROW(target_attenuation(truth, {2.0f}, ShadingSettings{}), Error)
        << "the truth is measured by rendering";

    for (const char* bad : {"exp:", "exp:-1", "exp:abc", "exp:inf", "linear", ""}) {
        try {
            parse_fade_target(bad, "--target");
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const Error& error) {
            EXPECT_EQ(error.file(), "--target") << bad;
        }
    }
}

}  // namespace
}  // namespace leanfade::eval
