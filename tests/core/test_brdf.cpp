// The Cook-Torrance lobe stage of the shared shading header (shaders/lean_shading.glsl,
// docs/math.md §9) compiled as C++: its Smith term against the exact Beckmann Lambda, its
// distribution against the closed-form Beckmann D, the white furnace, the bump normal's isotropic
// frame, fading and the parameters that feed it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/shading.hpp"
#include "shading_test_params.hpp"

using namespace leanfade::shading;

namespace {

// Beckmann's exact Smith G1 = 1 / (1 + Lambda(a)), Lambda(a) = (exp(-a^2) / (a sqrt(pi)) -
// erfc(a)) / 2 (Walter et al. 2007 eq. 27's left side).
double exact_g1(double a) {
    const double lambda = 0.5 * (std::exp(-a * a) / (a * std::sqrt(M_PI)) - std::erfc(a));
    return 1.0 / (1.0 + lambda);
}

// Isotropic Beckmann D of roughness alpha at cos(theta_h) = c (Walter et al. 2007 eq. 25).
double beckmann_d(double c, double alpha) {
    const double c2 = c * c, tan2 = (1.0 - c2) / c2;
    return std::exp(-tan2 / (alpha * alpha)) / (M_PI * alpha * alpha * c2 * c2);
}

vec3 direction(double theta_degrees, double phi_degrees) {
    const double t = theta_degrees * M_PI / 180.0, p = phi_degrees * M_PI / 180.0;
    return vec3(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)),
                float(std::cos(t)));
}

// Directional albedo without Fresnel: the integral over light directions l of the lobe times
// l.z, for slopes of mean B and covariance Sigma. Integrated over the half vector h on a grid of
// projected slopes around B (the lobe's support), with dl = 4 (h.v) dh and dh = h.z^3 dslope;
// l = reflect(-v, h).
double albedo(vec3 v, vec2 mean, vec3 sigma) {
    const double spread = std::sqrt(std::max(sigma.x, sigma.y));
    const double range = 9.0 * spread;
    const int steps = 1200;
    const double step = 2.0 * range / steps;
    double sum = 0.0;
    for (int j = 0; j < steps; ++j) {
        for (int i = 0; i < steps; ++i) {
            const double sx = mean.x - range + (i + 0.5) * step;
            const double sy = mean.y - range + (j + 0.5) * step;
            const vec3 h = normalize(vec3(float(sx), float(sy), 1.0f));
            const float h_dot_v = dot(h, v);
            if (h_dot_v <= 0.0f) continue;
            const vec3 l = 2.0f * h_dot_v * h - v;
            if (l.z <= 0.0f) continue;
            const double lobe = lf_cook_torrance_lobe(h, l, v, mean, sigma);
            sum += lobe * l.z * 4.0 * h_dot_v * std::pow(double(h.z), 3.0) * step * step;
        }
    }
    return sum;
}

}  // namespace

// Walter et al.'s rational G1 stays within 0.4% of the exact Beckmann Smith term and is exactly 1
// from a = 1.6 on (where the exact term is above 0.9996).
TEST(CookTorrance, SmithApproximationFollowsTheExactBeckmannTerm) {
    double worst = 0.0;
    for (double a = 0.02; a < 6.0; a += 0.01) {
        const double approx = lf_smith_g1_beckmann(float(a));
        const double exact = exact_g1(a);
        worst = std::max(worst, std::abs(approx - exact) / exact);
        EXPECT_LE(approx, 1.0) << a;
    }
    EXPECT_LT(worst, 4e-3);
    EXPECT_EQ(lf_smith_g1_beckmann(0.0f), 0.0f);
    EXPECT_EQ(lf_smith_g1_beckmann(-0.3f), 0.0f);
    EXPECT_EQ(lf_smith_g1_beckmann(1.6f), 1.0f);
}

// With B = 0 and Sigma = (alpha^2 / 2) I the lobe is the textbook isotropic Beckmann
// D G / (4 (n.l)(n.v)) (Walter et al. 2007 eq. 20, 25, 27 with the exact Lambda).
TEST(CookTorrance, CentredIsotropicLobeIsBeckmannWithSmith) {
    for (const double alpha : {0.1, 0.3, 0.7}) {
        const float variance = float(alpha * alpha / 2.0);
        const vec3 sigma(variance, variance, 0.0f);
        for (const vec3 v : {direction(0, 0), direction(40, 30), direction(75, 200)}) {
            for (const vec3 l : {direction(10, 100), direction(50, 250), direction(70, 20)}) {
                const vec3 h = normalize(l + v);
                const auto g1 = [&](vec3 w) {
                    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - double(w.z) * w.z));
                    return sin_theta < 1e-9 ? 1.0 : exact_g1(w.z / (alpha * sin_theta));
                };
                const double expected =
                    beckmann_d(h.z, alpha) * g1(l) * g1(v) / (4.0 * l.z * v.z);
                const double got = lf_cook_torrance_lobe(h, l, v, vec2(0.0f), sigma);
                EXPECT_NEAR(got, expected, 5e-3 * expected + 1e-6)
                    << "alpha " << alpha << " v.z " << v.z << " l.z " << l.z;
            }
        }
    }
}

