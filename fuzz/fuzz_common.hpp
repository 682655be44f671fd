#pragma once
// Shared by the libFuzzer targets. A target returns normally for every input a reader refuses
// with leanfade::Error (the expected, documented outcome for bad data); anything else - a crash,
// a sanitizer report, another exception escaping (std::terminate), a hang, unbounded memory - is
// a finding.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace leanfade::fuzz {

// Images larger than this on a side are refused by the readers in the fuzz targets, so that one
// input cannot ask for more than a few MiB (the product's default is 16384, docs/robustness.md).
inline constexpr int kMaxDimension = 512;

inline std::vector<std::uint8_t> to_bytes(const std::uint8_t* data, std::size_t size) {
    return std::vector<std::uint8_t>(data, data + size);
}

}  // namespace leanfade::fuzz
