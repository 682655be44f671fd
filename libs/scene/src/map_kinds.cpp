// shaders/map_kinds.glsl from the map-kind table (map_kinds.hpp).
#include "leanfade/scene/detail/map_kinds.hpp"

#include <cctype>

namespace leanfade::scene {
namespace {

// `text` as comment lines of at most 100 characters, "// " first.
std::string comment_lines(const std::string& text) {
    std::string out, line = "//";
    std::size_t at = 0;
    while (at < text.size()) {
        std::size_t end = text.find(' ', at);
        if (end == std::string::npos) end = text.size();
        const std::string word = text.substr(at, end - at);
        if (line.size() + 1 + word.size() > 100) {
            out += line + "\n";
            line = "//";
        }
        line += " " + word;
        at = end + 1;
    }
    return out + line + "\n";
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace

std::string map_kinds_glsl() {
    std::string out =
        "// The material's surface maps (leanfade/scene/detail/map_kinds.hpp, kMapKinds): each a\n"
        "// texture unit LF_BINDING_* and a bit LF_MAP_* of LfShadingUniforms::maps, set when the\n"
        "// material has the map and the shader reads it (its sampler: map_samplers.glsl).\n"
        "// Generated from the table by scene::map_kinds_glsl(): do not edit; `make shader-tables`\n"
        "// writes it again and the test MapKinds.ShaderFilesAreTheTable compares the two.\n"
        "#ifndef LEANFADE_MAP_KINDS_GLSL\n"
        "#define LEANFADE_MAP_KINDS_GLSL\n";
    for (const MapKindInfo& row : kMapKinds) {
        const std::string name(row.glsl_name);
        out += "\n" + comment_lines(std::string(row.name) + ": " + std::string(row.meaning));
        out += "const int LF_BINDING_" + name + " = " + std::to_string(row.binding) + ";\n";
        out += "const int LF_MAP_" + name + " = " + std::to_string(row.mask_bit) + ";\n";
    }
    out += "\n#endif  // LEANFADE_MAP_KINDS_GLSL\n";
    return out;
}

std::string map_samplers_glsl() {
    std::string out =
        "// The samplers of the material's surface maps (leanfade/scene/detail/map_kinds.hpp,\n"
        "// kMapKinds), at their units (map_kinds.glsl); a map whose row names a variant define is\n"
        "// declared in the variants that define it. Included by scene.frag, which reads the maps.\n"
        "// Generated from the table by scene::map_samplers_glsl(): do not edit; `make\n"
        "// shader-tables` writes it again and the test MapKinds.ShaderFilesAreTheTable compares\n"
        "// the two.\n"
        "#ifndef LEANFADE_MAP_SAMPLERS_GLSL\n"
        "#define LEANFADE_MAP_SAMPLERS_GLSL\n\n";
    for (const MapKindInfo& row : kMapKinds) {
        const std::string declaration = "layout(binding = LF_BINDING_" + std::string(row.glsl_name) +
                                        ") uniform sampler2D u_" + lower(row.glsl_name) + ";\n";
        if (row.variant_define.empty()) {
            out += declaration;
        } else {
            out += "#if defined(" + std::string(row.variant_define) + ")\n" + declaration +
                   "#endif\n";
        }
    }
    out += "\n#endif  // LEANFADE_MAP_SAMPLERS_GLSL\n";
    return out;
}

}  // namespace leanfade::scene
