#pragma once
// Shared helpers of the io tests: a fresh scratch folder per test, raw file access, and checks
// that a call throws leanfade::Error naming the file and the cause on one line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"

namespace leanfade::io::test {

// LEANFADE_TEST_TMP/io/<suite>.<test>, emptied.
inline std::string scratch_folder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "." + info->name();
    for (char& character : name) {
        if (character == '/') character = '_';
    }
    const std::filesystem::path folder = std::filesystem::path(LEANFADE_TEST_TMP) / "io" / name;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder.string();
}

inline std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

inline void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Names of the entries of a folder, sorted.
inline std::vector<std::string> folder_entries(const std::string& folder) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

// Expects `call` to throw leanfade::Error for `file` whose one-line message contains `cause`.
template <class Call>
void expect_error(Call&& call, const std::string& file, const std::string& cause) {
    try {
        call();
        ADD_FAILURE() << "no leanfade::Error thrown; expected '" << file << ": ..." << cause << "'";
    } catch (const leanfade::Error& error) {
        const std::string message = error.what();
        EXPECT_EQ(error.file(), file) << message;
        EXPECT_THAT(message, ::testing::StartsWith(file + ": "));
        EXPECT_THAT(message, ::testing::HasSubstr(cause));
        EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line: " << message;
    }
}

inline void store_u32_le(std::vector<std::uint8_t>& bytes, std::size_t offset,
                         std::uint32_t value) {
    for (int i = 0; i < 4; ++i) bytes.at(offset + std::size_t(i)) = std::uint8_t(value >> (8 * i));
}
inline void store_u64_le(std::vector<std::uint8_t>& bytes, std::size_t offset,
                         std::uint64_t value) {
    for (int i = 0; i < 8; ++i) bytes.at(offset + std::size_t(i)) = std::uint8_t(value >> (8 * i));
}
inline std::uint32_t u32_le(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
    std::uint32_t value = 0;
    for (int i = 3; i >= 0; --i) value = (value << 8) | bytes[offset + std::size_t(i)];
    return value;
}
inline std::uint64_t u64_le(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
    return std::uint64_t(u32_le(bytes, offset)) | (std::uint64_t(u32_le(bytes, offset + 4)) << 32);
}

// Largest single operator-new request since the last reset (allocation_tracker.cpp).
void reset_largest_allocation();
std::size_t largest_allocation();
// Makes every single request of more than `bytes` throw std::bad_alloc (as under `ulimit -v`);
// 0 lifts the limit.
void set_allocation_limit(std::size_t bytes);

}  // namespace leanfade::io::test
