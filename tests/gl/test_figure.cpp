// The comparison figure: golden image of the teaser, layout, labels, sRGB encoding.
//
// Golden images live in tests/gl/golden/. Refresh them after an intended change of the look
// (shaders, defaults, scene or bump set) with
//     LEANFADE_UPDATE_GOLDEN=1 ctest --test-dir build -R Golden
// and check the new PNGs by eye before committing them (see tests/gl/README.md).
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/figure.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

Image quantize8(const Image& image) {
    Image out = image;
    for (float& v : out.pixels) v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
    return out;
}

class GlFigure : public GlTest {};

// `make demo`'s teaser (teapot, bumps, bump/lean/fade at 3 and 24 radii) at 96-pixel cells.
// Tolerance: the mean absolute difference of the 8-bit sRGB values at most 1.5 / 255, and at most
// 0.5 % of the values off by more than 24 / 255: other drivers place a few sparkles of the
// aliasing baseline differently, but any change of the shading moves whole regions.
TEST_F(GlFigure, TeaserMatchesGolden) {
    gl::Renderer renderer(context());
    renderer.set_mesh(scene::make_scene_mesh("teapot"));
    renderer.set_lean_map(make_bumps_map(256));
    gl::FigureRequest request;
    request.cell_width = 96;
    request.cell_height = 96;
    const Image picture = quantize8(gl::render_figure(renderer, request).picture);

    const fs::path golden = fs::path(LEANFADE_SOURCE_DIR) / "tests/gl/golden/teaser_96.png";
    const char* update = std::getenv("LEANFADE_UPDATE_GOLDEN");
    if (update != nullptr && std::string(update) == "1") {
        io::write_png(golden.string(), picture, 8);
        std::printf("updated %s\n", golden.string().c_str());
        return;
    }
    ASSERT_TRUE(fs::exists(golden))
        << golden << " is missing: run LEANFADE_UPDATE_GOLDEN=1 ctest -R Golden";
    const Image expected = io::read_image(golden.string());
    ASSERT_EQ(expected.width, picture.width);
    ASSERT_EQ(expected.height, picture.height);
    ASSERT_EQ(expected.channels, picture.channels);
    double sum = 0.0;
    std::size_t large = 0;
    for (std::size_t i = 0; i < picture.pixels.size(); ++i) {
        const double d = std::abs(double(picture.pixels[i]) - double(expected.pixels[i]));
        sum += d;
        if (d > 24.0 / 255.0) ++large;
    }
    const double mean = sum / double(picture.pixels.size());
    const double large_fraction = double(large) / double(picture.pixels.size());
    if (mean > 1.5 / 255.0 || large_fraction > 0.005) {
        const fs::path actual = scratch_dir("golden") / "teaser_96.actual.png";
        io::write_png(actual.string(), picture, 8);
        ADD_FAILURE() << "teaser differs from " << golden << ": mean " << mean * 255.0 << "/255, "
                      << large_fraction * 100.0 << " % of values off by > 24/255; "
                      << "this render is in " << actual;
    }
}

TEST_F(GlFigure, LayoutLabelsAndZoomRows) {
    gl::Renderer renderer(context());
    renderer.set_mesh(scene::make_scene_mesh("sphere"));
    renderer.set_lean_map(make_bumps_map(64));
    gl::FigureRequest request;
    request.techniques = {gl::Technique::Lean, gl::Technique::Reference};
    request.distances = {2.5f, 30.0f};
    request.cell_width = 64;
    request.cell_height = 48;
    request.reference_samples = 2;
    request.zoom = true;
    int calls = 0;
    const gl::Figure figure = gl::render_figure(renderer, request, [&](int done, int total) {
        ++calls;
        EXPECT_EQ(total, 4);
        EXPECT_EQ(done, calls);
    });
    EXPECT_EQ(calls, 4);
    ASSERT_EQ(figure.cells.size(), 4u);
    EXPECT_EQ(figure.cells[1].technique, gl::Technique::Reference);
    EXPECT_EQ(figure.cells[2].distance, 30.0f);
    EXPECT_EQ(figure.cells[3].radiance.width, 64);
    EXPECT_EQ(figure.cells[3].radiance.height, 48);
    // Rows: d=2.5, d=30, and a zoom row for d=30 (the far sphere is < 1/3 of the cell).
    const int scale = 1, top = gl::text_height(scale) + 6 * scale;
    EXPECT_EQ(figure.picture.height, top + 3 * (48 + 1));
    const int left = gl::text_width("d=2.5", scale) + 6 * scale;
    EXPECT_EQ(figure.picture.width, left + 2 * (64 + 1));
    // The header holds text pixels (the technique names).
    int ink = 0;
    for (int y = 0; y < top; ++y)
        for (int x = left; x < figure.picture.width; ++x) ink += figure.picture.at(x, y, 0) > 0.5f;
    EXPECT_GT(ink, 20);

    request.distances = {1.0f};
    EXPECT_THROW(gl::render_figure(renderer, request), Error);
    request.distances = {};
    EXPECT_THROW(gl::render_figure(renderer, request), Error);
}

TEST(Figure, SrgbEncodingAndText) {
    EXPECT_FLOAT_EQ(gl::encode_srgb(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(gl::encode_srgb(1.0f), 1.0f);
    EXPECT_FLOAT_EQ(gl::encode_srgb(7.0f), 1.0f);
    EXPECT_NEAR(gl::encode_srgb(0.18f), 0.4614f, 1e-3);    // mid grey
    EXPECT_NEAR(gl::encode_srgb(0.002f), 0.02584f, 1e-5);  // linear segment
    EXPECT_EQ(gl::distance_text(24.0f), "24");
    EXPECT_EQ(gl::distance_text(2.5f), "2.5");
    EXPECT_EQ(gl::text_width("lean", 2), (4 * 6 - 1) * 2);

    Image canvas(40, 10, 3);
    gl::draw_text(canvas, 1, 1, "x8", 1, glm::vec3(1.0f));
    int ink = 0;
    for (float v : canvas.pixels) ink += v > 0.0f;
    EXPECT_GT(ink, 3 * 10);
    gl::draw_text(canvas, 35, 5, "clipped", 3, glm::vec3(1.0f));  // partly outside: no crash
}

}  // namespace
}  // namespace leanfade::test
