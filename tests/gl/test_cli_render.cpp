// `leanfade render` as a user runs it: outputs, cells, and one-line errors.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "gl_test_helpers.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

// Runs `leanfade render <args>` in `dir`; `env` ("NAME=value ...") is added to its environment.
RunResult run_render(const std::string& args, const fs::path& dir, const std::string& env = "") {
    return run_leanfade_in("render " + args, dir, dir, env.empty() ? "" : "env " + env);
}

std::size_t lines(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

TEST(CliRender, WritesTheGridAndTheCells) {
    const fs::path dir = scratch_dir("cli_render");
    const RunResult r = run_render(
        "--scene sphere --techniques bump,reference --distances 2.5,12 --size 40x32 "
        "--ref-samples 2 --texture-size 64 --bits 8 --shininess 200 --fade-distance eye "
        "--fog linear --fog-start 2 --fog-end 30 --light-dir=-1,1,0.5 --kd 0.4 "
        "--cells cells --cell-format pfm -o grid.png",
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(lines(r.out), 1u) << r.out;
    EXPECT_TRUE(r.err.empty()) << "no progress line when stderr is not a terminal: " << r.err;
    const Image grid = io::read_image((dir / "grid.png").string());
    EXPECT_GT(grid.width, 2 * 40);
    EXPECT_GT(grid.height, 2 * 32);
    for (const char* name : {"bump_d2.5", "bump_d12", "reference_d2.5", "reference_d12"}) {
        const Image png = io::read_image((dir / "cells" / (std::string(name) + ".png")).string());
        EXPECT_EQ(png.width, 40);
        EXPECT_EQ(png.height, 32);
        const Image pfm = io::read_image((dir / "cells" / (std::string(name) + ".pfm")).string());
        EXPECT_EQ(pfm.width, 40);
        EXPECT_EQ(pfm.channels, 3);
    }
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos)
            << "temporary left behind: " << entry.path();
}

TEST(CliRender, BadInputsAreOneLineErrors) {
    const fs::path dir = scratch_dir("cli_render_errors");
    const std::string cases[] = {
        "--techniques bump,phong",
        "--distances 3,0.5",
        "--size 10x10",
        "--size big",
        "--shininess -1",
        "--pmax 0.5",
        "--fade-distance far",
        "--fog smoke",
        "--light-dir 1,2",
        "--kd red",
        "--msaa 3",
        "--aniso 0",
        "--ref-samples 0",
        "--bits 12",
        "--bumps missing.png",
        "--scene nothing",
        "--from heightmap",
        "--shader-dir nowhere",
        "--fog linear --fog-start 5 --fog-end 5",
        // Bump layers (docs/math.md §6).
        "--layers sine",
        "--layers sine,flat,sine,flat,sine",
        "--layers sine,flat --layer-weights 0.3,0.3",
        "--layers sine,flat --layer-weights 0.5",
        "--layers sine,flat --layer-strengths 1,0",
        "--layers sine,flat --layer-strengths 1,nan",
        "--layers sine,flat --layer-tiling 1,-2",
        "--layers sine,flat --layer-velocity 1",
        "--layers sine,flat --mixing blend",
        "--layers sine,missing.png",
        "--layers sine,flat --layer-weight-map missing.png",
        // One generated map repeating once per unit of uv: whole tilings, a bounded size.
        "--layers sine,flat --mixing height --layer-tiling 1,1.5",
        "--layers sine,flat --mixing height --layer-tiling 1,64 --texture-size 128",
        "--layers sine,flat --mixings height",
        "--mixings height,approx",
        "--time inf",
    };
    for (const std::string& args : cases) {
        std::string all = args + " -o never.png";
        if (args.find("--scene") == std::string::npos) all += " --scene sphere";
        if (args.find("--size") == std::string::npos) all += " --size 32x32";
        const RunResult r = run_render(all, dir);
        EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << args << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "never.png")) << args;
    }
    // CLI11 rejects a non-number itself, also in one line.
    const RunResult r = run_render("--shininess shiny -o never.png", dir);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_FALSE(fs::exists(dir / "never.png"));
}

