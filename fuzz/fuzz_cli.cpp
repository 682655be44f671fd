// Fuzz target: the command-line parser of `leanfade` (CLI11 app with every registered subcommand,
// their options and validators), parse only: the subcommands never run, so no file is touched.
// The input is split into arguments at newlines (at most 64 arguments); run the target with
// -close_fd_mask=3, as `make fuzz` does, to silence the help and error text.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cli_app.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    constexpr std::size_t kMaxArguments = 64;
    std::vector<std::string> words = {"leanfade"};
    std::string word;
    for (std::size_t i = 0; i < size && words.size() < kMaxArguments; ++i) {
        if (data[i] == '\n') {
            words.push_back(word);
            word.clear();
        } else {
            word.push_back(char(data[i]));
        }
    }
    if (words.size() < kMaxArguments) words.push_back(word);
    std::vector<const char*> argv;
    for (const std::string& w : words) argv.push_back(w.c_str());
    argv.push_back(nullptr);

    leanfade::cli::RunOptions options;
    options.parse_only = true;
    const int code = leanfade::cli::run_leanfade(int(words.size()), argv.data(), options);
    if (code != 0 && code != 2) __builtin_trap();  // parsing alone gives 0 or 2
    return 0;
}
