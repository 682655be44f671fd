#pragma once
// Small text helpers shared by the command line, presets and result files.
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace leanfade {

// The pieces of `text` between the separators, empty pieces included: "a,,b" -> {"a", "", "b"},
// "" -> {""}.
std::vector<std::string> split(const std::string& text, char separator);

// Names for a message or a help text: "a, b, c or d" (`last` between the last two).
std::string name_list(std::span<const std::string_view> names, std::string_view last = "or");
std::string name_list(std::span<const std::string> names, std::string_view last = "or");

}  // namespace leanfade
