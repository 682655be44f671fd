// The supersampled truth for each BRDF and reference model (docs/math.md §7, §9), on the GPU:
// - on a constant LEAN map every MIP level is the same, so the truth with LEAN's own model
//   (LEAN's lobe at LOD 0, supersampled) must equal the LEAN technique's image up to the box
//   filter of the supersampling, and the baseline truth the baseline's image;
// - on bumps, the two truths differ (LEAN's model mismatch), and the Cook-Torrance truth differs
//   from the Blinn-Phong one.
#include <cmath>

#include "gl_test_helpers.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::test {
namespace {

class ReferenceModels : public GlTest {
  protected:
    Image render(gl::Renderer& renderer, gl::Technique technique, const ShadingSettings& s,
                 int k = 4) {
        gl::RenderRequest r;
        r.technique = technique;
        r.width = 64;
        r.height = 48;
        r.view = gl::view_at_distance(2.4f, 40.0f, {0.3f, -0.2f, 1.0f});
        r.settings = s;
        r.output = gl::OutputMode::Specular;
        r.reference_samples = k;
        return renderer.render(r);
    }
};

// Mean relative difference over the pixels inside the quad (both images non-zero there), away
// from its edge where the supersampled image blends with the background.
double interior_difference(const Image& a, const Image& b) {
    double diff = 0.0, total = 0.0;
    for (int y = 4; y < a.height - 4; ++y)
        for (int x = 4; x < a.width - 4; ++x) {
            if (a.at(x, y, 0) <= 0.0f || b.at(x, y, 0) <= 0.0f) continue;
            bool interior = true;
            for (int dy = -2; dy <= 2 && interior; ++dy)
                for (int dx = -2; dx <= 2; ++dx)
                    if (b.at(x + dx, y + dy, 0) <= 0.0f) interior = false;
            if (!interior) continue;
            for (int c = 0; c < 3; ++c) {
                diff += std::abs(double(a.at(x, y, c)) - b.at(x, y, c));
                total += std::abs(double(b.at(x, y, c)));
            }
        }
    return total > 0.0 ? diff / total : 1.0;
}

// Tolerance 2%: the truth box-filters k x k samples of a smoothly varying specular term (the view
// and light directions change across a pixel), the technique shades the pixel centre once; with a
// lobe of roughness 0.45 / s = 64 spanning many pixels the difference is a fraction of a percent.
TEST_F(ReferenceModels, OnAConstantMapEachTruthIsItsTechnique) {
    gl::Renderer renderer(context());
    const scene::Mesh quad = make_test_quad();
    renderer.set_mesh(quad);
    renderer.set_lean_map(make_constant_lean_map({0.12f, -0.07f}, {0.010f, 0.018f, 0.004f}, 0.97f,
                                                 Storage::Float32));
    for (const Brdf brdf : {Brdf::BlinnPhong, Brdf::CookTorrance}) {
        ShadingSettings s;
        s.light_direction = {-0.4f, 0.5f, 0.8f};
        s.shininess = 64.0f;
        s.brdf = brdf;
        s.roughness = 0.45f;
        s.reference_model = ReferenceModel::Lean;
        const Image lean_truth = render(renderer, gl::Technique::Reference, s);
        const Image lean = render(renderer, gl::Technique::Lean, s);
        s.reference_model = ReferenceModel::Baseline;
        const Image baseline_truth = render(renderer, gl::Technique::Reference, s);
        const Image bump = render(renderer, gl::Technique::Bump, s);
        ASSERT_GT(image_sum(lean), 1.0);
        const double lean_error = interior_difference(lean_truth, lean);
        const double bump_error = interior_difference(baseline_truth, bump);
        const double between = interior_difference(lean_truth, baseline_truth);
        std::printf("%s: |lean truth - lean| %.4f, |baseline truth - bump| %.4f, between %.4f\n",
                    to_string(brdf), lean_error, bump_error, between);
        EXPECT_LT(lean_error, 0.02) << to_string(brdf);
        EXPECT_LT(bump_error, 0.02) << to_string(brdf);
        // This map's LEAN lobe has the texel's slope variance, the baseline only the base
        // roughness around the filtered normal: the two truths must differ by far more.
        EXPECT_GT(between, 0.1) << to_string(brdf);
    }
}

// On bumps the two truths differ (the model mismatch of docs/math.md §7), and each BRDF gives its
// own truth; the Cook-Torrance truth of the baseline is lit where the Blinn-Phong one is.
TEST_F(ReferenceModels, OnBumpsTheTruthsDifferByModelAndBrdf) {
    gl::Renderer renderer(context());
    renderer.set_mesh(scene::make_scene_mesh("sphere"));
    renderer.set_lean_map(make_bumps_map(128));
    ShadingSettings s;
    s.shininess = 256.0f;
    s.roughness = std::pow(2.0f / (256.0f + 2.0f), 0.25f);  // a0^2 = 2 / (s + 2)
    const auto truth = [&](Brdf brdf, ReferenceModel model) {
        ShadingSettings t = s;
        t.brdf = brdf;
        t.reference_model = model;
        gl::RenderRequest request;
        request.technique = gl::Technique::Reference;
        request.width = 48;
        request.height = 48;
        request.view = gl::view_at_distance(4.0f);
        request.settings = t;
        request.output = gl::OutputMode::Specular;
        request.reference_samples = 4;
        return renderer.render(request);
    };
    const Image bp = truth(Brdf::BlinnPhong, ReferenceModel::Baseline);
    const Image bp_lean = truth(Brdf::BlinnPhong, ReferenceModel::Lean);
    const Image ct = truth(Brdf::CookTorrance, ReferenceModel::Baseline);
    const Image ct_lean = truth(Brdf::CookTorrance, ReferenceModel::Lean);
    for (const Image* image : {&bp, &bp_lean, &ct, &ct_lean}) ASSERT_GT(image_sum(*image), 1.0);
    const double model_bp = relative_l1(bp_lean, bp), model_ct = relative_l1(ct_lean, ct);
    const double brdf_gap = relative_l1(ct, bp);
    std::printf("model mismatch: blinn-phong %.4f, cook-torrance %.4f; brdf gap %.4f\n", model_bp,
                model_ct, brdf_gap);
    EXPECT_GT(model_bp, 1e-3);
    EXPECT_GT(model_ct, 1e-3);
    EXPECT_GT(brdf_gap, 1e-2);
    // Same lobe width (a0^2 = 2 / (s + 2)): the same highlights in the same places. Their
    // energies differ by the models' scales (Cook-Torrance's F0 = 0.04 and 1 / (4 n.v) against
    // Blinn-Phong's Fresnel 0.2 + 0.8 (1 - n.v)^5), so the shapes are compared at equal energy.
    Image ct_scaled = ct;
    const double scale = image_sum(bp) / image_sum(ct);
    for (float& v : ct_scaled.pixels) v = float(v * scale);
    const double shape = relative_l1(ct_scaled, bp);
    std::printf("energy ratio cook-torrance / blinn-phong %.4f, shape difference %.4f\n",
                1.0 / scale, shape);
    EXPECT_LT(shape, 0.05);  // 0.008 measured on llvmpipe
}

}  // namespace
}  // namespace leanfade::test
