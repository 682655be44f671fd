#pragma once
// Shader sources: the files under shaders/ (embedded at build time, or read from a folder on
// disk for hot reload), `#include "file"` resolution, variants by prepended #defines, and program
// compilation and linking.
//
// Resolution: the text of a file with each line `#include "name"` replaced by the text of
// shaders/<name> (each file at most once per resolved source, nested includes allowed), and the
// variant's `#define`s inserted right after the `#version` line. `#line` directives keep compiler
// messages pointing at the right file and line: source string 0 is the main file, 1, 2, ... the
// included files in ResolvedSource::files order.
#include <array>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/gl/detail/objects.hpp"

namespace leanfade::gl {

struct ResolvedSource {
    std::string text;                // ready for glShaderSource / glslangValidator
    std::vector<std::string> files;  // source string number -> file name
};

class ShaderSources {
  public:
    // The files of shaders/ compiled into the binary (the default).
    static ShaderSources embedded();
    // The files of `folder` on disk, read afresh at every resolve() (hot reload). Throws
    // leanfade::Error(folder, cause) if it is not a readable folder.
    static ShaderSources directory(const std::string& folder);

    // Throws leanfade::Error(file, cause) for a missing file, a malformed #include, an include
    // nested deeper than 16 levels, or a main file without a #version first line.
    ResolvedSource resolve(const std::string& name, const std::vector<std::string>& defines) const;

    // "embedded" or the folder.
    const std::string& origin() const { return origin_; }

    // The file `name` as messages name it: <folder>/<name> for a folder on disk, <name> for the
    // embedded copies.
    std::string location(const std::string& name) const;

  private:
    std::string read(const std::string& name) const;
    std::optional<std::string> folder_;
    std::string origin_;
};

// Variants of the scene program of a technique, as bits (shaders/scene.frag), each described once
// in kSceneVariantBits: its part of the variant's name, the defines it adds and the techniques
// that have it. A new bit is its constant and its row.
using SceneVariantFlags = unsigned;
inline constexpr SceneVariantFlags kPlainColor = 1u;
inline constexpr SceneVariantFlags kFadeFast = 2u;
inline constexpr SceneVariantFlags kCookTorrance = 4u;
inline constexpr SceneVariantFlags kLeanModel = 8u;
inline constexpr SceneVariantFlags kLayered = 16u;
inline constexpr SceneVariantFlags kGeometricAa = 32u;

// Which techniques' programs have a variant bit (TechniqueInfo's columns).
enum class VariantScope { Every, NotSupersampled, Supersampled, Fading };

struct SceneVariantBit {
    SceneVariantFlags bit;
    std::string_view suffix;                  // its part of variant_name ("_plain")
    std::array<std::string_view, 3> defines;  // the defines it adds ("" unused)
    VariantScope scope;
    std::string_view description;
};

inline constexpr std::array<SceneVariantBit, 6> kSceneVariantBits{{
    {kPlainColor, "_plain", {"LF_PLAIN_COLOR", "", ""}, VariantScope::NotSupersampled,
     "the renderer's ordinary frames: colour output without fog, without the output and fog "
     "branches (docs/perf.md)"},
    {kFadeFast, "_fast", {"LF_FADE_EXPONENT_2", "LF_FADE_TANGENT_Z_ONLY", "LF_FADE_ACTIVE"},
     VariantScope::Fading,
     "fading on with its defaults (p = 2, d = Vt.z; Fade > 0, Pmax > 1): (d Fade)^2 as a "
     "product, no distance-mode test, NdotL^sf D in one exponential without the exact sf == 1 "
     "path"},
    // LF_BRDF's value (1) rather than a define of its own (scene_defines).
    {kCookTorrance, "_ct", {"", "", ""}, VariantScope::Every, "the Cook-Torrance BRDF"},
    // LF_TECHNIQUE's value (LEAN's) and LF_READS_MOMENTS (scene_defines).
    {kLeanModel, "_leanmodel", {"", "", ""}, VariantScope::Supersampled,
     "the reference shades with LEAN's lobe at the finest level (docs/math.md §7)"},
    {kLayered, "_layered", {"LF_LAYERED", "", ""}, VariantScope::Every,
     "the material's moments mixed from bump layers (docs/math.md §6; Renderer picks it per "
     "material)"},
    {kGeometricAa, "_gaa", {"LF_GEOMETRIC_AA", "", ""}, VariantScope::NotSupersampled,
     "geometric specular antialiasing (docs/math.md §11)"},
}};

// Every bit of the table.
constexpr SceneVariantFlags all_scene_variant_flags() {
    SceneVariantFlags all = 0;
    for (const SceneVariantBit& row : kSceneVariantBits) all |= row.bit;
    return all;
}
inline constexpr SceneVariantFlags kAllSceneVariantFlags = all_scene_variant_flags();
// One bit per row, in ascending order (the order of the names' parts).
constexpr bool scene_variant_bits_are_ordered() {
    SceneVariantFlags previous = 0;
    for (const SceneVariantBit& row : kSceneVariantBits) {
        if (row.bit == 0 || (row.bit & (row.bit - 1)) != 0 || row.bit <= previous) return false;
        previous = row.bit;
    }
    return true;
}
static_assert(scene_variant_bits_are_ordered());

// Which program of the renderer: a technique's scene program with its variant bits, or one of
// the fixed programs. Programs are found and cached by this key; its name is for logs, file
// names and `leanfade shaders` only.
struct VariantKey {
    enum class Program : unsigned char {
        Scene,          // scene.vert + scene.frag of `technique` with `flags`
        BoxFilter,      // fullscreen.vert + box_filter.frag: the reference's reduction
        ConstantColor,  // scene.vert + constant.frag: the fill-rate floor of `leanfade bench`
    };
    Program program = Program::Scene;
    Technique technique = Technique::Bump;  // Scene only
    SceneVariantFlags flags = 0;            // Scene only

