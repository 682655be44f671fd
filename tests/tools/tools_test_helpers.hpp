#pragma once
// Helpers of the CLI tests in tests/tools: the runner, and a scratch folder per test.
#include <filesystem>
#include <string>

#include "cli_runner.hpp"

namespace leanfade::test {

// A fresh, empty scratch folder under the build's test-tmp, named after the test.
inline std::filesystem::path scratch_dir(const std::string& name) {
    const auto dir = std::filesystem::path(LEANFADE_TEST_TMP) / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace leanfade::test
