// `leanfade view` as a user runs it, in a virtual X server (xvfb-run; Mesa llvmpipe through GLX),
// and `leanfade render --preset`.
#include <gtest/gtest.h>


#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "cli_runner.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade {
namespace {

namespace fs = std::filesystem;
using test::RunResult;

fs::path scratch(const std::string& name) {
    return leanfade::test::fresh_scratch_folder("viewer_cli", name);
}

// Runs `leanfade ARGS` in `dir`; under xvfb-run with a 1600x1000 screen when `x_server`.
RunResult run(const std::string& args, const fs::path& dir, bool x_server) {
    const std::string prefix =
        x_server ? test::shell_quote(LEANFADE_XVFB_RUN) + " -a -s '-screen 0 1600x1000x24'"
                 : "env -u DISPLAY -u WAYLAND_DISPLAY";
    return test::run_leanfade_in(args, dir, dir, prefix);
}

std::size_t lines(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

// Fraction of the pixels of [x0, x1) x [y0, y1) within `tolerance` (of 255) of `rgb`.
double fraction_near(const Image& image, int x0, int y0, int x1, int y1, const int rgb[3],
                     int tolerance) {
    int hits = 0, total = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            bool near = true;
            for (int c = 0; c < 3; ++c)
                near = near &&
                       std::abs(int(std::lround(image.at(x, y, c) * 255.0f)) - rgb[c]) <= tolerance;
            hits += near;
            ++total;
        }
    return total > 0 ? double(hits) / total : 0.0;
}

double standard_deviation(const Image& image) {
    double sum = 0.0, squares = 0.0;
    for (float v : image.pixels) {
        sum += v;
        squares += double(v) * v;
    }
    const double n = double(image.pixels.size());
    return std::sqrt(std::max(0.0, squares / n - (sum / n) * (sum / n)));
}

TEST(CliView, ScreenshotIsTheWindowWithThePanelAndTheObject) {
    const fs::path dir = scratch("screenshot");
    const RunResult r =
        run("view --scene teapot --frames 5 --screenshot shot.png --size 900x560", dir, true);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(lines(r.out), 1u) << r.out;
    EXPECT_NE(r.out.find("5 frames, window 900x560"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("lean "), std::string::npos) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;

    const Image shot = io::read_image((dir / "shot.png").string());
    ASSERT_EQ(shot.width, 900);
    ASSERT_EQ(shot.height, 560);
    EXPECT_GT(standard_deviation(shot), 0.05) << "the screenshot is blank";
    // The panel: Dear ImGui's default title bar colour (focused window, dark style) across the
    // top of the left 380 pixels, and its window body below.
    const int title[3] = {41, 74, 122};
    EXPECT_GT(fraction_near(shot, 2, 3, 300, 15, title, 3), 0.6) << "no panel title bar";
    const int body[3] = {15, 15, 15};
    EXPECT_GT(fraction_near(shot, 2, 20, 370, 540, body, 4), 0.3) << "no panel body";
    // The object: the teapot's lit terracotta fills the middle of the 3D area (right of the
    // panel), well above the dark background.
    int lit = 0;
    for (int y = 180; y < 380; ++y)
        for (int x = 520; x < 760; ++x) lit += shot.at(x, y, 0) > 0.35f;
    EXPECT_GT(lit, 240 * 200 / 3) << "no object in the 3D area";
    EXPECT_LT(fraction_near(shot, 380, 0, 900, 560, title, 3), 0.01);
}

TEST(CliView, TwoAndThreeTechniquesSideBySideAndSplit) {
    const fs::path dir = scratch("panes");
    RunResult r =
        run("view --scene sphere --techniques bump,lean,fade --frames 3 --size 640x400 "
            "--texture-size 64",
            dir, true);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* pane : {"bump ", "lean ", "fade "})
        EXPECT_NE(r.out.find(pane), std::string::npos) << r.out;
    r =
        run("view --scene sphere --techniques lean,fade --layout split --divider 0.3 --frames 2 "
            "--size 640x400 --texture-size 64 --fly-away --scale 0.25 --timing gpu",
            dir, true);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("GPU time"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("fade 80x100"), std::string::npos) << r.out;  // (640 - 320) / 4
}

// A preset with something unusual in every group, and the flags that say the same.
const char* const kPreset = R"({
  "leanfade_preset": 1,
  "scene": "torus",
  "bumps": {"source": "ridges", "from": "height", "directx": false, "bits": "8", "seed": 3,
            "texture_size": 64},
  "shading": {"light_direction": [0.5, 1, 0.25], "light_color": [1, 0.9, 0.8],
              "ambient": [0.05, 0.05, 0.05], "kd": [0.2, 0.4, 0.6], "ks": [0.8, 0.8, 0.8],
              "shininess": 300, "fresnel_bias": 0.1, "fresnel_scale": 0.5, "fade": 0.4,
              "pmax": 8, "fade_exponent": 1.5, "fade_distance": "eye", "fog": "exp",
              "fog_color": [0.3, 0.3, 0.35], "fog_start": 1, "fog_end": 30,
              "fog_density": 0.02, "bump_strength": 2, "tiling": 2, "mip_bias": 0.5,
              "anisotropy": 1, "msaa": 1},
  "camera": {"target": [0.1, -0.05, 0], "direction": [0.3, 0.6, 1], "distance": 4.5,
             "fov_y_degrees": 40},
  "view": {"techniques": ["bump", "fade"], "layout": "side-by-side", "reference_samples": 2}
})";

