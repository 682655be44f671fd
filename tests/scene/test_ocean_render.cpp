// The built-in ocean rendered through OpenGL (llvmpipe here): the sun's glints show on the water
// (its specular far above its diffuse), the waves move (time T differs from T + dt) and loop (T
// and T + loop_seconds are the same image), the water reaches the horizon under the sky, fading
// dims the far view's glints only, and LEAN keeps the far view stable under a sub-pixel camera
// move where plain bump mapping sparkles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "cli_runner.hpp"
#include "gl_test_helpers.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/gl/detail/scene_view.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/detail/ocean.hpp"

using namespace leanfade;

namespace {

constexpr int kWidth = 192;
constexpr int kHeight = 108;

class OceanRender : public test::GlTest {
  protected:
    static void SetUpTestSuite() {
        GlTest::SetUpTestSuite();
        settings_ = new scene::OceanSettings();
        settings_->texture_size = 128;
        renderer_ = new gl::Renderer(context());
        renderer_->set_scene(scene::make_ocean_scene(*settings_, 0));
    }
    static void TearDownTestSuite() {
        delete renderer_;
        delete settings_;
        GlTest::TearDownTestSuite();
    }

    // `sideways`: the camera moved along +x by that many metres.
    static gl::RenderRequest request(const std::string& camera_name, Technique technique,
                                     float time, gl::OutputMode output = gl::OutputMode::Color,
                                     float sideways = 0.0f) {
        scene::OceanCamera camera = scene::ocean_camera(camera_name, *settings_);
        camera.eye.x += sideways;
        camera.target.x += sideways;
        gl::RenderRequest r;
        r.technique = technique;
        r.width = kWidth;
        r.height = kHeight;
        r.view = gl::view_in_scene(renderer_->model_matrix(), camera.eye, camera.target,
                                   camera.fov_y_degrees, camera.near_plane, camera.far_plane);
        r.settings = scene::ocean_shading(*settings_, float(kWidth) / float(kHeight));
        r.output = output;
        r.time = time;
        // The sky behind the horizon in colour; black behind the diffuse and specular terms.
        r.background =
            output == gl::OutputMode::Color ? scene::ocean_sky_colour() : glm::vec3(0.0f);
        return r;
    }

    static Image render(const gl::RenderRequest& r) { return renderer_->render(r); }

    static float max_channel(const Image& image) {
        return *std::max_element(image.pixels.begin(), image.pixels.end());
    }

    static scene::OceanSettings* settings_;
    static gl::Renderer* renderer_;
};

scene::OceanSettings* OceanRender::settings_ = nullptr;
gl::Renderer* OceanRender::renderer_ = nullptr;

}  // namespace

TEST_F(OceanRender, GlintsShowInEveryView) {
    for (const std::string& name : scene::ocean_camera_names()) {
        const Image specular =
            render(request(name, Technique::Lean, 3.0f, gl::OutputMode::Specular));
        const Image diffuse = render(request(name, Technique::Lean, 3.0f, gl::OutputMode::Diffuse));
        // The sun is off-screen, yet its glints on the water are many times brighter than the
        // water's own (ambient + diffuse) light.
        EXPECT_GT(max_channel(specular), 10.0f * max_channel(diffuse)) << name;
        // Glints, not a uniform sheen: most of the water is far dimmer than the brightest.
        std::vector<float> values;
        for (std::size_t i = 0; i < specular.pixels.size(); i += 3)
            values.push_back(specular.pixels[i]);
        std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
        EXPECT_LT(values[values.size() / 2], 0.1f * max_channel(specular)) << name;
        // The glints gather on the right, toward the sun.
        double left = 0.0, right = 0.0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                (x < kWidth / 2 ? left : right) += specular.at(x, y, 0);
        EXPECT_GT(right, left) << name;
    }
}

TEST_F(OceanRender, WavesMoveAndLoop) {
    const scene::OceanSettings& s = *settings_;
    const Image at_t = render(request("near", Technique::Lean, 1.0f));
    const Image later = render(request("near", Technique::Lean, 1.5f));
    const Image looped = render(request("near", Technique::Lean, 1.0f + s.loop_seconds));
    const Image again = render(request("near", Technique::Lean, 1.0f));
    EXPECT_EQ(at_t.pixels, again.pixels);  // deterministic
    // Half a second later the water (the lower half of the image) has changed by more than a
    // tenth of its mean radiance on average.
    double change = 0.0, mean = 0.0;
    for (int y = kHeight / 2; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            for (int c = 0; c < 3; ++c) {
                change += std::abs(double(at_t.at(x, y, c)) - double(later.at(x, y, c)));
                mean += double(at_t.at(x, y, c));
            }
    EXPECT_GT(change, 0.1 * mean);
    // Each layer moved a whole number of tiles: the same picture.
    EXPECT_EQ(at_t.pixels, looped.pixels);
}

TEST_F(OceanRender, TheWaterReachesTheHorizonUnderTheSky) {
    const Image image = render(request("near", Technique::Lean, 0.0f));
    const glm::vec3 sky = scene::ocean_sky_colour();
    // Down a column on the left (away from the glints): sky from the top row to the horizon in
    // the upper half, then water that darkens toward the camera (the haze thins), never brighter
    // than the sky. Just below the horizon the haze has made the water nearly the sky's colour.
    const int x = kWidth / 4;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.at(x, 0, c), sky[c], 1e-4f);
    int horizon = -1;
    for (int y = 0; y < kHeight && horizon < 0; ++y)
        if (std::abs(image.at(x, y, 2) - sky.z) > 1e-4f) horizon = y;
    ASSERT_GT(horizon, 0);
    ASSERT_LT(horizon, kHeight / 2);
    EXPECT_GT(image.at(x, horizon, 2), 0.8f * sky.z);
    EXPECT_LT(image.at(x, kHeight - 1, 2), 0.3f * sky.z);
    for (int y = horizon; y + 4 < kHeight; y += 4) {
        EXPECT_LE(image.at(x, y, 2), sky.z + 1e-4f) << y;
        EXPECT_GT(image.at(x, y, 2), image.at(x, y + 4, 2) - 0.01f) << y;
    }
}

