// Presets as JSON: strict reading (unknown and repeated keys, types, finiteness, ranges) and
// writing with the shortest exact numbers.
#include "leanfade/core/detail/preset.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <utility>

#include <nlohmann/json.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/detail/camera.hpp"

namespace leanfade {
namespace {

using json = nlohmann::ordered_json;

// Throws Error(file, "key 'path': cause"); the key and the cause may hold text of the file
// (keys, names, the JSON parser's "last read" bytes): escaped.
[[noreturn]] void fail(const std::string& file, const std::string& key, const std::string& cause) {
    throw Error(file, "key '" + escape_text(key) + "': " + escape_text(cause, 2000));
}

std::string join(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
}

// Reads the members of JSON objects into C++ values, naming the file and the key in errors.
class Reader {
  public:
    explicit Reader(std::string file) : file_(std::move(file)) {}

    using Field = std::function<void(const json& value, const std::string& key)>;

    // `value` must be an object whose keys are all in `fields`; each present key is read.
    void object(const json& value, const std::string& key,
                const std::vector<std::pair<std::string, Field>>& fields) const {
        if (!value.is_object())
            fail(file_, key.empty() ? "(top level)" : key,
                 std::string("expected an object, got ") + value.type_name());
        for (const auto& item : value.items()) {
            const auto it = std::find_if(fields.begin(), fields.end(),
                                         [&](const auto& f) { return f.first == item.key(); });
            if (it == fields.end()) {
                std::string expected;
                for (const auto& f : fields) expected += (expected.empty() ? "" : ", ") + f.first;
                fail(file_, join(key, item.key()),
                     "unknown key (expected one of: " + expected + ")");
            }
            it->second(item.value(), join(key, item.key()));
        }
    }

    float number(const json& value, const std::string& key) const {
        if (!value.is_number())
            fail(file_, key, std::string("expected a number, got ") + value.type_name());
        const double d = value.get<double>();
        if (!std::isfinite(d) || std::abs(d) > double(std::numeric_limits<float>::max()))
            fail(file_, key, "must be a finite number");
        return float(d);
    }

    std::int64_t integer(const json& value, const std::string& key, std::int64_t min,
                         std::int64_t max) const {
        if (!value.is_number_integer())
            fail(file_, key,
                 std::string("expected an integer, got ") +
                     (value.is_number() ? "a fraction" : value.type_name()));
        std::int64_t v = 0;
        if (value.is_number_unsigned()) {
            const std::uint64_t u = value.get<std::uint64_t>();
            if (u > std::uint64_t(max))
                fail(file_, key,
                     "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " +
                         std::to_string(u));
            v = std::int64_t(u);
        } else {
            v = value.get<std::int64_t>();
        }
        if (v < min || v > max)
            fail(file_, key,
                 "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " +
                     std::to_string(v));
        return v;
    }

    bool boolean(const json& value, const std::string& key) const {
        if (!value.is_boolean())
            fail(file_, key, std::string("expected true or false, got ") + value.type_name());
        return value.get<bool>();
    }

    std::string string(const json& value, const std::string& key) const {
        if (!value.is_string())
            fail(file_, key, std::string("expected a string, got ") + value.type_name());
        return value.get<std::string>();
    }

    glm::vec3 vec3(const json& value, const std::string& key) const {
        if (!value.is_array() || value.size() != 3)
            fail(file_, key,
                 std::string("expected an array of 3 numbers, got ") +
                     (value.is_array() ? "an array of " + std::to_string(value.size())
                                       : std::string(value.type_name())));
        glm::vec3 v;
        for (int i = 0; i < 3; ++i)
            v[i] = number(value[std::size_t(i)], key + "[" + std::to_string(i) + "]");
        return v;
    }

    const std::string& file() const { return file_; }

