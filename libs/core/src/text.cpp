#include "leanfade/core/detail/text.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

namespace leanfade {

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end == std::string::npos ? end : end - start));
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return parts;
}

std::string name_list(std::span<const std::string_view> names, std::string_view last) {
    std::string text;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i > 0 && i + 1 == names.size()) {
            text += ' ';
            text += last;
            text += ' ';
        } else if (i > 0) {
            text += ", ";
        }
        text += names[i];
    }
    return text;
}

std::string name_list(std::span<const std::string> names, std::string_view last) {
    const std::vector<std::string_view> views(names.begin(), names.end());
    return name_list(views, last);
}

namespace {

template <typename T, typename Parse>
std::optional<T> parse_finite(std::string_view text, Parse parse) {
    if (text.empty()) return std::nullopt;
    const std::string copy(text);  // NUL-terminated for strtof / strtod
    char* end = nullptr;
    const T value = parse(copy.c_str(), &end);
    if (end != copy.c_str() + copy.size() || !std::isfinite(value)) return std::nullopt;
    return value;
}

template <typename T>
std::string shortest(T value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

}  // namespace

std::optional<float> parse_finite_float(std::string_view text) {
    return parse_finite<float>(text, [](const char* s, char** end) { return std::strtof(s, end); });
}

std::optional<double> parse_finite_double(std::string_view text) {
    return parse_finite<double>(text,
                                [](const char* s, char** end) { return std::strtod(s, end); });
}

bool parse_finite(std::string_view text, float& value) {
    const std::optional<float> parsed = parse_finite_float(text);
    if (parsed) value = *parsed;
    return parsed.has_value();
}

bool parse_finite(std::string_view text, double& value) {
    const std::optional<double> parsed = parse_finite_double(text);
    if (parsed) value = *parsed;
    return parsed.has_value();
}

std::string shortest_text(float value) { return shortest(value); }
std::string shortest_text(double value) { return shortest(value); }

}  // namespace leanfade
