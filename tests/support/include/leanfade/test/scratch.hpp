#pragma once
// The one scratch-folder helper of the test suites: every test writes its files under the
// build's LEANFADE_TEST_TMP (tests/CMakeLists.txt), in a folder of its own.
#include <cctype>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace leanfade::test {

// An empty folder LEANFADE_TEST_TMP/<suite>/<name> for one test's files (removed first).
inline std::filesystem::path fresh_scratch_folder(const std::string& suite,
                                                  const std::string& name) {
    const std::filesystem::path dir = std::filesystem::path(LEANFADE_TEST_TMP) / suite / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// A fresh folder for the tests of one process that share a suite-wide setup: named after
// `prefix` and the process's test filter, since ctest runs each test in a process of its own, in
// parallel (LEANFADE_TEST_TMP/<prefix>_<filter's letters and digits>).
inline std::filesystem::path scratch_folder_for_this_selection(const std::string& prefix) {
    std::string selection;
    for (const char c : std::string(GTEST_FLAG_GET(filter)))
        if (std::isalnum(static_cast<unsigned char>(c)) && selection.size() < 80) selection += c;
    return fresh_scratch_folder(".", prefix + "_" + selection);
}

}  // namespace leanfade::test