  private:
    std::string file_;
};

// Shortest decimal that reads back as the same float, stored as a double (0.15f -> 0.15).
json exact(float value) {
    const std::optional<double> shortest = parse_finite_double(shortest_text(value));
    return shortest ? *shortest : double(value);
}

json exact(const glm::vec3& v) {
    return json::array({exact(v.x), exact(v.y), exact(v.z)});
}

// Parses with a check for repeated keys (nlohmann keeps the last one silently).
json parse_strict(const std::string& text, const std::string& file) {
    std::vector<std::vector<std::string>> seen;  // keys of each open object
    std::vector<std::string> path;               // current key of each open object
    std::string repeated;
    const json::parser_callback_t callback = [&](int, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start:
                seen.emplace_back();
                path.emplace_back();
                break;
            case json::parse_event_t::object_end:
                if (!seen.empty()) seen.pop_back();
                if (!path.empty()) path.pop_back();
                break;
            case json::parse_event_t::key: {
                const std::string key = parsed.get<std::string>();
                if (!seen.empty()) {
                    auto& keys = seen.back();
                    if (std::find(keys.begin(), keys.end(), key) != keys.end() &&
                        repeated.empty()) {
                        std::string full;
                        for (std::size_t i = 0; i + 1 < path.size(); ++i)
                            full = join(full, path[i]);
                        repeated = join(full, key);
                    }
                    keys.push_back(key);
                    path.back() = key;
                }
                break;
            }
            default:
                break;
        }
        return true;
    };
    json value;
    try {
        value = json::parse(text, callback);
    } catch (const json::exception& e) {
        std::string cause = e.what();
        // "[json.exception.parse_error.101] parse error at line 1, ..." -> "parse error at ..."
        if (const std::size_t close = cause.find("] "); close != std::string::npos)
            cause = cause.substr(close + 2);
        // The key being read when the text went wrong (NaN, an overflowing number, ...).
        std::string where;
        for (const std::string& k : path)
            if (!k.empty()) where = join(where, k);
        if (!where.empty()) fail(file, where, "not valid JSON: " + cause);
        throw Error(file, "not valid JSON: " + escape_text(cause, 2000));
    }
    if (!repeated.empty()) fail(file, repeated, "given more than once");
    return value;
}

// File names and technique names of a preset reach messages and the file system: no control
// characters (a newline, a terminal escape sequence).
void check_no_control_characters(const std::string& file, const std::string& key,
                                 const std::string& text) {
    for (const char character : text) {
        const auto byte = static_cast<unsigned char>(character);
        if (byte < 0x20 || byte == 0x7F)
            fail(file, key, "contains control characters ('" + text + "')");  // escaped there
    }
}

}  // namespace

const std::vector<std::string>& preset_layouts() {
    static const std::vector<std::string> layouts{"single", "split", "side-by-side"};
    return layouts;
}

const char* to_string(PaneLayout layout) {
    return preset_layouts()[std::size_t(layout)].c_str();
}

PaneLayout parse_pane_layout(std::string_view name, const std::string& setting) {
    const auto& layouts = preset_layouts();
    for (std::size_t i = 0; i < layouts.size(); ++i)
        if (name == layouts[i]) return PaneLayout(i);
    throw Error::setting(setting,
                         "expected " + name_list(layouts) + ", got '" + std::string(name) + "'");
}

bool layout_accepts(PaneLayout layout, std::size_t panes) {
    switch (layout) {
        case PaneLayout::Single:
            return panes == 1;
        case PaneLayout::Split:
            return panes == 2;
        case PaneLayout::SideBySide:
            return panes == 2 || panes == 3;
    }
    return false;
}

const char* layout_requirement(PaneLayout layout) {
    switch (layout) {
        case PaneLayout::Single:
            return "exactly 1 technique";
        case PaneLayout::Split:
            return "exactly 2 techniques";
        case PaneLayout::SideBySide:
            return "2 or 3 techniques";
    }
    return "";
}