// Each bad surface-map flag (`args`, on the sphere unless they name a scene) is a one-line error
// that names `named`, with exit 1 and no output.
struct BadMapCase {
    std::string args;
    std::string named;  // what the message names
};
void expect_bad_map_errors(const fs::path& dir, const std::string& common,
                           const std::vector<BadMapCase>& cases) {
    for (const BadMapCase& c : cases) {
        const std::string scene =
            c.args.find("--scene") == std::string::npos ? "--scene sphere " : "";
        const RunResult r =
            run_render(common + scene + "--techniques lean " + c.args + " -o never.png", dir);
        EXPECT_EQ(r.exit_code, 1) << c.args << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << c.args << ": " << r.err;
        EXPECT_NE(r.err.find(c.named), std::string::npos) << c.args << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "never.png")) << c.args;
    }
}

// --roughness-map (docs/roughness.md): Cook-Torrance's base roughness per texel, on one map or on
// bump layers; a missing file, values outside [0, 1], NaN, Blinn-Phong, the ocean and the map as
// the output are one-line errors with exit 1 and no output.
TEST(CliRender, RoughnessMap) {
    const fs::path dir = scratch_dir("cli_render_roughness_map");
    Image gradient(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) gradient.at(x, y) = 0.1f + 0.8f * float(x) / 31.0f;
    io::write_png((dir / "rough.png").string(), gradient, 16);
    Image metallic_roughness(32, 32, 3, 0.0f);  // glTF: r in G
    for (std::size_t t = 0; t < metallic_roughness.texel_count(); ++t)
        metallic_roughness.pixels[3 * t + 1] = 0.4f;
    io::write_png((dir / "mr.png").string(), metallic_roughness, 8);
    Image beyond(8, 8, 1, 0.5f);
    beyond.at(5, 2) = 1.5f;
    io::write_pfm((dir / "beyond.pfm").string(), beyond);
    {  // write_pfm refuses NaN: the bytes by hand (grey PFM, little-endian, rows bottom first)
        std::ofstream nan(dir / "nan.pfm", std::ios::binary);
        nan << "Pf\n8 8\n-1.0\n";
        for (int t = 0; t < 64; ++t) {
            const float v = t == 9 ? std::nanf("") : 0.5f;
            nan.write(reinterpret_cast<const char*>(&v), sizeof v);
        }
    }

    const std::string common = "--size 32x32 --distances 3 --texture-size 32 ";
    RunResult r = run_render(common +
                                 "--scene sphere --techniques lean,roughness,reference "
                                 "--ref-samples 2 "
                                 "--brdf cook-torrance --roughness-map rough.png -o map.png",
                             dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "map.png"));
    r = run_render(common +
                       "--scene sphere --techniques lean --layers sine,flat "
                       "--brdf cook-torrance "
                       "--roughness-map mr.png -o layers.png",
                   dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "layers.png"));

    expect_bad_map_errors(dir, common,
                          {
                              {"--brdf cook-torrance --roughness-map missing.png", "missing.png"},
                              {"--brdf cook-torrance --roughness-map beyond.pfm", "beyond.pfm"},
                              {"--brdf cook-torrance --roughness-map nan.pfm", "nan.pfm"},
                              {"--roughness-map rough.png", "--roughness-map"},
                              {"--brdf cook-torrance --roughness-map rough.png --scene ocean",
                               "--roughness-map"},
                          });
    // The map is an input: an output never overwrites it.
    const std::string before = read_text(dir / "rough.png");
    r = run_render(common +
                       "--scene sphere --techniques lean --brdf cook-torrance "
                       "--roughness-map rough.png -o rough.png",
                   dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_EQ(read_text(dir / "rough.png"), before);
}

