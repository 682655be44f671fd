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

// Variants of the scene program of a technique, as bits (shaders/scene.frag).
using SceneVariantFlags = unsigned;
inline constexpr SceneVariantFlags kPlainColor = 1u;  // colour output without fog, no branches
inline constexpr SceneVariantFlags kFadeFast = 2u;    // fading on with p = 2 and d = Vt.z
inline constexpr SceneVariantFlags kCookTorrance = 4u;  // the Cook-Torrance BRDF (LF_BRDF 1)
inline constexpr SceneVariantFlags kLeanModel = 8u;  // the reference shades with LEAN's lobe
// The material's moments mixed from bump layers (LF_LAYERED; Renderer picks it per material).
inline constexpr SceneVariantFlags kLayered = 16u;
// Geometric specular antialiasing (LF_GEOMETRIC_AA, docs/math.md §11; not for the reference).
inline constexpr SceneVariantFlags kGeometricAa = 32u;
inline constexpr SceneVariantFlags kAllSceneVariantFlags = 63u;

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