// White furnace (F = 1): the directional albedo of the LOD-0 lobe is at most 1. Smith's G counts
// only single scattering, so energy is lost as roughness and the view angle grow (up to ~40% at
// alpha = 1 near grazing view, Heitz 2014); a smooth surface seen head-on keeps almost all of it.
// Tolerance 1%: the numerical integration (a 1200^2 grid over 9 standard deviations: below 1e-3)
// and the 0.4% of the rational G1, which can raise G1 above the exact value.
TEST(CookTorrance, WhiteFurnaceAlbedoIsAtMostOne) {
    for (const double r : {0.2, 0.4, 0.6, 0.8, 1.0}) {
        const double alpha = r * r;
        const float variance = float(alpha * alpha / 2.0);
        const vec3 sigma(variance, variance, 0.0f);
        for (const double theta : {0.0, 30.0, 60.0, 80.0}) {
            const double a = albedo(direction(theta, 35.0), vec2(0.0f), sigma);
            std::printf("r %.1f, view %2.0f deg: albedo %.4f\n", r, theta, a);
            EXPECT_LE(a, 1.01) << "r " << r << " view " << theta;
            // Single scattering keeps most of the light (about 0.46 at alpha = 1 seen head-on,
            // where 37 % of the facets send it below the horizon).
            EXPECT_GT(a, 0.4) << "r " << r << " view " << theta;
            if (r <= 0.4 && theta <= 30.0) {
                EXPECT_GT(a, 0.99) << "r " << r;
            }
        }
    }
}

// The same with a tilted mean B and an anisotropic, correlated Sigma (a LEAN texel of a coarser
// level): the sheared frame keeps the albedo at or below 1 as well, and near 1 for a smooth
// surface seen along its mean normal.
TEST(CookTorrance, WhiteFurnaceHoldsForTiltedAnisotropicSlopes) {
    const vec2 mean(0.25f, -0.15f);
    const vec3 mean_normal = normalize(vec3(mean.x, mean.y, 1.0f));
    for (const vec3 sigma : {vec3(0.004f, 0.002f, 0.001f), vec3(0.06f, 0.02f, -0.015f)}) {
        for (const vec3 v : {mean_normal, direction(40, 60), direction(70, 210)}) {
            const double a = albedo(v, mean, sigma);
            std::printf("tilted, Sxx %.3f, v.z %.3f: albedo %.4f\n", sigma.x, v.z, a);
            EXPECT_LE(a, 1.01) << "Sxx " << sigma.x << " v.z " << v.z;
            // At grazing views much of the light leaves below the tangent plane.
            EXPECT_GT(a, 0.2) << "Sxx " << sigma.x << " v.z " << v.z;
        }
    }
    // A smooth tilted surface seen along its mean normal: a tilted mirror.
    EXPECT_GT(albedo(mean_normal, mean, vec3(0.004f, 0.002f, 0.001f)), 0.97);
}

// The bump normal's lobe (lf_cook_torrance_isotropic) equals the centred lobe evaluated with the
// directions rotated so that the bump normal becomes +z.
TEST(CookTorrance, IsotropicLobeAroundABumpNormalIsTheRotatedCentredLobe) {
    const vec3 n = normalize(vec3(0.3f, -0.2f, 1.0f));
    // Rotation taking n to +z (Rodrigues about n x z).
    const vec3 axis = normalize(cross(n, vec3(0.0f, 0.0f, 1.0f)));
    const float angle = std::acos(n.z);
    const auto rotate = [&](vec3 w) {
        return w * std::cos(angle) + cross(axis, w) * std::sin(angle) +
               axis * dot(axis, w) * (1.0f - std::cos(angle));
    };
    ASSERT_NEAR(rotate(n).z, 1.0f, 1e-6f);
    const float alpha_squared = 0.05f;
    const vec3 sigma(0.5f * alpha_squared, 0.5f * alpha_squared, 0.0f);
    for (const vec3 l : {direction(20, 10), direction(55, 140)}) {
        for (const vec3 v : {direction(5, 300), direction(45, 80)}) {
            const vec3 h = normalize(l + v);
            const double around_n = lf_cook_torrance_isotropic(n, h, l, v, alpha_squared);
            const double rotated =
                lf_cook_torrance_lobe(rotate(h), rotate(l), rotate(v), vec2(0.0f), sigma);
            EXPECT_NEAR(around_n, rotated, 1e-4 * rotated + 1e-7);
        }
    }
}