// --specular-map (a row of the map-kind table read generically): a linear RGB factor on Ks
// (Blinn-Phong) or on the dielectric's F0 (Cook-Torrance), per texel at the bumps' uv. A constant
// map of 0.5 renders exactly as --ks 0.5 or --f0 0.02 (half of 0.04) do, in every technique,
// the supersampled truth included; bad maps are one-line errors with no output.
TEST(CliRender, SpecularMapScalesTheSpecularColour) {
    const fs::path dir = scratch_dir("cli_render_specular_map");
    io::write_pfm((dir / "half.pfm").string(), Image(8, 8, 3, 0.5f));
    Image grey(16, 16, 1, 0.5f);  // a grey 16-bit PNG: 0.5 is no 16-bit code, 32768/65535 is
    io::write_png((dir / "grey.png").string(), grey, 16);
    Image negative(8, 8, 1, 0.5f);
    negative.at(2, 3) = -0.25f;
    io::write_pfm((dir / "negative.pfm").string(), negative);

    const std::string view =
        "--scene sphere --techniques lean,two-lobe,reference --ref-samples 2 "
        "--distances 3 --size 40x40 --texture-size 64 --cell-format pfm ";
    auto render = [&](const std::string& args, const std::string& name) {
        const RunResult r =
            run_render(view + args + " --cells " + name + " -o " + name + ".png", dir);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        std::vector<Image> cells;
        for (const char* cell : {"lean_d3", "two-lobe_d3", "reference_d3"})
            cells.push_back(io::read_image((dir / name / (std::string(cell) + ".pfm")).string()));
        return cells;
    };
    auto expect_same = [](const std::vector<Image>& a, const std::vector<Image>& b,
                          const std::string& what) {
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_EQ(a[i].pixels.size(), b[i].pixels.size()) << what;
            std::size_t differing = 0;
            for (std::size_t k = 0; k < a[i].pixels.size(); ++k)
                differing += a[i].pixels[k] != b[i].pixels[k] ? 1 : 0;
            EXPECT_EQ(differing, 0u) << what << ", cell " << i;
        }
    };
    const auto plain = render("", "plain");
    const auto mapped = render("--specular-map half.pfm", "mapped");
    expect_same(mapped, render("--ks 0.5,0.5,0.5", "ks"), "Blinn-Phong");
    const auto ct_mapped = render("--brdf cook-torrance --specular-map half.pfm", "ct_mapped");
    expect_same(ct_mapped, render("--brdf cook-torrance --f0 0.02", "ct_f0"), "Cook-Torrance");
    // The map does something: the sphere's highlight is darker than without it.
    double with = 0.0, without = 0.0;
    for (std::size_t k = 0; k < plain[0].pixels.size(); ++k) {
        with += mapped[0].pixels[k];
        without += plain[0].pixels[k];
    }
    EXPECT_LT(with, without);
    // A grey PNG is replicated to RGB.
    const RunResult png = run_render(view + "--specular-map grey.png -o grey_out.png", dir);
    EXPECT_EQ(png.exit_code, 0) << png.err;

    expect_bad_map_errors(dir, "--size 32x32 --distances 3 --texture-size 32 ",
                          {
                              {"--specular-map missing.png", "missing.png"},
                              {"--specular-map negative.pfm",
                               "negative.pfm: value -0.25 at texel (2, 3)"},
                              {"--specular-map half.pfm --scene ocean", "--specular-map"},
                          });
    // The map is an input: an output never replaces it.
    const std::string before = read_text(dir / "half.pfm");
    const RunResult r = run_render(
        "--size 32x32 --distances 3 --texture-size 32 --scene sphere --techniques lean "
        "--specular-map half.pfm -o half.pfm",
        dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(read_text(dir / "half.pfm"), before);
}

