#pragma once
// Small text helpers shared by the command line, presets and result files.
#include <string>
#include <vector>

namespace leanfade {

// The pieces of `text` between the separators, empty pieces included: "a,,b" -> {"a", "", "b"},
// "" -> {""}.
std::vector<std::string> split(const std::string& text, char separator);

}  // namespace leanfade