// Schlick's F on h.v: F0 at normal incidence, 1 at grazing, per channel.
TEST(CookTorrance, SchlickFresnelSpansF0ToOne) {
    const vec3 f0(0.04f, 0.5f, 0.9f);
    const vec3 h(0.0f, 0.0f, 1.0f);
    const vec3 head_on = lf_fresnel_schlick(h, h, f0);
    const vec3 grazing = lf_fresnel_schlick(h, vec3(1.0f, 0.0f, 0.0f), f0);
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(head_on[c], f0[c]);
        EXPECT_FLOAT_EQ(grazing[c], 1.0f);
    }
    const vec3 mid = lf_fresnel_schlick(h, normalize(vec3(1.0f, 0.0f, 1.0f)), f0);
    const float c = 1.0f - std::sqrt(0.5f);
    EXPECT_NEAR(mid.x, 0.04f + 0.96f * std::pow(c, 5.0f), 1e-6f);
}

// Fade = 0 (or Pmax = 1) leaves every pixel of the Cook-Torrance LEAN lobe exactly as it is.
TEST(CookTorrance, FadeZeroIsExactlyLean) {
    LfParams p = leanfade::test::shading_test_params(300.0f);
    p.brdf = LF_BRDF_COOK_TORRANCE;
    p.inv_s_shading = 0.5f * std::pow(0.3f, 4.0f);
    const vec4 lean1(0.55f, 0.48f, 0.99f, 0.51f), lean2(0.56f, 0.47f, 0.02f, 0.03f);
    // Near the mirror direction of the map's mean slope B = (0.06, -0.03) seen from above.
    const vec3 l = normalize(vec3(0.05f, -0.09f, 1.0f));
    for (const float fade : {0.0f, 0.7f}) {
        p.fade = fade;
        p.pmax = fade == 0.0f ? 8.0f : 1.0f;
        for (const vec3 view : {vec3(0.2f, 0.1f, 3.0f), vec3(-2.0f, 1.0f, 0.5f)}) {
            const LfShade lean =
                lf_shade(LF_TECHNIQUE_LEAN, lf_unpack(lean1, lean2, 0.5f, 1.0f), l, view, p);
            const LfShade fade_shade =
                lf_shade(LF_TECHNIQUE_FADE, lf_unpack(lean1, lean2, 0.5f, 1.0f), l, view, p);
            if (view.z > 1.0f) {
                EXPECT_GT(lean.specular.x, 1e-3f);
            }
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(fade_shade.specular[c], lean.specular[c]);
                EXPECT_EQ(fade_shade.diffuse[c], lean.diffuse[c]);
            }
        }
    }
    // Fading on lowers the specular term by NdotL^(sf - 1) and leaves the diffuse term.
    p.fade = 0.5f;
    p.pmax = 8.0f;
    const vec3 view(0.2f, 0.1f, 3.0f);
    const LfMoments m = lf_unpack(lean1, lean2, 0.5f, 1.0f);
    const LfShade lean = lf_shade(LF_TECHNIQUE_LEAN, m, l, view, p);
    const LfShade faded = lf_shade(LF_TECHNIQUE_FADE, m, l, view, p);
    const float sf = lf_fade_factor(view.z, p.fade, p.fade_exponent, p.pmax);
    const float n_dot_l = clamp(dot(m.normal, l), 0.0f, 1.0f);
    EXPECT_NEAR(faded.specular.x, lean.specular.x * std::pow(n_dot_l, sf - 1.0f),
                1e-5f * lean.specular.x);
    EXPECT_EQ(faded.diffuse.x, lean.diffuse.x);
}

// At the finest level of a flat map (B = 0, M = 0), LEAN, CLEAN and the baseline agree under
// Cook-Torrance: the same Beckmann lobe of alpha0 around the same normal; Toksvig too (a unit
// normal adds no variance).
TEST(CookTorrance, TechniquesAgreeOnAFlatFinestLevel) {
    LfParams p = leanfade::test::shading_test_params(300.0f);
    p.brdf = LF_BRDF_COOK_TORRANCE;
    p.inv_s_shading = 0.5f * std::pow(0.35f, 4.0f);
    const vec4 lean1(0.5f, 0.5f, 1.0f, 0.5f), lean2(0.5f, 0.5f, 0.0f, 0.0f);
    const LfMoments m = lf_unpack(lean1, lean2, 1.0f, 1.0f);
    const vec3 l = normalize(vec3(0.3f, 0.2f, 0.9f));
    for (const vec3 view : {vec3(-0.25f, -0.2f, 1.0f), vec3(-1.0f, 0.5f, 0.7f)}) {
        const float lean = lf_shade(LF_TECHNIQUE_LEAN, m, l, view, p).specular.x;
        EXPECT_GT(lean, 0.0f);
        for (const int t : {LF_TECHNIQUE_BUMP, LF_TECHNIQUE_CLEAN, LF_TECHNIQUE_TOKSVIG})
            EXPECT_NEAR(lf_shade(t, m, l, view, p).specular.x, lean, 1e-4f * lean) << t;
        // Blinn-Phong is another model: its value differs.
        LfParams bp = p;
        bp.brdf = LF_BRDF_BLINN_PHONG;
        EXPECT_GT(std::abs(lf_shade(LF_TECHNIQUE_LEAN, m, l, view, bp).specular.x - lean),
                  1e-3f * lean);
    }
}