// `--mixings`: a column per mixing method, and the metrics against the first as CSV and JSON;
// the coherent pair sine / -sine gives textures = height and approx far from it (Fig. 10).
TEST(CliRender, MixingsWritesTheLayerFigureAndItsTable) {
    const fs::path dir = scratch_dir("cli_render_mixings");
    const RunResult r = run_render(
        "--scene sphere --techniques lean --distances 3 --size 48x48 --layers sine,sine "
        "--layer-strengths 1,-1 --mixings height,textures,approx --bits 32f --texture-size 64 "
        "-o fig.png --table fig.csv",
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Image picture = io::read_image((dir / "fig.png").string());
    EXPECT_GT(picture.width, 3 * 48);
    std::ifstream csv(dir / "fig.csv");
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "distance,technique,mixing,reference,relative_rmse,energy_ratio");
    std::map<std::string, double> rmse;
    while (std::getline(csv, line)) {
        const std::vector<std::string> f = split(line, ',');
        ASSERT_EQ(f.size(), 6u) << line;
        rmse[f[2]] = std::stod(f[4]);
    }
    EXPECT_EQ(rmse.at("height"), 0.0);
    EXPECT_LT(rmse.at("textures"), 1e-3);
    EXPECT_GT(rmse.at("approx"), 0.1);
    EXPECT_TRUE(fs::exists(dir / "fig.json"));
}

// `bake --cross-terms A,B`: the pair's cross-term texture (docs/ktx2.md): layer 0 the slope
// products, layer 1 the two mean slopes, whose products equal layer 0 at the finest level only.
TEST(CliRender, BakeWritesTheCrossTermTexture) {
    const fs::path dir = scratch_dir("cli_bake_cross_terms");
    const RunResult r =
        run_leanfade_in("bake --cross-terms bumps,noise --size 32 -o pair.ktx2", dir, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const PackedLeanMap pair = io::read_cross_term_ktx2((dir / "pair.ktx2").string());
    ASSERT_EQ(pair.levels.size(), 6u);
    EXPECT_EQ(pair.storage, Storage::Float32);
    double level0 = 0.0, level2 = 0.0;
    for (int level : {0, 2})
        for (int y = 0; y < pair.levels[std::size_t(level)].height; ++y)
            for (int x = 0; x < pair.levels[std::size_t(level)].width; ++x) {
                const glm::vec4 p = fetch_packed_texel(pair, level, 0, x, y);
                const glm::vec4 b = fetch_packed_texel(pair, level, 1, x, y);
                const glm::vec4 q(b.x * b.z, b.y * b.w, b.x * b.w, b.z * b.y);
                const double d = std::abs(double(p.x - q.x)) + std::abs(double(p.y - q.y)) +
                                 std::abs(double(p.z - q.z)) + std::abs(double(p.w - q.w));
                (level == 0 ? level0 : level2) = std::max(level == 0 ? level0 : level2, d);
            }
    EXPECT_LT(level0, 1e-6);
    EXPECT_GT(level2, 1e-4);
    const RunResult bad = run_leanfade_in("bake --cross-terms bumps -o never.ktx2", dir, dir);
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_EQ(lines(bad.err), 1u) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "never.ktx2"));
}

// The image size limit (docs/robustness.md): refused on the header by default, --max-size
// lowers or raises it.
TEST(CliRender, MaxSizeLimitsTheBumpImage) {
    const fs::path dir = scratch_dir("cli_render_max_size");
    Image height(40, 24, 1);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 40; ++x) height.at(x, y, 0) = float((x * 7 + y * 3) % 11) / 10.0f;
    io::write_png((dir / "height.png").string(), height, 16);
    const std::string common = "--scene sphere --size 32x32 --techniques lean --distances 3 ";

    RunResult r = run_render(common + "--bumps height.png --max-size 32 -o never.png", dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("height.png: image size 40x24 exceeds the limit of 32 texels per side"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "never.png"));

    r = run_render(common + "--bumps height.png --max-size 0 -o never.png", dir);
    EXPECT_NE(r.exit_code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir / "never.png"));

    r = run_render(common + "--bumps height.png --max-size 40 -o ok.png", dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "ok.png"));
}