const char* const kPresetFlags =
    "--scene torus --bumps ridges --from height --bits 8 --seed 3 --texture-size 64 "
    "--light-dir 0.5,1,0.25 --light-color 1,0.9,0.8 --ambient 0.05 --kd 0.2,0.4,0.6 --ks 0.8 "
    "--shininess 300 --fresnel-bias 0.1 --fresnel-scale 0.5 --fade 0.4 --pmax 8 "
    "--fade-exponent 1.5 --fade-distance eye --fog exp --fog-color 0.3,0.3,0.35 --fog-start 1 "
    "--fog-end 30 --fog-density 0.02 --strength 2 --tiling 2 --mip-bias 0.5 --aniso 1 --msaa 1 "
    "--target 0.1,-0.05,0 --view-dir 0.3,0.6,1 --distances 4.5 --fov 40 --techniques bump,fade "
    "--ref-samples 2";

void expect_same_cells(const fs::path& a, const fs::path& b, const char* const names[], int n) {
    for (int i = 0; i < n; ++i) {
        SCOPED_TRACE(names[i]);
        const Image x = io::read_image((a / names[i]).string());
        const Image y = io::read_image((b / names[i]).string());
        ASSERT_EQ(x.width, y.width);
        EXPECT_EQ(x.pixels, y.pixels);
    }
}

TEST(CliRenderPreset, EqualsTheFlagsItStores) {
    const fs::path dir = scratch("render_preset");
    std::ofstream(dir / "p.json") << kPreset;
    RunResult r = run("render --preset p.json --size 48x40 --cells a -o a.png", dir, false);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run(std::string("render ") + kPresetFlags + " --size 48x40 --cells b -o b.png", dir, false);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const char* const cells[] = {"bump_d4.5.pfm", "fade_d4.5.pfm"};
    expect_same_cells(dir / "a", dir / "b", cells, 2);
    // Not the defaults: the same flags without the preset differ.
    r = run("render --techniques bump,fade --distances 4.5 --size 48x40 --cells c -o c.png", dir,
            false);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(io::read_image((dir / "a" / cells[0]).string()).pixels,
              io::read_image((dir / "c" / cells[0]).string()).pixels);
}

TEST(CliRenderPreset, ExplicitFlagsOverrideThePreset) {
    const fs::path dir = scratch("render_preset_override");
    std::ofstream(dir / "p.json") << kPreset;
    RunResult r =
        run("render --preset p.json --shininess 50 --fog none --techniques lean "
            "--size 40x40 --cells a -o a.png",
            dir, false);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::string flags = kPresetFlags;
    for (const auto& [from, to] :
         {std::pair<std::string, std::string>{"--shininess 300", "--shininess 50"},
          {"--fog exp", "--fog none"},
          {"--techniques bump,fade", "--techniques lean"}}) {
        const std::size_t at = flags.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        flags.replace(at, from.size(), to);
    }
    r = run("render " + flags + " --size 40x40 --cells b -o b.png", dir, false);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const char* const cells[] = {"lean_d4.5.pfm"};
    expect_same_cells(dir / "a", dir / "b", cells, 1);
}

TEST(CliView, SavedPresetsOpenInTheViewer) {
    const fs::path dir = scratch("view_preset");
    std::ofstream(dir / "p.json") << kPreset;
    RunResult r = run("view --preset p.json --frames 2 --size 640x400", dir, true);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("bump "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("fade "), std::string::npos) << r.out;
    // An explicit --technique replaces the preset's panes.
    r = run("view --preset p.json --technique reference --frames 1 --size 640x400", dir, true);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("reference "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("bump "), std::string::npos) << r.out;
}

TEST(CliView, BadInputsAreOneLineErrorsNotCrashes) {
    const fs::path dir = scratch("view_errors");
    std::ofstream(dir / "bad.json") << R"({"shading": {"fade": "fast"}})";
    const struct {
        const char* args;
        const char* message;
        int status;
    } cases[] = {
        {"view --scene missing.obj --frames 1", "missing.obj", 1},
        {"view --bumps missing.png --frames 1", "missing.png", 1},
        {"view --shader-dir no-such-folder --frames 1", "no-such-folder", 1},
        {"view --preset bad.json --frames 1", "key 'shading.fade'", 1},
        {"view --preset missing.json", "missing.json", 1},
        {"view --technique phong", "phong", 1},
        {"view --techniques bump,lean,fade,reference", "at most 3", 1},
        {"view --techniques bump,lean,fade --layout split", "split", 1},
        {"view --screenshot x.png", "--frames", 1},
        {"view --size 10x10", "--size", 1},
        {"view --timing sometimes", "--timing", 1},
        {"view --fade -1", "--fade", 1},
        {"view --frames 1", "xvfb-run", 1},  // no X display
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.args);
        const RunResult r = run(c.args, dir, false);
        EXPECT_EQ(r.exit_code, c.status) << r.err;
        EXPECT_EQ(lines(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
        EXPECT_TRUE(r.out.empty()) << r.out;
    }
}

TEST(CliView, AShaderErrorIsShownNotFatal) {
    const fs::path dir = scratch("view_shader_error");
    fs::create_directories(dir / "shaders");
    for (const auto& entry : fs::directory_iterator(fs::path(LEANFADE_SOURCE_DIR) / "shaders"))
        fs::copy_file(entry.path(), dir / "shaders" / entry.path().filename());
    std::ofstream(dir / "shaders" / "scene.frag", std::ios::app) << "\nthis is not GLSL;\n";
    const RunResult r =
        run("view --shader-dir shaders --scene sphere --texture-size 64 --frames 3 "
            "--screenshot shot.png --size 640x400",
            dir, true);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("scene.frag"), std::string::npos) << r.err;  // shown, and logged
    const Image shot = io::read_image((dir / "shot.png").string());
    EXPECT_EQ(shot.width, 640);
    EXPECT_EQ(shot.height, 400);
}

}  // namespace
}  // namespace leanfade
