// Presets on the command line: `render --preset FILE` draws what the same values given as flags
// draw (scene, bump layers, mixing, techniques, camera), and a flag given on the command line
// replaces the preset's value, byte for byte.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

// The PNG `render ARGS` writes (empty when it fails).
std::string rendered(const fs::path& dir, const std::string& args, const std::string& name) {
    const fs::path picture = dir / name;
    const RunResult r =
        run_leanfade("render " + args + " --size 32x32 -o " + shell_quote(picture.string()), dir);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
    return fs::exists(picture) ? read_text(picture) : std::string();
}

TEST(CliPresets, PresetLayersRenderAsTheirFlags) {
    const fs::path dir = fresh_scratch_folder("cli_presets", "layers");
    {
        std::ofstream preset(dir / "p.json");
        preset << R"({
  "leanfade_preset": 1,
  "scene": "sphere",
  "bumps": {"texture_size": 32, "bits": "16"},
  "layers": {"sources": ["bumps", "noise"], "weights": [0.25, 0.75], "mixing": "approx"},
  "camera": {"distance": 3, "direction": [0.2, 0.3, 1]},
  "view": {"techniques": ["lean", "fade"], "layout": "side-by-side"}
})";
    }
    const std::string preset = "--preset " + shell_quote((dir / "p.json").string());
    auto flags = [](const std::string& weights) {
        return "--scene sphere --texture-size 32 --bits 16 --layers bumps,noise --layer-weights " +
               weights +
               " --mixing approx --distances 3 --view-dir 0.2,0.3,1 --techniques lean,fade";
    };
    const std::string from_preset = rendered(dir, preset, "preset.png");
    ASSERT_FALSE(from_preset.empty());
    EXPECT_EQ(from_preset, rendered(dir, flags("0.25,0.75"), "flags.png"));

    // A flag given replaces the preset's value; the others stay the preset's.
    const std::string reweighted = rendered(dir, preset + " --layer-weights 0.75,0.25", "w.png");
    EXPECT_NE(reweighted, from_preset);
    EXPECT_EQ(reweighted, rendered(dir, flags("0.75,0.25"), "w_flags.png"));
    // --bumps replaces the preset's layers with one map.
    EXPECT_EQ(rendered(dir, preset + " --bumps noise", "one.png"),
              rendered(dir,
                       "--scene sphere --texture-size 32 --bits 16 --bumps noise --distances 3 "
                       "--view-dir 0.2,0.3,1 --techniques lean,fade",
                       "one_flags.png"));
}

}  // namespace
}  // namespace leanfade::test