void validate(const Preset& p, const std::string& file) {
    if (p.scene.empty()) fail(file, "scene", "must not be empty");
    check_no_control_characters(file, "scene", p.scene);
    const BumpSource& b = p.bumps;
    if (b.source.empty()) fail(file, "bumps.source", "must not be empty");
    check_no_control_characters(file, "bumps.source", b.source);
    try {
        check_texture_size(b.texture_size, kDefaultMaxImageDimension, false);
    } catch (const Error& e) {
        fail(file, "bumps.texture_size", e.cause());
    }
    const LayerSettings& l = p.layers;
    for (const std::string& source : l.sources)
        check_no_control_characters(file, "layers.sources", source);
    check_no_control_characters(file, "layers.weight_map", l.weight_map);
    try {
        validate(l);
    } catch (const Error& e) {
        // The settings of the layers are the keys of "layers".
        const std::string& setting = e.setting();
        const std::string key = setting == "layers" || setting.empty() ? "sources"
                                : setting.rfind("layer-", 0) == 0      ? setting.substr(6)
                                                                       : setting;
        fail(file, "layers." + key, e.cause());
    }
    for (std::size_t i = 0; i < p.maps.size(); ++i) {
        const MapFile& map = p.maps[i];
        check_no_control_characters(file, "maps", map.kind);
        check_no_control_characters(file, "maps." + map.kind, map.path);
        if (map.path.empty()) fail(file, "maps." + map.kind, "must not be empty");
        for (std::size_t j = 0; j < i; ++j)
            if (p.maps[j].kind == map.kind) fail(file, "maps." + map.kind, "given more than once");
    }
    try {
        validate(p.shading);
    } catch (const Error& e) {
        if (e.kind() == ErrorKind::Setting && find_shading_parameter(e.setting()) != nullptr)
            fail(file, "shading." + e.setting(), e.cause());
        fail(file, "shading", e.what());
    }

    const CameraSettings& c = p.camera;
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(c.target[i])) fail(file, "camera.target", "must be finite");
    if (!is_camera_target(c.target)) {
        try {
            check_camera_target(c.target, "camera.target");
        } catch (const Error& e) {
            fail(file, "camera.target", e.cause());
        }
    }
    const float length = std::sqrt(c.direction.x * c.direction.x + c.direction.y * c.direction.y +
                                   c.direction.z * c.direction.z);
    if (!std::isfinite(length) || !(length > 0.0f))
        fail(file, "camera.direction", "must be a finite, non-zero vector");
    if (!is_camera_distance(c.distance))
        fail(file, "camera.distance",
             "must be in (1, " + std::to_string(int(kMaxCameraDistance)) +
                 "] bounding radii, got " + std::to_string(c.distance));
    if (!is_field_of_view(c.fov_y_degrees))
        fail(file, "camera.fov_y_degrees",
             "must be in (1, 170) degrees, got " + std::to_string(c.fov_y_degrees));

    if (!layout_accepts(p.layout, p.techniques.size()))
        fail(file, "view.techniques",
             std::string("layout \"") + to_string(p.layout) + "\" needs " +
                 layout_requirement(p.layout) + ", got " + std::to_string(p.techniques.size()));
    for (std::size_t i = 0; i < p.techniques.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (p.techniques[j] == p.techniques[i])
                fail(file, "view.techniques",
                     std::string("\"") + to_string(p.techniques[i]) + "\" given twice");
    if (!(p.divider >= 0.0f && p.divider <= 1.0f))
        fail(file, "view.divider", "must be in [0, 1], got " + std::to_string(p.divider));
    if (p.reference_samples < 1 || p.reference_samples > kMaxReferenceSamples)
        fail(file, "view.reference_samples",
             "must be in [1, " + std::to_string(kMaxReferenceSamples) + "], got " +
                 std::to_string(p.reference_samples));
    if (!(p.resolution_scale >= 0.1f && p.resolution_scale <= 1.0f))
        fail(file, "view.resolution_scale",
             "must be in [0.1, 1], got " + std::to_string(p.resolution_scale));
    const FlyAwaySettings& f = p.fly_away;
    if (!(f.near_distance > 1.0f))
        fail(file, "view.fly_away.near", "must be > 1, got " + std::to_string(f.near_distance));
    if (!(f.far_distance > f.near_distance && f.far_distance <= kMaxCameraDistance))
        fail(file, "view.fly_away.far",
             "must be greater than near and at most " + std::to_string(int(kMaxCameraDistance)) +
                 ", got " + std::to_string(f.far_distance));
    if (!(f.period >= 0.5f && f.period <= 600.0f))
        fail(file, "view.fly_away.period",
             "must be in [0.5, 600] seconds, got " + std::to_string(f.period));
}

