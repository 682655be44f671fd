#pragma once
// The one scratch-folder helper of the test suites: every test writes its files under the
// build's LEANFADE_TEST_TMP (tests/CMakeLists.txt), in a folder of its own.
#include <filesystem>
#include <string>

namespace leanfade::test {

// An empty folder LEANFADE_TEST_TMP/<suite>/<name> for one test's files (removed first).
inline std::filesystem::path fresh_scratch_folder(const std::string& suite,
                                                  const std::string& name) {
    const std::filesystem::path dir = std::filesystem::path(LEANFADE_TEST_TMP) / suite / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace leanfade::test