// --from defaults to auto, as in `leanfade bake`: an RGB image is read as a normal map, a
// grey one as a height map; --from overrides it.
TEST(CliRender, FromDefaultsToAutoAsBake) {
    const fs::path dir = scratch_dir("cli_render_from_auto");
    Image normals(32, 32, 3), height(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const float bx = 0.4f * std::sin(0.7f * float(x)),
                        by = 0.3f * std::cos(0.5f * float(y));
            const float inv = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
            normals.at(x, y, 0) = 0.5f - 0.5f * bx * inv;
            normals.at(x, y, 1) = 0.5f - 0.5f * by * inv;
            normals.at(x, y, 2) = 0.5f + 0.5f * inv;
            height.at(x, y, 0) = float((x * 5 + y * 3) % 7) / 6.0f;
        }
    io::write_png((dir / "normals.png").string(), normals, 16);
    io::write_png((dir / "height.png").string(), height, 16);
    const std::string common = "--scene sphere --size 48x48 --techniques lean --distances 3 ";
    auto render = [&](const std::string& args, const std::string& out) {
        const RunResult r = run_render(common + args + " -o " + out, dir);
        EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
        return read_text(dir / out);
    };
    const std::string normal_auto = render("--bumps normals.png", "n_auto.png");
    const std::string normal_explicit = render("--bumps normals.png --from normal", "n.png");
    const std::string normal_as_height = render("--bumps normals.png --from height", "n_h.png");
    EXPECT_FALSE(normal_auto.empty());
    EXPECT_EQ(normal_auto, normal_explicit);
    EXPECT_NE(normal_auto, normal_as_height);
    EXPECT_EQ(render("--bumps height.png", "h_auto.png"),
              render("--bumps height.png --from height", "h.png"));
}

// Determinism: the same command twice writes byte-identical files (same driver).
TEST(CliRender, SameCommandTwiceWritesIdenticalFiles) {
    const fs::path dir = scratch_dir("cli_render_twice");
    const std::string args =
        "--scene teapot --techniques bump,lean,fade,reference --distances 3,24 --size 48x40 "
        "--ref-samples 2 --texture-size 64 --msaa 4 --fog linear --fog-start 2 --fog-end 30 "
        "--cell-format pfm";
    for (const char* run : {"a", "b"}) {
        const RunResult r =
            run_render(args + " --cells cells_" + run + " -o grid_" + run + ".png", dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    EXPECT_EQ(read_text(dir / "grid_a.png"), read_text(dir / "grid_b.png"));
    std::size_t cells = 0;
    for (const auto& entry : fs::directory_iterator(dir / "cells_a")) {
        SCOPED_TRACE(entry.path().filename().string());
        EXPECT_EQ(read_text(entry.path()), read_text(dir / "cells_b" / entry.path().filename()));
        ++cells;
    }
    EXPECT_EQ(cells, 4u * 2u * 2u);  // 4 techniques x 2 distances, PNG and PFM
}

// GL faults: each is one line naming the cause, exit code 1 and no output file.

// glvnd's vendor file of Mesa's libEGL (Debian: libegl-mesa0), or "" when there is none.
std::string mesa_egl_vendor_file() {
    for (const char* folder : {"/usr/share/glvnd/egl_vendor.d", "/etc/glvnd/egl_vendor.d",
                               "/usr/local/share/glvnd/egl_vendor.d"}) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(folder, ec))
            if (entry.path().filename().string().find("mesa") != std::string::npos)
                return entry.path().string();
    }
    return {};
}

