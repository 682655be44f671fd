// Flags and inputs outside the range leanfade can compute with: a thread count no machine needs,
// a light direction or shininess whose math is not finite in float, an OBJ whose coordinates
// overflow, eval distances the object vanishes at or rounds together. Each is one line naming
// the flag or file and what is wrong (docs/robustness.md), never an abort, a NaN or a
// misleading cause.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
    return leanfade::test::fresh_scratch_folder("cli_limits", name);
}

std::size_t lines(const std::string& text) {
    return std::size_t(std::count(text.begin(), text.end(), '\n'));
}

// Before: the 10000 threads were started (or std::terminate ran when the system refused some).
TEST(CliLimits, BenchBakeRefusesMoreThreadsThanBakeTakes) {
    const fs::path dir = scratch("threads");
    const RunResult r =
        run_leanfade_bounded("bench --bake --bake-sizes 16 --bake-runs 1 --threads 10000", dir, 60);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err, "leanfade bench: --threads: must be in [0, 256] (0 = all hardware threads), "
                     "got 10000\n");
    const RunResult bake = run_leanfade_bounded(
        "bake --builtin bumps --size 8 --threads 10000 -o " + shell_quote((dir / "b.ktx2").string()),
        dir);
    EXPECT_EQ(bake.exit_code, 2) << bake.err;
    EXPECT_NE(bake.err.find("--threads"), std::string::npos) << bake.err;
    EXPECT_FALSE(fs::exists(dir / "b.ktx2"));
}

// Before: both rendered black specular (NaN) and exited 0.
TEST(CliLimits, ShadingFlagsWhoseMathIsNotFiniteAreRefused) {
    const fs::path dir = scratch("shading");
    const struct {
        const char* flags;
        const char* message;
    } cases[] = {
        {"--light-dir 1e-30,1e-30,0",
         "leanfade render: --light-dir: its length must be in [1e-06, 1e+06] (it is normalised), "
         "got 1.41421e-30\n"},
        {"--light-dir 1e30,0,0",
         "leanfade render: --light-dir: its length must be in [1e-06, 1e+06] (it is normalised), "
         "got 1e+30\n"},
        {"--shininess 1e-45", "leanfade render: --shininess: must be in [0.001, 1e+07], got "
                              "1.4013e-45\n"},
        {"--shininess 1e30", "leanfade render: --shininess: must be in [0.001, 1e+07], got "
                             "1e+30\n"},
        {"--ks 1e30", "leanfade render: --ks: colour components must be <= 1e+06, got 1e+30\n"},
        {"--tiling 1e30", "leanfade render: --tiling: must be in (0, 1e+06], got 1e+30\n"},
    };
    for (const auto& c : cases) {
        const RunResult r = run_leanfade_bounded(
            std::string("render --scene sphere --techniques lean --distances 3 --size 16x16 ") +
                c.flags + " -o " + shell_quote((dir / "out.png").string()),
            dir);
        EXPECT_EQ(r.exit_code, 1) << c.flags << ": " << r.err;
        EXPECT_EQ(r.err, c.message) << c.flags;
        EXPECT_FALSE(fs::exists(dir / "out.png")) << c.flags;
    }
}

// Before: "the mesh's bounding radius is zero" (the float difference of the coordinates
// overflowed to infinity).
TEST(CliLimits, ObjCoordinatesTooLargeToScaleNameTheRadius) {
    const fs::path dir = scratch("obj");
    std::ofstream(dir / "huge.obj") << "v -3e38 -3e38 0\nv 3e38 -3e38 0\nv 0 3e38 0\n"
                                       "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n";
    const RunResult r = run_leanfade_bounded(
        "render --scene " + shell_quote((dir / "huge.obj").string()) +
            " --techniques lean --distances 3 --size 16x16 -o " +
            shell_quote((dir / "out.png").string()),
        dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err,
              "leanfade render: huge: the vertex positions span a bounding radius of 4.24e+38 "
              "units; the renderer scales objects to radius 1 in float, which needs a radius in "
              "[1e-12, 1e12]\n");
    EXPECT_FALSE(fs::exists(dir / "out.png"));
}

