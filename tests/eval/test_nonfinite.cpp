// A NaN or an infinity from the shading math is an error naming the technique, never black
// pixels in a file with exit 0; an eval case whose object covers no pixel is an error, never NaN
// metrics (docs/robustness.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

fs::path nonfinite_folder(const std::string& name) {
    return leanfade::test::fresh_scratch_folder("nonfinite", name);
}

// The float samples of a PFM file as written (no check of their values, unlike io::read_image).
std::vector<float> pfm_samples(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string magic;
    int width = 0, height = 0;
    double scale = 0.0;
    in >> magic >> width >> height >> scale;
    in.get();
    const std::size_t count = std::size_t(width) * std::size_t(height) * (magic == "PF" ? 3 : 1);
    std::vector<float> samples(count);
    in.read(reinterpret_cast<char*>(samples.data()), std::streamsize(count * sizeof(float)));
    EXPECT_TRUE(in.good()) << path;
    return samples;
}

// An 8-bit bake of a 3x1 normal map: one normal along +x at the horizon (slope 64 once z is
// raised to 1/64, so sc = 64) and two at the horizon straight up (slope 0.25, 0.25). At the
// texel centres M = B^2 exactly; 8-bit codes round B and M apart, and M - B^2 comes out
// negative in both directions: LEAN's Gaussian gets a negative covariance, exp(+large), and
// lean gave NaN, clean and fade infinity, written as black pixels with exit 0.
TEST(NonFiniteShading, IsAnErrorOrFinitePixelsNeverBlack) {
    const fs::path dir = nonfinite_folder("extreme_normals");
    Image normals(3, 1, 3);
    const float texels[3][3] = {{1.0f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}};
    for (int x = 0; x < 3; ++x)
        for (int c = 0; c < 3; ++c) normals.at(x, 0, c) = texels[x][c];
    io::write_png((dir / "extreme.png").string(), normals, 8);
    const RunResult bake = run_leanfade_bounded(
        "bake " + shell_quote((dir / "extreme.png").string()) + " --bits 8 -o " +
            shell_quote((dir / "extreme.ktx2").string()),
        dir);
    ASSERT_EQ(bake.exit_code, 0) << bake.err;

    for (const char* technique : {"clean", "lean", "fade"}) {
        const std::string render = std::string("render --scene sphere --techniques ") +
                                   technique + " --distances 2 --size 64x64 --bumps " +
                                   shell_quote((dir / "extreme.ktx2").string());
        const fs::path picture = dir / (std::string(technique) + ".png");
        const RunResult r =
            run_leanfade_bounded(render + " -o " + shell_quote(picture.string()), dir, 120);
        if (r.exit_code != 0) {
            EXPECT_EQ(r.exit_code, 1) << technique << ": " << r.err;
            // One line naming the technique and the non-finite value.
            EXPECT_EQ(r.err.rfind("leanfade render: ", 0), 0u) << r.err;
            EXPECT_NE(r.err.find(technique), std::string::npos) << r.err;
            EXPECT_TRUE(r.err.find("NaN") != std::string::npos ||
                        r.err.find("infinity") != std::string::npos)
                << r.err;
            EXPECT_EQ(r.err.find(".pfm"), std::string::npos) << "the render, not a file: " << r.err;
            EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
            EXPECT_FALSE(fs::exists(picture)) << technique;
            continue;
        }
        // Accepted: then the shading kept the covariance positive, and every radiance of the
        // same render, written as linear floats, is a finite number.
        const fs::path cells = dir / (std::string("cells_") + technique);
        const RunResult with_cells = run_leanfade_bounded(
            render + " --cells " + shell_quote(cells.string()) + " -o " +
                shell_quote((dir / "again.png").string()),
            dir, 120);
        ASSERT_EQ(with_cells.exit_code, 0) << technique << ": " << with_cells.err;
        std::size_t files = 0;
        for (const auto& entry : fs::directory_iterator(cells))
            if (entry.path().extension() == ".pfm") {
                ++files;
                for (float v : pfm_samples(entry.path()))
                    ASSERT_TRUE(std::isfinite(v)) << technique << ": " << entry.path();
            }
        EXPECT_EQ(files, 1u) << technique;
    }
}

// At 5000 bounding radii the sphere is far below a pixel of a 16x16 frame: eval measured
// nothing and reported NaN energy and flicker with exit 0.
TEST(NonFiniteMetrics, ACaseWithoutObjectPixelsIsAnError) {
    const fs::path dir = nonfinite_folder("vanished");
    const RunResult r = run_leanfade_bounded(
        "eval --scene sphere --techniques lean --distances 5000 --shininess 128 --spp 1 "
        "--frames 2 --size 16x16 --texture-size 32 --out " +
            shell_quote((dir / "out").string()),
        dir, 120);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err,
              "leanfade eval: --distances: at distance 5000 the object covers no whole pixel of "
              "the 16x16 frame: nothing to measure (use smaller distances or a larger image size)\n");
    EXPECT_FALSE(fs::exists(dir / "out" / "results.json"));
}

}  // namespace
}  // namespace leanfade::test
