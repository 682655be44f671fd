// Lookups over the technique table (leanfade/core/technique.hpp).
#include "leanfade/core/technique.hpp"

#include <algorithm>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/text.hpp"

namespace leanfade {

const char* to_string(Technique technique) {
    return info(technique).name.data();
}

const std::vector<Technique>& all_techniques() {
    static const std::vector<Technique> all = [] {
        std::vector<Technique> result;
        for (const TechniqueInfo& row : kTechniques) result.push_back(row.id);
        return result;
    }();
    return all;
}

std::vector<Technique> approximating_techniques() {
    std::vector<Technique> result;
    for (const TechniqueInfo& row : kTechniques)
        if (!row.supersampled) result.push_back(row.id);
    return result;
}

std::string technique_names(std::span<const Technique> techniques, std::string_view last) {
    std::vector<std::string_view> names;
    for (const Technique t : techniques) names.push_back(info(t).name);
    return name_list(names, last);
}

std::string join_technique_names(std::span<const Technique> techniques) {
    std::string text;
    for (const Technique t : techniques) {
        if (!text.empty()) text += ',';
        text += info(t).name;
    }
    return text;
}

Technique parse_technique(std::string_view name, const std::string& setting) {
    for (const TechniqueInfo& row : kTechniques)
        if (name == row.name) return row.id;
    throw Error::setting(setting, "unknown technique '" + std::string(name) + "' (expected " +
                                      technique_names(all_techniques()) + ")");
}

std::vector<Technique> parse_techniques(std::string_view list, const std::string& setting) {
    std::vector<Technique> result;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        const Technique t = parse_technique(list.substr(start, comma - start), setting);
        if (std::find(result.begin(), result.end(), t) != result.end())
            throw Error::setting(setting,
                                 std::string("technique '") + to_string(t) + "' given twice");
        result.push_back(t);
        start = comma + 1;
    }
    return result;
}

}  // namespace leanfade