// Before: "distance 101 given twice" (3 significant digits could not tell the 1000 distances
// apart), although the user gave each once.
TEST(CliLimits, FineDistanceRangesAreDistinctNotGivenTwice) {
    const std::vector<float> d = eval::parse_distance_sweep("2:1000:1000", "--distances");
    ASSERT_EQ(d.size(), 1000u);
    EXPECT_EQ(d.front(), 2.0f);
    EXPECT_EQ(d.back(), 1000.0f);
    for (std::size_t i = 1; i < d.size(); ++i) EXPECT_LT(d[i - 1], d[i]) << i;
    // Coarse ranges keep 3 significant digits.
    EXPECT_EQ(eval::parse_distance_sweep("2:64:10", "--distances")[1], 2.94f);
    try {
        eval::parse_distance_sweep("1.0000001:1.0000002:1000", "--distances");
        FAIL() << "distances float cannot tell apart were accepted";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "--distances: A:B:N: 1000 distances from 1.0000001 to 1.0000002 are closer "
                  "than float numbers tell apart; give fewer or a wider range");
    }
    EXPECT_THROW(eval::parse_distance_sweep("3,3", "--distances"), Error) << "given twice";

    const fs::path dir = scratch("distances");
    const RunResult r = run_leanfade_bounded(
        "eval --distances 2:1000:1000 --frames 1 --out " + shell_quote((dir / "o").string()), dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err.find("given twice"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--frames"), std::string::npos) << "the next check is reached: " << r.err;
}

// Before: eval ran and reported NaN metrics (the object covers no pixel at 1e30 radii).
TEST(CliLimits, EvalDistancesBeyondTheBoundAreRefused) {
    const fs::path dir = scratch("far");
    const RunResult r = run_leanfade_bounded(
        "eval --distances 1e30 --out " + shell_quote((dir / "o").string()), dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err,
              "leanfade eval: --distances: distances must be at most 1e4 bounding radii (the "
              "object covers far less than a pixel beyond), got 1e30\n");
    EXPECT_EQ(lines(r.err), 1u);
    EXPECT_FALSE(fs::exists(dir / "o"));
    EXPECT_THROW(eval::parse_distance_sweep("2:1e30:4", "--distances"), Error);
}

// Every flag's text becomes a typed value when the command line is parsed: bad text is one line
// naming the subcommand, the flag and the cause, exit 1, before anything is read or written.
TEST(CliTypedFlags, BadTextIsRefusedWhenParsed) {
    const fs::path dir = scratch("typed");
    const std::string out = " -o " + shell_quote((dir / "o.png").string());
    const struct {
        std::string command;
        std::string message;
    } cases[] = {
        {"render --layers bumps,noise --mixings height,blend" + out,
         "leanfade render: --mixings: unknown mixing method 'blend' (expected height, textures, "
         "approx)\n"},
        {"render --layers bumps,noise --mixing blend" + out,
         "leanfade render: --mixing: unknown mixing method 'blend' (expected height, textures, "
         "approx)\n"},
        {"render --layers bumps,noise --layer-velocity 1" + out,
         "leanfade render: --layer-velocity: expected U:V per layer, got '1'\n"},
        {"render --layers bumps,noise --layer-weights 0.5,x" + out,
         "leanfade render: --layer-weights: expected a finite number, got 'x'\n"},
        {"render --techniques bump,phong" + out,
         "leanfade render: --techniques: unknown technique 'phong' (expected " +
             technique_names(all_techniques()) + ")\n"},
        {"render --size 10x10" + out,
         "leanfade render: --size: each side must be in [16, 8192] pixels, got '10x10'\n"},
        {"render --fov 170" + out, "leanfade render: --fov: must be in (1, 170) degrees, got 170\n"},
        {"render --view-dir 0,0,0" + out,
         "leanfade render: --view-dir: must not be the zero vector\n"},
        {"render --target 1,2" + out, "leanfade render: --target: expected X,Y,Z, got '1,2'\n"},
        {"render --from heightmap" + out,
         "leanfade render: --from: expected auto, height or normal, got 'heightmap'\n"},
        {"eval --distances 0.5 --out " + shell_quote((dir / "e").string()),
         "leanfade eval: --distances: distances are in bounding radii from the object's centre "
         "and must be > 1, got 0.5\n"},
        {"calibrate --target exp:x", "leanfade calibrate: --target: "},
        {"bench --timing fast", "leanfade bench: --timing: "},
        {"bench --bake-input png", "leanfade bench: --bake-input: expected normal or height, got "
                                   "'png'\n"},
        {"bench --scenes sphere,sphere",
         "leanfade bench: --scenes: scene 'sphere' given twice\n"},
    };
    for (const auto& c : cases) {
        const RunResult r = run_leanfade_bounded(c.command, dir, 60);
        EXPECT_EQ(r.exit_code, 1) << c.command << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << c.command << ": " << r.err;
        if (c.message.back() == '\n')
            EXPECT_EQ(r.err, c.message) << c.command;
        else
            EXPECT_EQ(r.err.rfind(c.message, 0), 0u) << c.command << ": " << r.err;
        EXPECT_TRUE(r.out.empty()) << c.command << ": " << r.out;
    }
    EXPECT_FALSE(fs::exists(dir / "o.png"));
    EXPECT_FALSE(fs::exists(dir / "e"));
}

// The layers' counts and ranges are checked once, by the library, and named by their flags.
TEST(CliTypedFlags, LayerRulesNameTheirFlags) {
    const fs::path dir = scratch("layer_rules");
    const std::string out = " --size 16x16 -o " + shell_quote((dir / "o.png").string());
    const struct {
        std::string flags;
        std::string message;
    } cases[] = {
        {"--layers bumps",
         "leanfade render: --layers: 2 to 4 sources, got 1 (a single map is the bump source, not "
         "a layer)\n"},
        {"--layers bumps,noise --layer-weights 0.3,0.3",
         "leanfade render: --layer-weights: weights must sum to 1, got 0.600000\n"},
        {"--layers bumps,noise --layer-tiling 1,2,3",
         "leanfade render: --layer-tiling: one value per layer: 2 layers, 3 values\n"},
        {"--layers bumps,noise --layer-tiling 1,-2",
         "leanfade render: --layer-tiling: each tiling must be in (0, 1e+06], as --tiling, got "
         "-2\n"},
    };
    for (const auto& c : cases) {
        const RunResult r = run_leanfade_bounded("render " + c.flags + out, dir, 60);
        EXPECT_EQ(r.exit_code, 1) << c.flags << ": " << r.err;
        EXPECT_EQ(r.err, c.message) << c.flags;
    }
    EXPECT_FALSE(fs::exists(dir / "o.png"));
}

// A preset's layers and maps are checked by the preset's reader, naming the file and the key,
// and a map kind that the rendering commands do not take is refused by name.
TEST(CliTypedFlags, PresetLayersAndMapsAreChecked) {
    const fs::path dir = scratch("preset_layers");
    const struct {
        std::string json;
        std::string cause;
    } cases[] = {
        {R"({"layers": {"sources": ["bumps"]}})", "key 'layers.sources': 2 to 4 sources, got 1"},
        {R"({"layers": {"sources": ["bumps", "noise"], "weights": [0.3, 0.3]}})",
         "key 'layers.weights': weights must sum to 1"},
        {R"({"maps": {"base_color_map": "x.png"}})",
         "key 'maps.base_color_map': unknown map (expected roughness_map, roughness_mips, specular_map)"},
    };
    for (const auto& c : cases) {
        {
            std::ofstream file(dir / "p.json");
            file << c.json;
        }
        const RunResult r = run_leanfade_bounded(
            "render --preset " + shell_quote((dir / "p.json").string()) +
                " --size 16x16 -o " + shell_quote((dir / "o.png").string()),
            dir, 60);
        EXPECT_EQ(r.exit_code, 1) << c.json << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find("p.json: " + c.cause), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "o.png"));
}

}  // namespace
}  // namespace leanfade::test
