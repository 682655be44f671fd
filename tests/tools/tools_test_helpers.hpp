#pragma once
// Helpers of the CLI tests in tests/tools: the runner, and a scratch folder per test.
#include <filesystem>
#include <string>

#include "cli_runner.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::test {

// A fresh, empty scratch folder under the build's test-tmp, named after the test.
inline std::filesystem::path scratch_dir(const std::string& name) {
    return fresh_scratch_folder(".", name);
}

}  // namespace leanfade::test