TEST(CliRenderGlFaults, NoEglDisplay) {
    const fs::path dir = scratch_dir("cli_render_no_display");
    // glvnd's libEGL with no vendor library: every platform gives EGL_NO_DISPLAY.
    const RunResult r = run_render("--scene sphere --size 32x32 -o never.png", dir,
                                   "-u LEANFADE_EGL_DEVICE "
                                   "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/no-vendor.json");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_EQ(r.err.rfind("leanfade render: EGL: no EGL display", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("no driver"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "never.png"));
}

TEST(CliRenderGlFaults, ContextBelowOpenGl45) {
    const fs::path dir = scratch_dir("cli_render_old_gl");
    const std::string mesa = mesa_egl_vendor_file();
    ASSERT_FALSE(mesa.empty()) << "Mesa's EGL vendor file was not found (Debian: libegl-mesa0)";
    // Mesa only (llvmpipe), told to offer OpenGL 3.3 at most: a driver too old for leanfade.
    const RunResult r =
        run_render("--scene sphere --size 32x32 -o never.png", dir,
                   "-u LEANFADE_EGL_DEVICE __EGL_VENDOR_LIBRARY_FILENAMES='" + mesa +
                       "' LIBGL_ALWAYS_SOFTWARE=1 MESA_GL_VERSION_OVERRIDE=3.3");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_EQ(r.err.rfind("leanfade render: EGL: no OpenGL 4.5 core context could be made", 0), 0u)
        << r.err;
    EXPECT_NE(r.err.find("offers OpenGL 3.3 core at most, below the required 4.5 core"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "never.png"));
}

TEST(CliRenderGlFaults, ShaderThatDoesNotCompileFromShaderDir) {
    const fs::path dir = scratch_dir("cli_render_broken_shader");
    const fs::path shaders = dir / "shaders";
    fs::create_directories(shaders);
    for (const auto& entry : fs::directory_iterator(fs::path(LEANFADE_SOURCE_DIR) / "shaders"))
        fs::copy_file(entry.path(), shaders / entry.path().filename());
    // An error on a known line of the shared header (included by scene.frag).
    std::string text = read_text(shaders / "lean_shading.glsl");
    if (!text.empty() && text.back() != '\n') text += '\n';
    const int line = 1 + int(std::count(text.begin(), text.end(), '\n'));
    text += "this is not GLSL;\n";
    std::ofstream(shaders / "lean_shading.glsl", std::ios::binary | std::ios::trunc) << text;

    const RunResult r = run_render("--scene sphere --size 32x32 --techniques lean --shader-dir '" +
                                       shaders.string() + "' -o never.png",
                                   dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    const std::string where = "leanfade render: " + (shaders / "lean_shading.glsl").string() +
                              ": line " + std::to_string(line) + ", column 1: error:";
    EXPECT_EQ(r.err.rfind(where, 0), 0u) << r.err;
    EXPECT_NE(r.err.find("fragment shader scene.frag"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "never.png"));
}

}  // namespace
}  // namespace leanfade::test

