// The command line's text (cli_text.hpp).
#include "cli_text.hpp"

#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/text.hpp"

namespace leanfade::cli {

CLI::Option* add_spike_option(CLI::App& app, SpikeFit& value, const std::string& help) {
    static const std::vector<std::pair<std::string, SpikeFit>> names = [] {
        std::vector<std::pair<std::string, SpikeFit>> table;
        for (const std::string& name : spike_fit_names())
            table.emplace_back(name, parse_spike_fit(name));
        return table;
    }();
    return add_named_option(app, "--spike", value, names,
                            help + ": auto (the plateaus and/or a window around the mean or "
                                   "densest slope, whichever fits the map's far highlight best) "
                                   "or plateaus (the plateaus alone, as leanfade 0.2 baked)",
                            to_string(value));
}

std::string long_flag(const std::string& names) {
    const std::size_t comma = names.rfind(',');
    return comma == std::string::npos ? names : names.substr(comma + 1);
}

std::vector<std::string> parse_names(const std::string& text) {
    return split(text, ',');
}

namespace {

float parse_number(const std::string& text, const std::string& flag) {
    const std::optional<float> value = parse_finite_float(text);
    if (!value) throw Error::setting(flag, "expected a finite number, got '" + text + "'");
    return *value;
}

}  // namespace

std::vector<float> parse_numbers(const std::string& text, const std::string& flag) {
    std::vector<float> values;
    for (const std::string& part : split(text, ',')) values.push_back(parse_number(part, flag));
    return values;
}

FramebufferSize parse_size(const std::string& text, const std::string& flag) {
    const std::size_t x = text.find('x');
    auto parse_int = [&](const std::string& s, int& v) {
        if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
            return false;
        v = std::stoi(s);
        return true;
    };
    FramebufferSize size;
    if (x == std::string::npos || !parse_int(text.substr(0, x), size.width) ||
        !parse_int(text.substr(x + 1), size.height))
        throw Error::setting(flag, "expected WIDTHxHEIGHT in pixels, got '" + text + "'");
    if (size.width < kMinFramebufferSide || size.height < kMinFramebufferSide ||
        size.width > kMaxFramebufferSide || size.height > kMaxFramebufferSide)
        throw Error::setting(flag, "each side must be in [16, 8192] pixels, got '" + text + "'");
    return size;
}

glm::vec3 parse_vector(const std::string& text, const std::string& flag) {
    glm::vec3 v(0.0f);
    std::size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const std::size_t comma = text.find(',', start);
        const bool last = i == 2;
        if ((comma == std::string::npos) != last)
            throw Error::setting(flag, "expected X,Y,Z, got '" + text + "'");
        const std::string part = text.substr(start, last ? std::string::npos : comma - start);
        const std::optional<float> value = parse_finite_float(part);
        if (!value) throw Error::setting(flag, "expected X,Y,Z, got '" + text + "'");
        v[i] = *value;
        start = comma + 1;
    }
    return v;
}

std::vector<glm::vec2> parse_velocities(const std::string& text, const std::string& flag) {
    std::vector<glm::vec2> values;
    for (const std::string& part : split(text, ',')) {
        const std::vector<std::string> uv = split(part, ':');
        if (uv.size() != 2)
            throw Error::setting(flag, "expected U:V per layer, got '" + part + "'");
        values.emplace_back(parse_number(uv[0], flag), parse_number(uv[1], flag));
    }
    return values;
}

std::vector<float> parse_distances(const std::string& text, const std::string& flag) {
    std::vector<float> result;
    for (const std::string& part : split(text, ',')) {
        float d = 0.0f;
        if (!parse_finite(part, d))
            throw Error::setting(flag, "expected comma-separated numbers, got '" + text + "'");
        check_camera_distance(d, flag, part);
        result.push_back(d);
    }
    return result;
}

std::vector<int> parse_sizes(const std::string& text, const std::string& flag, int low, int high) {
    std::vector<int> sizes;
    for (const std::string& part : split(text, ',')) {
        char* end = nullptr;
        const long value = std::strtol(part.c_str(), &end, 10);
        if (part.empty() || *end != 0)
            throw Error::setting(flag,
                                 "expected comma-separated sizes in texels, got '" + text + "'");
        if (value < low || value > high)
            throw Error::setting(flag, "sizes must be in [" + std::to_string(low) + ", " +
                                           std::to_string(high) + "], got " + part);
        sizes.push_back(int(value));
    }
    return sizes;
}

std::string number_text(float value) {
    return shortest_text(value);
}

std::string vector_text(const glm::vec3& v) {
    return number_text(v.x) + "," + number_text(v.y) + "," + number_text(v.z);
}

std::string velocities_text(const std::vector<glm::vec2>& velocities) {
    std::string text;
    for (const glm::vec2& v : velocities)
        text += (text.empty() ? "" : ",") + number_text(v.x) + ":" + number_text(v.y);
    return text;
}

std::string join(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& n : names) text += (text.empty() ? "" : ",") + n;
    return text;
}

std::string size_text(const FramebufferSize& size) {
    return std::to_string(size.width) + "x" + std::to_string(size.height);
}

}  // namespace leanfade::cli
