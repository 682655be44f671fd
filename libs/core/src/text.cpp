#include "leanfade/core/text.hpp"

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

}  // namespace leanfade
