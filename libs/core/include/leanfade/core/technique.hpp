#pragma once
// The shading techniques of leanfade, described once. Everything that lists, parses, names or
// compiles a technique (the command line and its help, presets, the viewer's lists, eval's tables
// and plots, the benchmark's columns and ratios, the renderer's shader variants, the CPU
// reference) reads this table; nothing else spells a technique's name. How they are drawn is the
// drawing code's (eval's plot colours follow the table's order).
//
// Adding a technique: its lobe in shaders/lean_shading.glsl (a new LF_TECHNIQUE_* constant and a
// branch of lf_shade), a row here, and its test (docs/architecture.md).
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/core/shading.hpp"

namespace leanfade {

// Values are positions in kTechniques.
enum class Technique { Bump, Toksvig, Clean, Lean, Fade, Roughness, TwoLobe, Reference };

struct TechniqueInfo {
    Technique id;
    std::string_view name;         // in command lines, presets, JSON keys and file names
    std::string_view label;        // for people: figure headers, the viewer, reports
    std::string_view description;  // one line for help texts and the docs
    int shader_technique;          // the lobe stage of lf_shade (LF_TECHNIQUE_*)
    bool reads_moments;  // samples lean2 (B and M); false: the filtered normal of lean1 only
    bool fades;          // applies specular fading (Fade, Pmax, p and the distance measure)
    bool supersampled;   // the ground truth: k x k samples per pixel at the finest MIP level,
                         // box-filtered (docs/math.md §7); drawn in several passes
    bool reads_plateau;  // samples the material's plateau layer (MapKind::Plateau, two-lobe)
    // Gets geometric specular antialiasing under GeometricAa::Auto (docs/math.md §11).
    bool geometric_aa_by_default;
    // The technique this one extends (LEAN the bump-mapping baseline; fading and two-lobe LEAN),
    // or itself: `leanfade bench` reports a frame-time ratio to it ("lean/bump").
    Technique builds_on;
};

inline constexpr std::array<TechniqueInfo, 8> kTechniques{{
    {Technique::Bump, "bump", "Blinn-Phong bump mapping",
     "Blinn-Phong around the trilinear-filtered normal map (the baseline)",
     shading::LF_TECHNIQUE_BUMP, false, false, false, false, false, Technique::Bump},
    {Technique::Toksvig, "toksvig", "Toksvig mapping",
     "Blinn-Phong with the exponent lowered by the filtered normal's length (Toksvig 2005)",
     shading::LF_TECHNIQUE_TOKSVIG, false, false, false, false, false, Technique::Toksvig},
    {Technique::Clean, "clean", "CLEAN mapping",
     "LEAN with one isotropic second moment (Baker 2011)", shading::LF_TECHNIQUE_CLEAN, true, false,
     false, false, false, Technique::Clean},
    {Technique::Lean, "lean", "LEAN mapping",
     "a Gaussian over bump slopes from filtered first and second moments (Olano and Baker 2010)",
     shading::LF_TECHNIQUE_LEAN, true, false, false, false, false, Technique::Bump},
    {Technique::Fade, "fade", "LEAN + specular fading",
     "LEAN with the specular exponent raised with distance: NdotL^sf", shading::LF_TECHNIQUE_FADE,
     true, true, false, false, false, Technique::Lean},
    {Technique::Roughness, "roughness", "Roughness MIPs",
     "an engine's ordinary BRDF on roughness and normal MIPs baked from the moments, trilinear",
     shading::LF_TECHNIQUE_ROUGHNESS_MIPS, true, false, false, false, false, Technique::Bump},
    {Technique::TwoLobe, "two-lobe", "Two-lobe LEAN",
     "LEAN split into a plateau's mirror spike and the halo of the other slopes, with geometric "
     "specular antialiasing",
     shading::LF_TECHNIQUE_TWO_LOBE, true, false, false, true, true, Technique::Lean},
    {Technique::Reference, "reference", "Reference (supersampled)",
     "the baseline (or LEAN's lobe) at the finest MIP level, k x k samples per pixel, "
     "box-filtered (ground truth)",
     shading::LF_TECHNIQUE_BUMP, false, false, true, false, false, Technique::Reference},
}};

// The supersampled reference takes k x k samples per pixel at the finest level, k in
// [1, kMaxReferenceSamples] (docs/math.md §7): every setting, flag and widget of k obeys this.
inline constexpr int kMaxReferenceSamples = 16;

// Every row sits at the position of its enum value.
constexpr bool technique_table_is_ordered() {
    for (std::size_t i = 0; i < kTechniques.size(); ++i)
        if (std::size_t(kTechniques[i].id) != i) return false;
    return true;
}
static_assert(technique_table_is_ordered());

constexpr const TechniqueInfo& info(Technique technique) {
    return kTechniques[std::size_t(technique)];
}

// The technique's name ("bump", "lean", ...).
const char* to_string(Technique technique);

// Every technique, in table order.
const std::vector<Technique>& all_techniques();
// The techniques measured against the ground truth (every one but the supersampled reference).
std::vector<Technique> approximating_techniques();

// Throws leanfade::Error(setting, cause) for an unknown name; the cause lists the known ones.
Technique parse_technique(std::string_view name, const std::string& setting = "techniques");
// A comma-separated list ("bump,lean,fade"); duplicates and empty lists are errors.
std::vector<Technique> parse_techniques(std::string_view list,
                                        const std::string& setting = "techniques");
// "bump, toksvig, clean, lean, fade or reference": for help texts and messages.
std::string technique_names(std::span<const Technique> techniques, std::string_view last = "or");
// Comma-separated names, the inverse of parse_techniques.
std::string join_technique_names(std::span<const Technique> techniques);

}  // namespace leanfade
