// The leanfade command line: the subcommand registry, CLI11 parsing and one-line error reports.
#include "cli_app.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "cli_flags.hpp"
#include "command.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"

namespace leanfade::cli {
namespace {

// One line on stderr: the message whole (a NUL or newline in a name does not cut it) and made
// safe for the terminal (terminal_text).
void print_error_line(const std::string& prefix, const std::string& message,
                      const std::string& suffix = {}) {
    const std::string line = prefix + terminal_text(message) + suffix + "\n";
    std::fwrite(line.data(), 1, line.size(), stderr);
}

}  // namespace

std::vector<Command>& command_registry() {
    static std::vector<Command> commands;
    return commands;
}

bool stderr_is_terminal() {
    return isatty(STDERR_FILENO) != 0;
}

int run_leanfade(int argc, const char* const* argv, const RunOptions& options) {
    CLI::App app{std::string("leanfade: LEAN mapping and specular fading toolkit (version ") +
                     LEANFADE_VERSION + ")",
                 "leanfade"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("leanfade ") + LEANFADE_VERSION);

    auto& commands = command_registry();
    std::sort(commands.begin(), commands.end(),
              [](const Command& a, const Command& b) { return a.name < b.name; });
    std::vector<std::pair<CLI::App*, Runner>> runners;
    for (const Command& command : commands) {
        CLI::App* sub = app.add_subcommand(command.name, command.description);
        runners.emplace_back(sub, command.setup(*sub));
    }

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line, naming the cause; CLI11's default adds a second line.
        print_error_line("leanfade: ", e.what(), " (see leanfade --help)");
        return 2;
    } catch (const leanfade::Error& e) {
        // A flag's value that its typed conversion refused (cli_text.hpp: add_typed_option),
        // reported as the subcommand reports the errors of its run.
        const Error named = with_flag_name(e);
        const std::vector<CLI::App*> parsed = app.get_subcommands();
        print_error_line(
            parsed.empty() ? std::string("leanfade: ")
                           : "leanfade " + parsed.front()->get_name() + ": ",
            named.file().empty() ? named.cause() : named.file() + ": " + named.cause());
        return 1;
    }
    if (options.parse_only) return 0;

    for (auto& [sub, run] : runners) {
        if (!sub->parsed()) continue;
        try {
            return run();
        } catch (const leanfade::Error& e) {
            // Libraries name settings; the command line names their flags.
            const Error named = with_flag_name(e);
            print_error_line(
                "leanfade " + sub->get_name() + ": ",
                named.file().empty() ? named.cause() : named.file() + ": " + named.cause());
            return 1;
        } catch (const std::exception& e) {
            print_error_line("leanfade " + sub->get_name() + ": internal error: ", e.what());
            return 3;
        }
    }
    return 2;
}

}  // namespace leanfade::cli
