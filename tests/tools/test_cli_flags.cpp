// The command line derives its shading flags from the parameter schema and prints the settings
// the libraries name in errors as those flags (tools/leanfade/cli_flags.hpp).
#include <gtest/gtest.h>

#include "cli_flags.hpp"
#include "cli_runner.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "tools_test_helpers.hpp"

namespace leanfade::test {
namespace {

TEST(CliFlags, SettingsMapToTheirFlags) {
    EXPECT_EQ(cli::flag_for_setting("fade_exponent"), "--fade-exponent");
    EXPECT_EQ(cli::flag_for_setting("light_direction"), "--light-dir");
    EXPECT_EQ(cli::flag_for_setting("bump_strength"), "--strength");
    EXPECT_EQ(cli::flag_for_setting("anisotropy"), "--aniso");
    EXPECT_EQ(cli::flag_for_setting("ref_samples"), "--ref-samples");
    EXPECT_EQ(cli::flag_for_setting("distances"), "--distances");
    EXPECT_EQ(cli::flag_for_setting("layer-tiling"), "--layer-tiling");
    EXPECT_EQ(cli::flag_for_setting("layers"), "--layers");
    EXPECT_EQ(cli::flag_for_setting("--from"), "--from") << "a flag already";
    // A setting error names the flag; a file error (a file name, "GL") keeps its subject, even
    // one spelled like a setting: the kind says which it is, not the name.
    EXPECT_EQ(cli::with_flag_name(Error::setting("shininess", "must be > 0")).what(),
              std::string("--shininess: must be > 0"));
    EXPECT_EQ(cli::with_flag_name(Error("a.png", "empty file")).what(),
              std::string("a.png: empty file"));
    EXPECT_EQ(cli::with_flag_name(Error("size", "a file named size")).what(),
              std::string("size: a file named size"));
    // The settings a cause quotes are flags where the library listed them, and only there.
    const Error mentioning = Error::file_mentioning(
        "n.png", "refused by 'strict_normals' (read it with 'from' height; 'size' is a word)",
        {"strict_normals", "from"});
    EXPECT_EQ(mentioning.kind(), ErrorKind::File);
    EXPECT_EQ(mentioning.setting(), "");
    EXPECT_EQ(cli::with_flag_name(mentioning).what(),
              std::string("n.png: refused by --strict-normals (read it with --from height; "
                          "'size' is a word)"));
    const Error setting = Error::setting("layer-tiling", "as 'tiling', 'tiling'", {"tiling"});
    EXPECT_EQ(setting.kind(), ErrorKind::Setting);
    EXPECT_EQ(setting.setting(), "layer-tiling");
    EXPECT_EQ(cli::with_flag_name(setting).what(),
              std::string("--layer-tiling: as --tiling, --tiling"));
}

// Every row of the schema is a flag of the commands that render, with its help text.
TEST(CliFlags, EveryParameterIsAFlagOfTheRenderingCommands) {
    for (const char* command : {"render", "view", "eval", "calibrate", "bench"}) {
        const RunResult r =
            run_leanfade(std::string(command) + " --help", scratch_dir("cli_flags_help"));
        ASSERT_EQ(r.exit_code, 0) << command << ": " << r.err;
        for (const ParameterInfo& row : shading_parameters()) {
            const std::string flag = cli::flag_for_setting(row.key);
            EXPECT_NE(r.out.find(flag + " "), std::string::npos) << command << " " << flag;
            // eval sweeps a list of shininesses under the same flag, with its own help.
            if (std::string(command) == "eval" && row.key == "shininess") continue;
            EXPECT_NE(r.out.find(std::string(row.help)), std::string::npos)
                << command << " " << flag;
        }
    }
}

// The base roughness map (docs/roughness.md) beside the source flags of every rendering command.
TEST(CliFlags, RoughnessMapIsAFlagOfTheRenderingCommands) {
    for (const char* command : {"render", "view", "eval", "calibrate", "bench"}) {
        const RunResult r =
            run_leanfade(std::string(command) + " --help", scratch_dir("cli_flags_roughness_map"));
        ASSERT_EQ(r.exit_code, 0) << command << ": " << r.err;
        EXPECT_NE(r.out.find("--roughness-map "), std::string::npos) << command;
    }
}

TEST(CliFlags, ARangeErrorNamesTheFlag) {
    const RunResult r =
        run_leanfade("render --fade-exponent 0 -o never.png", scratch_dir("cli_flags_range"));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.err, "leanfade render: --fade-exponent: must be > 0, got 0\n");
}

}  // namespace
}  // namespace leanfade::test
