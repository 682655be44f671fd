#pragma once
// The command line's text, in one place: the flags' values are converted to typed values once,
// when CLI11 parses them (add_typed_option), and typed values are written back as text only for
// help texts, reports and file names. Numbers use leanfade/core/detail/text.hpp. Every parser throws
// leanfade::Error(flag, cause) naming the flag and what was wrong.
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade::cli {

// A framebuffer's or a cell's size in pixels (`--size WIDTHxHEIGHT`).
struct FramebufferSize {
    int width = 0;
    int height = 0;
    bool operator==(const FramebufferSize&) const = default;
};
inline constexpr int kMinFramebufferSide = 16;
inline constexpr int kMaxFramebufferSide = 8192;

// A flag whose text `parse(text)` turns into `value` when CLI11 parses the command line (throwing
// leanfade::Error naming the flag for bad text); `default_text` is the default its help shows
// ("" for none). The value keeps its initial contents when the flag is not given.
template <typename T, typename Parse>
CLI::Option* add_typed_option(CLI::App& app, const std::string& flag, T& value, Parse parse,
                              const std::string& help, const std::string& default_text = {}) {
    CLI::Option* option = app.add_option_function<std::string>(
        flag, [&value, parse](const std::string& text) { value = parse(text); }, help);
    if (!default_text.empty()) option->default_str(default_text);
    return option;
}

// A flag whose value is one of the names of `names` (name -> typed value, as the libraries list
// them: io::supercompression_names() ...): the help shows "TEXT:{a,b}", any other text is refused
// naming the flag, and the value is converted once, when CLI11 parses it. `value` may be of
// another type that the names' values convert to (a std::optional of them, for one).
template <typename T, typename U>
CLI::Option* add_named_option(CLI::App& app, const std::string& flag, T& value,
                              const std::vector<std::pair<std::string, U>>& names,
                              const std::string& help, const std::string& default_text = {}) {
    std::vector<std::string> keys;
    for (const auto& entry : names) keys.push_back(entry.first);
    auto parse = [names, flag](const std::string& text) -> T {
        for (const auto& entry : names)
            if (entry.first == text) return T(entry.second);
        throw Error(flag, "unknown value '" + text + "'");
    };
    return add_typed_option(app, flag, value, parse, help, default_text)
        ->check(CLI::IsMember(keys));
}

// `--spike auto|plateaus` (two-lobe LEAN's spike, BakeOptions::spike_fit) into `value`, with
// `help` before the choices' description; bake's and the on-the-fly bakes' flag.
CLI::Option* add_spike_option(CLI::App& app, SpikeFit& value, const std::string& help);

// The flag's name as CLI11 stores it from "-o,--output": its long name ("--output").
std::string long_flag(const std::string& names);

// "a,b,c" -> {"a", "b", "c"} (empty pieces kept: the callers name them).
std::vector<std::string> parse_names(const std::string& text);
// "0.5,2" -> {0.5, 2}: finite numbers. Throws Error(flag, "expected a finite number, got 'x'").
std::vector<float> parse_numbers(const std::string& text, const std::string& flag);
// "400x300" -> {400, 300}; each side in [16, 8192].
FramebufferSize parse_size(const std::string& text, const std::string& flag);
// "x,y,z" -> a vector of finite components.
glm::vec3 parse_vector(const std::string& text, const std::string& flag);
// "u:v,u:v" -> one velocity per layer, uv units per second.
std::vector<glm::vec2> parse_velocities(const std::string& text, const std::string& flag);
// "3,6,18" -> camera distances, each checked by check_camera_distance (leanfade/core/detail/camera.hpp).
std::vector<float> parse_distances(const std::string& text, const std::string& flag);
// "1024,2048" -> whole numbers in [low, high] (texels per side).
std::vector<int> parse_sizes(const std::string& text, const std::string& flag, int low, int high);

// The shortest text that reads back as the same float ("0.15", "3", "1e-05").
std::string number_text(float value);
// "x,y,z" with number_text components.
std::string vector_text(const glm::vec3& v);
// "u:v,u:v".
std::string velocities_text(const std::vector<glm::vec2>& velocities);
// "a,b,c".
std::string join(const std::vector<std::string>& names);
// "400x300".
std::string size_text(const FramebufferSize& size);

}  // namespace leanfade::cli