namespace leanfade::test {
namespace {

// Mean linear RGB of the pixels of `image` in columns [x0, x1) brighter than the background.
glm::vec3 mean_colour(const Image& image, int x0, int x1) {
    glm::dvec3 sum(0.0);
    int count = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = x0; x < x1; ++x) {
            const glm::vec3 c(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
            if (c.x + c.y + c.z < 0.02f) continue;
            sum += glm::dvec3(c);
            ++count;
        }
    return count > 0 ? glm::vec3(sum / double(count)) : glm::vec3(0.0f);
}

}  // namespace

// An OBJ with an MTL library of two materials (several per file, as exporters write them): the
// left quad red by Kd, the right one green by its map_Kd texture and bumpy by its map_Bump.
// render draws them with their materials unless --bumps is given.
TEST(CliRender, ObjMaterialsFromTheMtlAreUsed) {
    const fs::path dir = scratch_dir("cli_render_obj_mtl");
    {
        std::ofstream obj(dir / "two.obj");
        obj << "mtllib two.mtl\n"
               "v -2 -1 0\nv 0 -1 0\nv 0 1 0\nv -2 1 0\nv 2 -1 0\nv 2 1 0\n"
               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
               "usemtl Red\nf 1/1 2/2 3/3 4/4\n"
               "usemtl Textured Wood\nf 2/1 5/2 6/3 3/4\n";
        std::ofstream mtl(dir / "two.mtl");
        mtl << "# two materials\nnewmtl Red\nKd 0.8 0.05 0.05\nKs 0.2 0.2 0.2\nNs 200\n\n"
               "newmtl Textured Wood\nKd 1 1 1\nNs 96\nmap_Kd textures\\green.png\n"
               "map_Bump -bm 2 textures/height.png\n";
    }
    fs::create_directories(dir / "textures");
    Image green(8, 8, 3, 0.0f);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) green.at(x, y, 1) = 0.8f;
    io::write_png((dir / "textures" / "green.png").string(), green, 8);
    Image height(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            height.at(x, y) = 0.5f + 0.4f * std::sin(0.6f * float(x)) * std::cos(0.45f * float(y));
    io::write_png((dir / "textures" / "height.png").string(), height, 16);

    const std::string view =
        "--scene two.obj --techniques lean --distances 2.5 --size 64x32 --view-dir 0,0,1 ";
    const RunResult r = run_render(view + "--cells mtl --cell-format pfm -o mtl.png", dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Image image = io::read_image((dir / "mtl" / "lean_d2.5.pfm").string());
    const glm::vec3 left = mean_colour(image, 0, image.width / 2 - 2);
    const glm::vec3 right = mean_colour(image, image.width / 2 + 2, image.width);
    EXPECT_GT(left.x, 0.05f);
    EXPECT_GT(left.x, 3.0f * left.y) << "Kd of 'Red'";
    EXPECT_GT(right.y, 0.05f);
    EXPECT_GT(right.y, 3.0f * right.x) << "map_Kd of 'Textured Wood'";
    // --bumps flat replaces every MTL map and material: the default colours, no bumps.
    const RunResult flat = run_render(view +
                                          "--bumps flat --cells flat --cell-format pfm -o "
                                          "flat.png",
                                      dir);
    ASSERT_EQ(flat.exit_code, 0) << flat.err;
    const Image plain = io::read_image((dir / "flat" / "lean_d2.5.pfm").string());
    const glm::vec3 plain_left = mean_colour(plain, 0, plain.width / 2 - 2);
    EXPECT_LT(plain_left.x, 3.0f * plain_left.y) << "the default Kd with --bumps, not 'Red'";
    // The bumps of 'Textured Wood' spread its highlight: the right half's pixels vary.
    double spread = 0.0, plain_spread = 0.0;
    for (int y = 4; y < image.height - 4; ++y)
        for (int x = image.width / 2 + 4; x < image.width - 4; ++x) {
            spread += std::abs(image.at(x, y, 1) - image.at(x - 1, y, 1));
            plain_spread += std::abs(plain.at(x, y, 1) - plain.at(x - 1, y, 1));
        }
    EXPECT_GT(spread, 2.0 * plain_spread) << "the map_Bump of 'Textured Wood'";

    // Bad or missing MTL files and textures: one line naming the file, exit 1.
    const auto expect_error = [&](const std::string& obj_text, const std::string& mtl_text,
                                  const std::string& expected) {
        std::ofstream(dir / "bad.obj") << obj_text;
        if (!mtl_text.empty()) std::ofstream(dir / "bad.mtl") << mtl_text;
        const RunResult e = run_render(
            "--scene bad.obj --techniques lean --distances 2.5 "
            "--size 16x16 -o bad.png",
            dir);
        EXPECT_EQ(e.exit_code, 1) << expected;
        EXPECT_NE(e.err.find(expected), std::string::npos) << e.err;
        EXPECT_EQ(lines(e.err), 1u) << e.err;
    };
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n";
    expect_error("mtllib missing.mtl\nusemtl A\n" + quad, "", "missing.mtl");
    expect_error("mtllib ../outside.mtl\nusemtl A\n" + quad, "",
                 "mtllib '../outside.mtl' leaves the OBJ's folder");
    expect_error("mtllib bad.mtl\nusemtl A\n" + quad, "newmtl A\nKd 1 zero 1\n",
                 "bad.mtl: line 2: 'zero' is not a number");
    expect_error("mtllib bad.mtl\nusemtl A\n" + quad, "newmtl A\nmap_Kd /etc/passwd\n",
                 "map_Kd '/etc/passwd' is an absolute path");
    expect_error("mtllib bad.mtl\nusemtl A\n" + quad, "newmtl A\nmap_Bump nothere.png\n",
                 "nothere.png");
}

}  // namespace leanfade::test

namespace leanfade::test {

// --scene plane: the built-in sets keep uv 0..50; a map of one's own repeats 5 times across
// (uv times 0.1), so the same map from a .ktx2 draws as the built-in one at --tiling 10.
TEST(CliRender, PlaneTilesAMapOfOnesOwnFiveTimesAcross) {
    const fs::path dir = scratch_dir("cli_render_plane_tiling");
    ASSERT_EQ(run_leanfade_in("bake --builtin bumps --size 256 -o bumps.ktx2", dir, dir).exit_code,
              0);
    // The light of earlier versions' plane (now the plane's default is near the mirror).
    const std::string view =
        "--scene plane --techniques bump --distances 1.2 --size 64x64 "
        "--light-dir -1,1,1 --cell-format pfm ";
    auto render = [&](const std::string& args, const std::string& name) {
        const RunResult r =
            run_render(view + args + " --cells " + name + " -o " + name + ".png", dir);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return io::read_image((dir / name / "bump_d1.2.pfm").string());
    };
    const Image builtin = render("--bumps bumps --texture-size 256", "builtin");
    const Image own = render("--bumps bumps.ktx2", "own");
    const Image own_tiled = render("--bumps bumps.ktx2 --tiling 10", "own_tiled");
    auto mean_difference = [](const Image& a, const Image& b) {
        double sum = 0.0;
        for (std::size_t i = 0; i < a.pixels.size(); ++i)
            sum += std::abs(a.pixels[i] - b.pixels[i]);
        return sum / double(a.pixels.size());
    };
    double mean = 0.0;
    for (float v : builtin.pixels) mean += v;
    mean /= double(builtin.pixels.size());
    // uv * 0.1 * 10 is the built-in's uv up to float rounding.
    EXPECT_LT(mean_difference(own_tiled, builtin), 0.01 * mean);
    // Tiled 50 times the bumps are finer than the pixels and vanish (the map's mean shading);
    // 5 times they are seen: neighbouring pixels differ.
    auto spread = [](const Image& image) {
        double sum = 0.0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 1; x < image.width; ++x)
                sum += std::abs(image.at(x, y, 0) - image.at(x - 1, y, 0));
        return sum;
    };
    EXPECT_GT(spread(own), 3.0 * spread(builtin)) << "the own map is not tiled 5 times";
}

}  // namespace leanfade::test

namespace leanfade::test {

// render notes a reference that has not converged, by eval's measure (its specular energy
// against a quarter of the samples): steep bumps with a sharp highlight at 8x8 samples, not the
// default bumps.
TEST(CliRender, NotesAReferenceThatHasNotConverged) {
    const fs::path dir = scratch_dir("cli_render_reference_noise");
    const std::string view =
        "--scene sphere --techniques lean,reference --distances 1.6,12 "
        "--size 64x64 --ref-samples 8 ";
    const RunResult steep =
        run_render(view + "--bumps noise --strength 6 --shininess 13777 -o steep.png", dir);
    ASSERT_EQ(steep.exit_code, 0) << steep.err;
    EXPECT_NE(steep.err.find("leanfade render: note: the reference at distance 12 has not "
                             "converged (its specular energy is uncertain by "),
              std::string::npos)
        << steep.err;
    EXPECT_NE(steep.err.find("with 8x8 samples; raise --ref-samples)"), std::string::npos);
    const RunResult gentle = run_render(view + "--bumps bumps -o gentle.png", dir);
    ASSERT_EQ(gentle.exit_code, 0) << gentle.err;
    EXPECT_EQ(gentle.err, "");
}

}  // namespace leanfade::test