// The settings that feed the lobe: a0 = r^2 and variance a0^2 / 2, F0 from metallic and Kd, the
// diffuse part of a metal gone, and a map with baked roughness refused.
TEST(CookTorrance, SettingsBecomeShaderParameters) {
    leanfade::ShadingSettings s;
    const LfParams blinn = leanfade::to_lf_params(s, false);
    EXPECT_EQ(blinn.brdf, LF_BRDF_BLINN_PHONG);
    EXPECT_FLOAT_EQ(blinn.inv_s_shading, 1.0f / s.shininess);

    s.brdf = leanfade::Brdf::CookTorrance;
    s.roughness = 0.5f;
    s.metallic = 0.0f;
    s.f0 = 0.05f;
    LfParams p = leanfade::to_lf_params(s, false);
    EXPECT_EQ(p.brdf, LF_BRDF_COOK_TORRANCE);
    EXPECT_FLOAT_EQ(p.inv_s_shading, 0.5f * 0.0625f);  // a0 = 0.25, a0^2 / 2
    EXPECT_EQ(p.f0, vec3(0.05f));
    EXPECT_EQ(p.kd, s.kd);

    s.metallic = 1.0f;
    p = leanfade::to_lf_params(s, false);
    EXPECT_EQ(p.f0, s.kd);
    EXPECT_EQ(p.kd, vec3(0.0f));

    EXPECT_THROW(leanfade::to_lf_params(s, true), leanfade::Error);
    try {
        leanfade::to_lf_params(s, true);
    } catch (const leanfade::Error& e) {
        EXPECT_NE(std::string(e.what()).find("brdf"), std::string::npos) << e.what();
    }
}

// The shader's engine texel (lf_roughness_mip_texel, used by the technique "roughness") is the
// texel `leanfade bake --roughness-out` writes: the core's roughness MIPs rounded to 8 bits, at
// every level of a baked map.
TEST(RoughnessMips, ShaderTexelIsTheBakedTexel) {
    using namespace leanfade;
    BakeOptions options;
    options.strength = 0.8f;
    const LeanMap map = bake_lean_map(make_builtin_height("bumps", 32, 5), BakeSource::Height,
                                      options)
                            .map;
    const PackedLeanMap packed = pack_lean_map(map, Storage::Float32, "test");
    RoughnessOptions ro;
    ro.base_roughness = 0.35f;
    const std::vector<RoughnessLevel> levels = roughness_mips(map, ro);
    const float alpha0_squared = std::pow(0.35f, 4.0f);
    int texels = 0, equal = 0;
    for (std::size_t l = 0; l < levels.size(); ++l) {
        for (int y = 0; y < levels[l].height; ++y) {
            for (int x = 0; x < levels[l].width; ++x) {
                const vec4 texel =
                    lf_roughness_mip_texel(fetch_packed_texel(packed, int(l), 0, x, y),
                                           fetch_packed_texel(packed, int(l), 1, x, y),
                                           packed.scale, lean_offset(packed.encoding), alpha0_squared);
                const std::size_t t = std::size_t(y * levels[l].width + x);
                const float r = std::sqrt(levels[l].alpha[t]);
                const vec3 n = levels[l].normal[t];
                const vec4 want(0.5f * n.x + 0.5f, 0.5f * n.y + 0.5f, 0.5f * n.z + 0.5f, r);
                for (int c = 0; c < 4; ++c) {
                    const float expected = std::round(want[c] * 255.0f) / 255.0f;
                    // One step where the two float paths round on either side of a half.
                    EXPECT_NEAR(texel[c], expected, 1.0f / 255.0f + 1e-6f) << l << " " << c;
                    equal += texel[c] == expected;
                }
                ++texels;
            }
        }
    }
    EXPECT_GE(equal, 4 * texels * 99 / 100);
    // Coarse levels are rougher than the base: the bumps' slope variance is folded in.
    EXPECT_GT(std::sqrt(levels.back().alpha[0]), 0.35f + 0.05f);
}
