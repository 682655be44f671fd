// Help texts derived from the tables: every rendering command's help names every built-in scene
// of kBuiltinScenes and every technique it accepts from kTechniques, and the bake-source and
// storage choices of --from and --bits come from their lists. A new table row that a help text
// misses fails here.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "tools_test_helpers.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

// The help of one option: from its line ("  --scene TEXT=...") to the next option's line.
std::string option_help(const std::string& help, const std::string& option) {
    const std::string start = "  " + option + " ";
    std::size_t at = help.find("\n" + start);
    if (at == std::string::npos) return {};
    ++at;
    std::size_t end = help.find("\n  -", at + 1);
    return help.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

std::string help_of(const std::string& command, const fs::path& dir) {
    const RunResult r = run_leanfade(command + " --help", dir);
    EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
    return r.out;
}

std::vector<std::string> rendering_commands() {
    std::vector<std::string> commands{"render", "eval", "calibrate", "bench"};
#ifdef LEANFADE_TEST_VIEWER
    commands.push_back("view");
#endif
    return commands;
}

TEST(CliHelp, EveryRenderingCommandNamesEveryBuiltinScene) {
    const fs::path dir = scratch_dir("cli_help_scenes");
    for (const std::string& command : rendering_commands()) {
        const std::string help = help_of(command, dir);
        const std::string option = command == "bench" ? "--scenes" : "--scene";
        const std::string text = option_help(help, option);
        ASSERT_FALSE(text.empty()) << command << " has no " << option;
        for (const scene::BuiltinScene& s : scene::kBuiltinScenes)
            EXPECT_NE(text.find(std::string(s.name)), std::string::npos)
                << command << " " << option << " misses '" << s.name << "': " << text;
        EXPECT_NE(text.find(".obj"), std::string::npos) << command;
        EXPECT_NE(text.find(".gltf"), std::string::npos) << command;
    }
}

TEST(CliHelp, TechniqueOptionsNameEveryTechniqueTheyAccept) {
    const fs::path dir = scratch_dir("cli_help_techniques");
    struct Case {
        std::string command, option;
        std::vector<Technique> accepted;
    };
    std::vector<Case> cases{{"render", "--techniques", all_techniques()},
                            {"eval", "--techniques", approximating_techniques()},
                            {"bench", "--techniques", approximating_techniques()}};
#ifdef LEANFADE_TEST_VIEWER
    cases.push_back({"view", "--technique", all_techniques()});
    cases.push_back({"view", "--techniques", all_techniques()});
#endif
    for (const Case& c : cases) {
        const std::string text = option_help(help_of(c.command, dir), c.option);
        ASSERT_FALSE(text.empty()) << c.command << " has no " << c.option;
        for (Technique t : c.accepted)
            EXPECT_NE(text.find(std::string(info(t).name)), std::string::npos)
                << c.command << " " << c.option << " misses '" << info(t).name << "': " << text;
    }
}

TEST(CliHelp, BumpSourceAndStorageChoicesComeFromTheirLists) {
    const fs::path dir = scratch_dir("cli_help_choices");
    std::vector<std::string> commands = rendering_commands();
    commands.push_back("bake");
    for (const std::string& command : commands) {
        const std::string help = help_of(command, dir);
        const std::string from = option_help(help, "--from");
        const std::string bits = option_help(help, "--bits");
        ASSERT_FALSE(from.empty()) << command;
        ASSERT_FALSE(bits.empty()) << command;
        for (const std::string& name : bake_source_names())
            EXPECT_NE(from.find(name), std::string::npos) << command << " --from: " << from;
        for (const std::string& name : bake_storage_names())
            EXPECT_NE(bits.find(name), std::string::npos) << command << " --bits: " << bits;
    }
#ifdef LEANFADE_TEST_VIEWER
    const std::string layout = option_help(help_of("view", dir), "--layout");
    for (const std::string& name : preset_layouts())
        EXPECT_NE(layout.find(name), std::string::npos) << "view --layout: " << layout;
#endif
}

TEST(CliHelp, OptionHelpReadsOneOptionOnly) {
    const std::string help =
        "Options:\n  --scene TEXT=teapot         Object: sphere\n  --techniques TEXT=lean  x\n";
    EXPECT_EQ(option_help(help, "--scene"), "  --scene TEXT=teapot         Object: sphere");
    EXPECT_EQ(option_help(help, "--size"), "");
}

}  // namespace
}  // namespace leanfade::test
