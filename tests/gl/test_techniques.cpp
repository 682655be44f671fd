// Properties of the techniques on a bumpy object: LEAN equals the baseline at the finest level,
// Fade = 0 is LEAN, fading only lowers the specular term at distance, the reference converges,
// and MSAA / anisotropic filtering / tiled references render without GL errors.
#include <cmath>

#include "gl_test_helpers.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::test {
namespace {

class Techniques : public GlTest {
  protected:
    void SetUp() override {
        renderer_ = std::make_unique<gl::Renderer>(context());
        renderer_->set_mesh(scene::make_scene_mesh("sphere"));
        renderer_->set_lean_map(make_bumps_map(256));
    }
    void TearDown() override {
        renderer_.reset();
        GlTest::TearDown();
    }
    Image render(gl::Technique technique, float distance, const ShadingSettings& settings,
                 gl::OutputMode output = gl::OutputMode::Color, int size = 96, int k = 8) {
        gl::RenderRequest r;
        r.technique = technique;
        r.width = size;
        r.height = size;
        r.view = gl::view_at_distance(distance);
        r.settings = settings;
        r.output = output;
        r.reference_samples = k;
        return renderer_->render(r);
    }
    std::unique_ptr<gl::Renderer> renderer_;
};

// docs/math.md §4: with Sigma = I/s the LEAN lobe matches the normalised Blinn-Phong lobe; at LOD 0
// (no filtering of distinct bumps) LEAN and the baseline must agree. They are not identical: LEAN
// is a Gaussian over projected slopes, Blinn-Phong a cosine power over angles. On a flat surface
// that alone gives 2.7 % at s = 64 and 0.4 % at s = 512 (measured); around a normal tilted by a
// slope B the slope-space lobe is narrower by about 1 / (1 + B^2) along the tilt (11 % less energy
// at B = 0.3), so the bumps are baked at strength 0.35 (slopes up to ~0.25) for this comparison.
// Measured on llvmpipe: 3.4 % at s = 64, 1.7 % at s = 256, 1.3 % at s = 1024.
TEST_F(Techniques, LeanMatchesBaselineAtTheFinestLevel) {
    renderer_->set_lean_map(make_bumps_map(512, 0.35f));
    for (float s : {64.0f, 256.0f, 1024.0f}) {
        ShadingSettings settings;
        settings.shininess = s;
        settings.tiling =
            0.25f;  // 4 x 2 tiles of 512 texels on the sphere, about 1 texel per pixel
        settings.mip_bias = -16.0f;  // force level 0
        const Image bump =
            render(gl::Technique::Bump, 1.6f, settings, gl::OutputMode::Specular, 128);
        const Image lean =
            render(gl::Technique::Lean, 1.6f, settings, gl::OutputMode::Specular, 128);
        ASSERT_GT(image_sum(bump), 1.0);
        const double difference = relative_l1(lean, bump);
        std::printf("s = %g: mean relative difference of the specular image %.4f\n", s, difference);
        EXPECT_LT(difference, 0.045) << "s = " << s;
    }
}

// Determinism: the same frame rendered twice, by the same renderer and by a new one (new GL
// objects, programs and textures), gives identical pixels on the same driver; for every technique,
// with MSAA and fog, and for the tiled reference.
TEST_F(Techniques, SameFrameTwiceGivesIdenticalPixels) {
    ShadingSettings settings;
    settings.fade = 0.5f;
    settings.fog = FogMode::Linear;
    settings.fog_start = 2.0f;
    settings.fog_end = 30.0f;
    const gl::Technique techniques[] = {gl::Technique::Bump,    gl::Technique::Lean,
                                        gl::Technique::Fade,    gl::Technique::Reference,
                                        gl::Technique::Toksvig, gl::Technique::Clean};
    for (int msaa : {1, 4}) {
        settings.msaa = msaa;
        for (gl::Technique technique : techniques) {
            SCOPED_TRACE(std::string(gl::to_string(technique)) + " msaa " + std::to_string(msaa));
            const Image first = render(technique, 5.0f, settings, gl::OutputMode::Color, 64, 4);
            const Image second = render(technique, 5.0f, settings, gl::OutputMode::Color, 64, 4);
            ASSERT_EQ(first.pixels.size(), second.pixels.size());
            EXPECT_TRUE(first.pixels == second.pixels) << "the same renderer, twice";
            EXPECT_GT(image_sum(first), 0.0);

            gl::Renderer fresh(context());
            fresh.set_mesh(scene::make_scene_mesh("sphere"));
            fresh.set_lean_map(make_bumps_map(256));
            gl::RenderRequest r;
            r.technique = technique;
            r.width = r.height = 64;
            r.view = gl::view_at_distance(5.0f);
            r.settings = settings;
            r.reference_samples = 4;
            EXPECT_TRUE(fresh.render(r).pixels == first.pixels) << "a new renderer";
        }
    }
    // The tiled reference (k = 16 at 160 pixels: 2 x 2 tiles).
    settings.msaa = 1;
    const Image a =
        render(gl::Technique::Reference, 4.0f, settings, gl::OutputMode::Color, 160, 16);
    const Image b =
        render(gl::Technique::Reference, 4.0f, settings, gl::OutputMode::Color, 160, 16);
    EXPECT_TRUE(a.pixels == b.pixels) << "tiled reference";
}

TEST_F(Techniques, FadeZeroIsBitIdenticalToLean) {
    ShadingSettings settings;
    settings.fade = 0.0f;
    for (float distance : {3.0f, 24.0f}) {
        const Image lean = render(gl::Technique::Lean, distance, settings);
        const Image fade = render(gl::Technique::Fade, distance, settings);
        ASSERT_EQ(lean.pixels.size(), fade.pixels.size());
        EXPECT_TRUE(lean.pixels == fade.pixels) << "distance " << distance;
    }
}

// Two-lobe LEAN (docs/math.md §10) on a material without a plateau layer reads f = 0: LEAN's
// pixels, bit for bit, in both BRDFs (without geometric antialiasing, which LEAN does not get).
TEST_F(Techniques, TwoLobeWithoutPlateauIsBitIdenticalToLean) {
    ShadingSettings settings;
    settings.geometric_aa = GeometricAa::Off;
    for (Brdf brdf : {Brdf::BlinnPhong, Brdf::CookTorrance}) {
        settings.brdf = brdf;
        for (float distance : {3.0f, 24.0f}) {
            const Image lean = render(gl::Technique::Lean, distance, settings);
            const Image two = render(gl::Technique::TwoLobe, distance, settings);
            ASSERT_EQ(lean.pixels.size(), two.pixels.size());
            EXPECT_TRUE(lean.pixels == two.pixels) << "distance " << distance;
        }
    }
}

// A LEAN map without its stored plateau layer (a file of an earlier version, or `bake
// --plateau-epsilon 0`) gets no plateau map: two-lobe draws it as LEAN, bit for bit.
TEST_F(Techniques, AMapWithoutAStoredPlateauLayerDrawsTwoLobeAsLean) {
    scene::Scene scene;
    scene.objects.push_back(scene::Object{scene::make_scene_mesh("sphere"), 0, glm::mat4(1.0f)});
    scene.materials.push_back(scene::Material{});
    scene.lean_maps.push_back(make_bumps_map(256));
    remove_plateau_layer(scene.lean_maps.back());
    scene::add_plateau_maps(scene);
    ASSERT_EQ(scene.materials[0].map(scene::MapKind::Plateau), -1);
    renderer_->set_scene(scene);
    ShadingSettings off;
    off.geometric_aa = GeometricAa::Off;
    const Image lean = render(gl::Technique::Lean, 24.0f, off, gl::OutputMode::Specular);
    const Image two = render(gl::Technique::TwoLobe, 24.0f, off, gl::OutputMode::Specular);
    EXPECT_TRUE(lean.pixels == two.pixels);
}

// With the plateau layer the far sphere's two-lobe highlight differs from LEAN's (the spike of
// the flat ground), and geometric antialiasing (docs/math.md §11) changes each technique's
// specular image when it is on and leaves it bit for bit when it is off.
TEST_F(Techniques, PlateauAndGeometricAntialiasingChangeTheFarHighlight) {
    scene::Scene scene;
    scene.objects.push_back(scene::Object{scene::make_scene_mesh("sphere"), 0, glm::mat4(1.0f)});
    scene.materials.push_back(scene::Material{});
    scene.lean_maps.push_back(make_bumps_map(256));
    scene::add_plateau_maps(scene);
    ASSERT_EQ(scene.materials[0].map(scene::MapKind::Plateau), 0);
    renderer_->set_scene(scene);
    ShadingSettings off;
    off.geometric_aa = GeometricAa::Off;
    const Image lean = render(gl::Technique::Lean, 24.0f, off, gl::OutputMode::Specular);
    const Image two = render(gl::Technique::TwoLobe, 24.0f, off, gl::OutputMode::Specular);
    EXPECT_GT(relative_l1(two, lean), 0.05) << "the plateau's spike must show";
    ShadingSettings on;
    on.geometric_aa = GeometricAa::On;
    for (gl::Technique t : {gl::Technique::Bump, gl::Technique::Lean, gl::Technique::TwoLobe}) {
        const Image a = render(t, 24.0f, off, gl::OutputMode::Specular);
        const Image b = render(t, 24.0f, on, gl::OutputMode::Specular);
        EXPECT_GT(relative_l1(b, a), 1e-3) << gl::to_string(t);
        EXPECT_GT(image_sum(b), 0.0) << gl::to_string(t);
    }
}

TEST_F(Techniques, FadingLowersOnlyTheSpecularTermAtDistance) {
    const ShadingSettings settings;  // the defaults: Fade 0.15, p 2, Pmax 16
    const float far = 24.0f;
    const Image lean_specular =
        render(gl::Technique::Lean, far, settings, gl::OutputMode::Specular);
    const Image fade_specular =
        render(gl::Technique::Fade, far, settings, gl::OutputMode::Specular);
    const double lean_sum = image_sum(lean_specular), fade_sum = image_sum(fade_specular);
    ASSERT_GT(lean_sum, 0.0);
    // At 24 radii sf = min(1 + (24 Fade)^2, Pmax) = 14; NdotL ~ 0.93 in the highlight.
    EXPECT_LT(fade_sum, 0.75 * lean_sum) << "the highlight must fade at distance";
    for (std::size_t i = 0; i < lean_specular.pixels.size(); ++i)
        ASSERT_LE(fade_specular.pixels[i], lean_specular.pixels[i] * (1.0f + 1e-5f) + 1e-7f)
            << "NdotL^sf <= NdotL: fading never adds energy (value " << i << ")";

    const Image lean_diffuse = render(gl::Technique::Lean, far, settings, gl::OutputMode::Diffuse);
    const Image fade_diffuse = render(gl::Technique::Fade, far, settings, gl::OutputMode::Diffuse);
    EXPECT_TRUE(lean_diffuse.pixels == fade_diffuse.pixels);

    // Close up (sf ~ 1.1) fading changes little: "at close range it is very similar to LEAN's".
    const Image lean_near = render(gl::Technique::Lean, 3.0f, settings, gl::OutputMode::Specular);
    const Image fade_near = render(gl::Technique::Fade, 3.0f, settings, gl::OutputMode::Specular);
    EXPECT_GT(image_sum(fade_near), 0.8 * image_sum(lean_near));
}

TEST_F(Techniques, ReferenceConverges) {
    ShadingSettings settings;
    settings.shininess = 128.0f;
    const Image k2 = render(gl::Technique::Reference, 6.0f, settings, gl::OutputMode::Color, 48, 2);
    const Image k4 = render(gl::Technique::Reference, 6.0f, settings, gl::OutputMode::Color, 48, 4);
    const Image k8 = render(gl::Technique::Reference, 6.0f, settings, gl::OutputMode::Color, 48, 8);
    const double d24 = mean_abs_difference(k2, k4), d48 = mean_abs_difference(k4, k8);
    std::printf("reference: |k2 - k4| = %.5f, |k4 - k8| = %.5f\n", d24, d48);
    EXPECT_GT(d24, 0.0);
    EXPECT_LT(d48, d24);
}

// The reference draws in tiles of at most 2048 x 2048 samples: k = 16 at 160 pixels uses 2 x 2
// tiles of 128 pixels, which must join without seams (compared with the untiled k = 8).
TEST_F(Techniques, TiledReferenceHasNoSeams) {
    ShadingSettings settings;
    settings.shininess = 128.0f;
    const Image k8 =
        render(gl::Technique::Reference, 4.0f, settings, gl::OutputMode::Color, 160, 8);
    const Image k16 =
        render(gl::Technique::Reference, 4.0f, settings, gl::OutputMode::Color, 160, 16);
    // Rows and columns next to the seam (pixel 128 from the bottom-left) behave like the others.
    double seam = 0.0, elsewhere = 0.0;
    for (int y = 0; y < 160; ++y)
        for (int x = 0; x < 160; ++x)
            for (int c = 0; c < 3; ++c) {
                const double d = std::abs(double(k8.at(x, y, c)) - double(k16.at(x, y, c)));
                const bool near_seam = x == 127 || x == 128 || y == 31 || y == 32;
                (near_seam ? seam : elsewhere) += d;
            }
    seam /= 4.0 * 160 * 3;
    elsewhere /= (160.0 * 160 - 4.0 * 160) * 3;
    EXPECT_LT(seam, 3.0 * elsewhere + 1e-3) << "seam " << seam << " elsewhere " << elsewhere;
    EXPECT_LT(mean_abs_difference(k8, k16), 0.02);
}

TEST_F(Techniques, MultisamplingAndAnisotropicFiltering) {
    ShadingSettings settings;
    settings.msaa = 4;
    const Image msaa = render(gl::Technique::Lean, 3.0f, settings);
    settings.msaa = 1;
    const Image plain = render(gl::Technique::Lean, 3.0f, settings);
    EXPECT_GT(mean_abs_difference(msaa, plain), 0.0) << "MSAA must smooth the silhouette";
    EXPECT_LT(mean_abs_difference(msaa, plain), 0.02);

    settings.anisotropy = 8;
    if (context().max_anisotropy() > 1.0f) {
        const Image aniso = render(gl::Technique::Lean, 3.0f, settings);
        EXPECT_LT(mean_abs_difference(aniso, plain), 0.05);
    } else {
        EXPECT_THROW(render(gl::Technique::Lean, 3.0f, settings), Error);
    }
}

TEST_F(Techniques, RejectsInvalidRequests) {
    ShadingSettings settings;
    settings.shininess = 0.0f;
    EXPECT_THROW(render(gl::Technique::Lean, 3.0f, settings), Error);
    settings = ShadingSettings();
    EXPECT_THROW(render(gl::Technique::Reference, 3.0f, settings, gl::OutputMode::Color, 32, 0),
                 Error);
    EXPECT_THROW(render(gl::Technique::Lean, 3.0f, settings, gl::OutputMode::Color, 0), Error);
    EXPECT_THROW(gl::view_at_distance(0.5f), Error);
    EXPECT_THROW(gl::parse_techniques("bump,phong"), Error);
    EXPECT_THROW(gl::parse_techniques("lean,lean"), Error);
    EXPECT_EQ(gl::parse_techniques("reference,fade").size(), 2u);

    gl::Renderer empty(context());
    gl::RenderRequest request;
    EXPECT_THROW(empty.render(request), Error);
    PackedLeanMap bad = make_constant_lean_map({0, 0}, {0.01f, 0.01f, 0}, 1.0f, Storage::Unorm8);
    bad.levels[0].lean1.pop_back();
    EXPECT_THROW(empty.set_lean_map(bad), Error);
}

TEST_F(Techniques, EveryStorageUploads) {
    ShadingSettings settings;
    Image first;
    for (Storage storage :
         {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
        renderer_->set_lean_map(
            make_constant_lean_map({0.1f, 0.05f}, {0.01f, 0.02f, 0.002f}, 0.98f, storage));
        const Image image = render(gl::Technique::Lean, 3.0f, settings, gl::OutputMode::Color, 48);
        if (first.empty())
            first = image;
        else
            EXPECT_LT(mean_abs_difference(image, first), 0.01) << to_string(storage);
    }
}

}  // namespace
}  // namespace leanfade::test
