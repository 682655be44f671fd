#pragma once
// The leanfade command line, callable without main(): builds the CLI11 app from the registered
// subcommands (command.hpp), parses argv and runs the chosen subcommand. main() is one call to
// run_leanfade; the command-line fuzz target (fuzz/fuzz_cli.cpp) calls it with parse_only.
namespace leanfade::cli {

struct RunOptions {
    // Parse (and validate) the arguments, then return without running the subcommand.
    bool parse_only = false;
};

// Returns the process exit code: 0 success; 1 a leanfade::Error (printed as one line on stderr);
// 2 a command-line error (one line on stderr); 3 an unexpected exception. --help and --version
// print to stdout and return 0. Never calls exit().
int run_leanfade(int argc, const char* const* argv, const RunOptions& options = {});

}  // namespace leanfade::cli