Preset preset_from_json(const std::string& text, const std::string& file) {
    const json root = parse_strict(text, file);
    const Reader r(file);
    Preset p;
    ShadingSettings& s = p.shading;
    auto num = [&](float& target) {
        return [&r, &target](const json& v, const std::string& k) { target = r.number(v, k); };
    };
    auto vec = [&](glm::vec3& target) {
        return [&r, &target](const json& v, const std::string& k) { target = r.vec3(v, k); };
    };
    auto str = [&](std::string& target) {
        return [&r, &target](const json& v, const std::string& k) { target = r.string(v, k); };
    };
    auto integer = [&](int& target, int min, int max) {
        return [&r, &target, min, max](const json& v, const std::string& k) {
            target = int(r.integer(v, k, min, max));
        };
    };

    // A name of one of the library's lists, parsed by `parse(name, setting)`.
    auto named = [&](auto& target, auto parse) {
        return [&r, &target, parse, &file](const json& v, const std::string& k) {
            const std::string name = r.string(v, k);
            try {
                target = parse(name, k);
            } catch (const Error& e) {
                fail(file, k, e.cause());
            }
        };
    };
    auto numbers = [&](std::vector<float>& target) {
        return [&r, &target, &file](const json& v, const std::string& k) {
            if (!v.is_array())
                fail(file, k, std::string("expected an array of numbers, got ") + v.type_name());
            target.clear();
            for (std::size_t i = 0; i < v.size(); ++i)
                target.push_back(r.number(v[i], k + "[" + std::to_string(i) + "]"));
        };
    };
    const Reader::Field layers = [&](const json& v, const std::string& key) {
        LayerSettings& l = p.layers;
        r.object(
            v, key,
            {{"sources",
              [&](const json& x, const std::string& k) {
                  if (!x.is_array())
                      fail(file, k, std::string("expected an array of names, got ") + x.type_name());
                  l.sources.clear();
                  for (std::size_t i = 0; i < x.size(); ++i)
                      l.sources.push_back(r.string(x[i], k + "[" + std::to_string(i) + "]"));
              }},
             {"weights", numbers(l.weights)},
             {"strengths", numbers(l.strengths)},
             {"tiling", numbers(l.tiling)},
             {"velocity",
              [&](const json& x, const std::string& k) {
                  if (!x.is_array())
                      fail(file, k,
                           std::string("expected an array of [u, v] pairs, got ") + x.type_name());
                  l.velocity.clear();
                  for (std::size_t i = 0; i < x.size(); ++i) {
                      const std::string item = k + "[" + std::to_string(i) + "]";
                      if (!x[i].is_array() || x[i].size() != 2)
                          fail(file, item, "expected an array of 2 numbers");
                      l.velocity.emplace_back(r.number(x[i][0], item + "[0]"),
                                              r.number(x[i][1], item + "[1]"));
                  }
              }},
             {"weight_map", str(l.weight_map)},
             {"mixing", named(l.mixing, parse_layer_mixing)}});
    };
    const Reader::Field maps = [&](const json& v, const std::string& key) {
        if (!v.is_object())
            fail(file, key, std::string("expected an object, got ") + v.type_name());
        p.maps.clear();
        for (const auto& item : v.items())
            p.maps.push_back({item.key(), r.string(item.value(), join(key, item.key()))});
    };
    const Reader::Field bumps = [&](const json& v, const std::string& key) {
        BumpSource& b = p.bumps;
        r.object(
            v, key,
            {{"source", str(b.source)},
             {"from", named(b.from, parse_bake_source)},
             {"directx", [&](const json& x, const std::string& k) { b.directx = r.boolean(x, k); }},
             {"bits", named(b.bits, parse_storage_policy)},
             {"seed",
              [&](const json& x, const std::string& k) {
                  b.seed = std::uint32_t(r.integer(x, k, 0, 0xFFFFFFFFll));
              }},
             {"texture_size", integer(b.texture_size, 4, kDefaultMaxImageDimension)}});
    };
    // Every row of the parameter schema is a key of "shading", read by its kind.
    const Reader::Field shading = [&](const json& v, const std::string& key) {
        std::vector<std::pair<std::string, Reader::Field>> fields;
        for (const ParameterInfo& row : shading_parameters()) {
            const ParameterInfo* p_row = &row;
            fields.emplace_back(std::string(row.key), [&r, &s, &file, p_row](const json& x,
                                                                          const std::string& k) {
                const ParameterInfo& rw = *p_row;
                switch (rw.kind) {
                    case ParameterKind::Scalar:
                        s.*rw.scalar = r.number(x, k);
                        break;
                    case ParameterKind::Integer:
                        s.*rw.integer =
                            int(r.integer(x, k, std::int64_t(rw.min), std::int64_t(rw.max)));
                        break;
                    case ParameterKind::Colour:
                    case ParameterKind::Direction:
                        s.*rw.vector = r.vec3(x, k);
                        break;
                    case ParameterKind::Choice:
                        try {
                            parse_parameter(rw, r.string(x, k), s);
                        } catch (const Error& e) {
                            fail(file, k, e.cause());
                        }
                        break;
                }
            });
        }
        r.object(v, key, fields);
    };
    const Reader::Field camera = [&](const json& v, const std::string& key) {
        CameraSettings& c = p.camera;
        r.object(v, key,
                 {{"target", vec(c.target)},
                  {"direction", vec(c.direction)},
                  {"distance", num(c.distance)},
                  {"fov_y_degrees", num(c.fov_y_degrees)}});
    };
    const Reader::Field fly_away = [&](const json& v, const std::string& key) {
        FlyAwaySettings& f = p.fly_away;
        r.object(v, key,
                 {{"near", num(f.near_distance)},
                  {"far", num(f.far_distance)},
                  {"period", num(f.period)}});
    };
    const Reader::Field view = [&](const json& v, const std::string& key) {
        r.object(
            v, key,
            {{"techniques",
              [&](const json& x, const std::string& k) {
                  if (!x.is_array())
                      fail(file, k,
                           std::string("expected an array of names, got ") + x.type_name());
                  p.techniques.clear();
                  for (std::size_t i = 0; i < x.size(); ++i) {
                      const std::string name = r.string(x[i], k + "[" + std::to_string(i) + "]");
                      check_no_control_characters(file, k, name);
                      if (name.empty()) fail(file, k, "a name is empty");
                      try {
                          p.techniques.push_back(parse_technique(name, k));
                      } catch (const Error& e) {
                          fail(file, k, e.cause());
                      }
                  }
              }},
             {"layout",
              [&](const json& x, const std::string& k) {
                  const std::string name = r.string(x, k);
                  try {
                      p.layout = parse_pane_layout(name, k);
                  } catch (const Error&) {
                      fail(file, k,
                           "expected \"single\", \"split\" or \"side-by-side\", got \"" + name +
                               "\"");
                  }
              }},
             {"divider", num(p.divider)},
             {"reference_samples", integer(p.reference_samples, 1, kMaxReferenceSamples)},
             {"resolution_scale", num(p.resolution_scale)},
             {"fly_away", fly_away}});
    };
    r.object(root, "",
             {{"leanfade_preset",
               [&](const json& x, const std::string& k) {
                   const std::int64_t version =
                       r.integer(x, k, 0, std::numeric_limits<std::int64_t>::max());
                   if (version != 1)
                       fail(file, k,
                            "unsupported preset version " + std::to_string(version) +
                                " (this leanfade reads version 1)");
               }},
              {"scene", str(p.scene)},
              {"bumps", bumps},
              {"layers", layers},
              {"maps", maps},
              {"shading", shading},
              {"camera", camera},
              {"view", view}});
    validate(p, file);
    return p;
}