TEST_F(OceanRender, FadingDimsOnlyTheFarGlints) {
    auto energy = [](const Image& image) { return test::image_sum(image); };
    const double near_lean =
        energy(render(request("near", Technique::Lean, 2.0f, gl::OutputMode::Specular)));
    const double near_fade =
        energy(render(request("near", Technique::Fade, 2.0f, gl::OutputMode::Specular)));
    const double far_lean =
        energy(render(request("far", Technique::Lean, 2.0f, gl::OutputMode::Specular)));
    const double far_fade =
        energy(render(request("far", Technique::Fade, 2.0f, gl::OutputMode::Specular)));
    EXPECT_NEAR(near_fade / near_lean, 1.0, 0.05);
    EXPECT_LT(far_fade / far_lean, 0.8);
    EXPECT_GT(far_fade, 0.0);
}

TEST_F(OceanRender, TheFarViewIsStableUnderLeanAndSparklesUnfiltered) {
    // A camera move of a fraction of a pixel: LEAN's far view changes little, while the same
    // waves shaded from their finest level only (bump mapping with a MIP bias of -16: what
    // shading without filtering sees) make glints jump from pixel to pixel.
    // At the image's centre the far camera sees the water about 970 m away (300 m up, 18 degrees
    // down), where a pixel spans about 2 tan(20 deg) / kHeight * 970 = 6.5 m: move by 2 m.
    auto flicker = [&](Technique technique, float mip_bias) {
        gl::RenderRequest a = request("far", technique, 2.0f, gl::OutputMode::Specular);
        gl::RenderRequest b = request("far", technique, 2.0f, gl::OutputMode::Specular, 2.0f);
        a.settings.mip_bias = b.settings.mip_bias = mip_bias;
        const Image ia = render(a), ib = render(b);
        return test::mean_abs_difference(ia, ib) /
               std::max(1e-12, test::image_sum(ia) / double(ia.pixels.size()));
    };
    const double lean = flicker(Technique::Lean, 0.0f);
    const double unfiltered = flicker(Technique::Bump, -16.0f);
    EXPECT_LT(lean, 0.25 * unfiltered) << "lean " << lean << ", unfiltered " << unfiltered;
}

// `leanfade render --scene ocean`: one instant, a frame sequence, and bad flags refused with one
// line and nothing written.
TEST(OceanCli, RendersAnInstantAndAFrameSequence) {
    const std::filesystem::path dir = test::scratch_dir("ocean_cli");
    const std::string common =
        "render --scene ocean --techniques lean --size 64x36 --texture-size 64 ";
    test::RunResult r =
        test::run_leanfade_in(common + "--views near --time 0 --frames 3 --fps 4 -o " +
                                  test::shell_quote((dir / "f_%02d.png").string()),
                              dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (int k = 0; k < 3; ++k)
        EXPECT_TRUE(std::filesystem::exists(dir / ("f_0" + std::to_string(k) + ".png"))) << k;
    // The frames differ (the waves move a quarter of a second apart); frame 1 is --time 0.25.
    const Image f0 = io::read_image((dir / "f_00.png").string());
    const Image f1 = io::read_image((dir / "f_01.png").string());
    EXPECT_GT(test::mean_abs_difference(f0, f1), 1e-3);
    r = test::run_leanfade_in(
        common + "--views near --time 0.25 -o " + test::shell_quote((dir / "one.png").string()),
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(io::read_image((dir / "one.png").string()).pixels, f1.pixels);

    for (const std::string& bad :
         {std::string("--frames 2 -o ") + test::shell_quote((dir / "plain.png").string()),
          std::string("--views space -o ") + test::shell_quote((dir / "v.png").string()),
          std::string("--ocean-layers 1 -o ") + test::shell_quote((dir / "l.png").string()),
          std::string("--flow ") + test::shell_quote((dir / "missing.png").string()) + " -o " +
              test::shell_quote((dir / "m.png").string())}) {
        r = test::run_leanfade_in(common + bad, dir);
        EXPECT_EQ(r.exit_code, 1) << bad;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << ": " << r.err;
    }
    for (const char* name : {"plain.png", "v.png", "l.png", "m.png"})
        EXPECT_FALSE(std::filesystem::exists(dir / name)) << name;
}
