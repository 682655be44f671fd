#pragma once
// Subcommand registry of the `leanfade` executable: one small file per subcommand (cmd_*.cpp)
// registers itself with a static LEANFADE_COMMAND(...) object. setup() adds the subcommand's
// options to CLI11 and returns the function that runs it; that function returns the exit code
// and may throw leanfade::Error, which main() prints as one line.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace leanfade::cli {

using Runner = std::function<int()>;
using Setup = std::function<Runner(CLI::App& subcommand)>;

struct Command {
    std::string name;
    std::string description;
    Setup setup;
};

std::vector<Command>& command_registry();

struct CommandRegistration {
    CommandRegistration(std::string name, std::string description, Setup setup) {
        command_registry().push_back({std::move(name), std::move(description), std::move(setup)});
    }
};

// True when stderr is a terminal: progress lines are shown only then.
bool stderr_is_terminal();

}  // namespace leanfade::cli