Preset read_preset(const std::string& path) {
    return preset_from_json(read_regular_file(path, kMaxPresetFileBytes, "a preset file"), path);
}

std::string preset_to_json(const Preset& p) {
    const ShadingSettings& s = p.shading;
    json root = json::object();
    root["leanfade_preset"] = 1;
    root["scene"] = p.scene;
    root["bumps"] = {{"source", p.bumps.source},
                     {"from", to_string(p.bumps.from)},
                     {"directx", p.bumps.directx},
                     {"bits", to_string(p.bumps.bits)},
                     {"seed", p.bumps.seed},
                     {"texture_size", p.bumps.texture_size}};
    json weights = json::array(), strengths = json::array(), tiling = json::array(),
         velocity = json::array();
    for (float w : p.layers.weights) weights.push_back(exact(w));
    for (float k : p.layers.strengths) strengths.push_back(exact(k));
    for (float t : p.layers.tiling) tiling.push_back(exact(t));
    for (const glm::vec2& v : p.layers.velocity)
        velocity.push_back(json::array({exact(v.x), exact(v.y)}));
    root["layers"] = {{"sources", p.layers.sources},
                      {"weights", std::move(weights)},
                      {"strengths", std::move(strengths)},
                      {"tiling", std::move(tiling)},
                      {"velocity", std::move(velocity)},
                      {"weight_map", p.layers.weight_map},
                      {"mixing", to_string(p.layers.mixing)}};
    json maps = json::object();
    for (const MapFile& map : p.maps) maps[map.kind] = map.path;
    root["maps"] = std::move(maps);
    json shading = json::object();
    for (const ParameterInfo& row : shading_parameters()) {
        const std::string key(row.key);
        switch (row.kind) {
            case ParameterKind::Scalar:
                shading[key] = exact(s.*row.scalar);
                break;
            case ParameterKind::Integer:
                shading[key] = s.*row.integer;
                break;
            case ParameterKind::Colour:
            case ParameterKind::Direction:
                shading[key] = exact(s.*row.vector);
                break;
            case ParameterKind::Choice:
                shading[key] = format_parameter(row, s);
                break;
        }
    }
    root["shading"] = std::move(shading);
    root["camera"] = {{"target", exact(p.camera.target)},
                      {"direction", exact(p.camera.direction)},
                      {"distance", exact(p.camera.distance)},
                      {"fov_y_degrees", exact(p.camera.fov_y_degrees)}};
    std::vector<std::string> techniques;
    for (Technique t : p.techniques) techniques.emplace_back(to_string(t));
    root["view"] = {{"techniques", techniques},
                    {"layout", to_string(p.layout)},
                    {"divider", exact(p.divider)},
                    {"reference_samples", p.reference_samples},
                    {"resolution_scale", exact(p.resolution_scale)},
                    {"fly_away",
                     {{"near", exact(p.fly_away.near_distance)},
                      {"far", exact(p.fly_away.far_distance)},
                      {"period", exact(p.fly_away.period)}}}};
    return root.dump(2) + "\n";
}

}  // namespace leanfade
