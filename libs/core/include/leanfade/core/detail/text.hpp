#pragma once
// Small text helpers shared by the command line, presets and result files.
#include <optional>
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

// Numbers as text, once for the command line, presets, result files and messages.
// The whole of `text` as a finite number (strtof / strtod syntax: decimal, exponent or hex form,
// leading white space allowed), or nothing: empty text, trailing characters, an embedded NUL,
// NaN, infinities and values beyond the type's range are not numbers here.
std::optional<float> parse_finite_float(std::string_view text);
std::optional<double> parse_finite_double(std::string_view text);
// The same as a test: true and `value` set for a number, false and `value` unchanged otherwise.
bool parse_finite(std::string_view text, float& value);
bool parse_finite(std::string_view text, double& value);
// The shortest decimal that reads back as the same value ("0.15", "1e-08", "300").
std::string shortest_text(float value);
std::string shortest_text(double value);

}  // namespace leanfade