    static constexpr VariantKey scene(Technique technique, SceneVariantFlags flags = 0) {
        return {Program::Scene, technique, flags};
    }
    static constexpr VariantKey box_filter() { return {Program::BoxFilter, Technique::Bump, 0}; }
    static constexpr VariantKey constant_color() {
        return {Program::ConstantColor, Technique::Bump, 0};
    }
    constexpr bool is_scene() const { return program == Program::Scene; }
    // The same scene program with more bits.
    constexpr VariantKey with(SceneVariantFlags more) const {
        return {program, technique, flags | more};
    }
    auto operator<=>(const VariantKey&) const = default;
};

// "scene_<technique>[_plain][_fast][_ct][_leanmodel][_layered]", "box_filter", "scene_constant".
std::string variant_name(const VariantKey& key);

// One program of the renderer: its key, its stages and its defines (e.g. {"LF_TECHNIQUE 1"}).
struct ShaderVariant {
    VariantKey key;
    std::string name;  // variant_name(key)
    std::string vertex;
    std::string fragment;
    std::vector<std::string> defines;
};

// The variant bits that ShadingSettings asks for: the BRDF, and the model of the reference.
SceneVariantFlags scene_variant_flags(Technique technique, const ShadingSettings& settings);
// Whether the technique gets geometric specular antialiasing under the settings (geometric_aa:
// on, or auto and the technique's row asks for it; never the supersampled reference).
bool uses_geometric_aa(Technique technique, const ShadingSettings& settings);

// Whether that variant is built: no plain variant for the supersampled reference, no fast one
// for the techniques that do not fade, LEAN's model for the reference only. Fixed programs: true.
bool has_variant(const VariantKey& key);

// Every variant the renderer builds (for validation): the scene variants of every technique,
// the box filter of the reference and the constant colour.
const std::vector<ShaderVariant>& shader_variants();
// The variant of `key`; throws leanfade::Error("shaders", cause) when it is not built.
const ShaderVariant& shader_variant(const VariantKey& key);

// Compiles and links a variant. A stage that does not compile throws
// leanfade::Error(<file>, "line L, column C: error: <message>; ... (<stage> shader <main file>
// does not compile)"): <file> is the file of the first error, an included file when the error
// is there (ShaderSources::location: the path on disk for a folder), and every location of the
// driver's log is given as a file and line (Mesa, NVIDIA and glslang-style logs are understood;
// another log is passed on as it is). A link failure throws Error("<vertex> + <fragment>", log).
Program build_program(const ShaderSources& sources, const ShaderVariant& variant);

// The error build_program throws for a stage that does not compile, from the driver's info log
// (`stage`: GL_VERTEX_SHADER, ...; `name`: the stage's main file; `source`: its resolution).
Error compile_error(GLenum stage, const std::string& name, const ResolvedSource& source,
                    const ShaderSources& sources, const std::string& log);

// Compiles and links a compute program from one file (e.g. "generate_lean.comp") with `defines`
// inserted after its #version line. Throws leanfade::Error(file, <compiler or linker log>), a
// compile error as build_program's.
Program build_compute_program(const ShaderSources& sources, const std::string& file,
                              const std::vector<std::string>& defines);

}  // namespace leanfade::gl
