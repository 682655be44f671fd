// The leanfade command line: the subcommand registry, CLI11 parsing and one-line error reports.
#include "cli_app.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "cli_flags.hpp"
#include "command.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {
namespace {

// One line on stderr: the message whole (a NUL or newline in a name does not cut it) and made
// safe for the terminal (terminal_text).
void print_error_line(const std::string& prefix, const std::string& message,
                      const std::string& suffix = {}) {
    const std::string line = prefix + terminal_text(message) + suffix + "\n";
    std::fwrite(line.data(), 1, line.size(), stderr);
}

// Reaches CLI::Option's protected members (a derived class may name them through a
// pointer to member): the type name of the value and the validators, in their order.
struct OptionInternals : CLI::Option {
    static std::string value_type(CLI::Option& option) {
        return (option.*(&OptionInternals::type_name_))();
    }
    static std::vector<CLI::Validator>& validators(CLI::Option& option) {
        return option.*(&OptionInternals::validators_);
    }
};

// True for CLI11's type names of numbers (INT, UINT, FLOAT, NUMBER, also inside a tuple's or a
// vector's "[FLOAT,FLOAT]").
bool is_number_type(const std::string& name) {
    std::string word;
    for (std::size_t i = 0; i <= name.size(); ++i) {
        if (i < name.size() && std::isalpha(static_cast<unsigned char>(name[i])) != 0) {
            word += name[i];
            continue;
        }
        if (word == "INT" || word == "UINT" || word == "FLOAT" || word == "NUMBER") return true;
        word.clear();
    }
    return false;
}

// CLI11 assigns an empty value to a number as 0 (or its type's empty value) without a word, and
// its range validators print their bounds in full ("--bake-roughness ''" printed a 309-digit
// number). Every numeric option of `app` and its subcommands gets, as its first check, the
// refusal of an empty value: "--seed: not a number (the value is empty)", exit 2.
void refuse_empty_numbers(CLI::App& app) {
    const CLI::Validator not_empty(
        [](std::string& text) {
            return text.empty() ? std::string("not a number (the value is empty)") : std::string();
        },
        std::string(), "not empty");
    for (CLI::Option* option : app.get_options()) {
        if (!is_number_type(OptionInternals::value_type(*option))) continue;
        auto& checks = OptionInternals::validators(*option);
        checks.insert(checks.begin(), not_empty);
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        refuse_empty_numbers(*sub);
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
    app.set_version_flag("--version", std::string(LEANFADE_GENERATOR));

    auto& commands = command_registry();
    std::sort(commands.begin(), commands.end(),
              [](const Command& a, const Command& b) { return a.name < b.name; });
    std::vector<std::pair<CLI::App*, Runner>> runners;
    for (const Command& command : commands) {
        CLI::App* sub = app.add_subcommand(command.name, command.description);
        runners.emplace_back(sub, command.setup(*sub));
    }
    refuse_empty_numbers(app);

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
