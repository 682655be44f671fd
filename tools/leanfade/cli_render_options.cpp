// Command-line binding of the shading settings, the LEAN map source and the GL context.
#include "cli_render_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "cli_flags.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/parameters.hpp"
#include "leanfade/core/procedural.hpp"
#include "leanfade/core/text.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/png_io.hpp"
#include "leanfade/core/camera.hpp"

namespace leanfade::cli {
namespace {


bool ends_with(const std::string& s, const std::string& suffix) {
    if (s.size() < suffix.size()) return false;
    for (std::size_t i = 0; i < suffix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i])
            return false;
    return true;
}

}  // namespace

namespace {

// "<help> (<unit>; <range>; <equation>)" from a schema row.
std::string parameter_help(const ParameterInfo& row) {
    std::string notes(row.unit);
    auto add = [&](const std::string& note) {
        if (!note.empty()) notes += (notes.empty() ? "" : "; ") + note;
    };
    const auto number = [](float v) {
        std::ostringstream out;
        out << v;
        return out.str();
    };
    if (row.kind == ParameterKind::Scalar || row.kind == ParameterKind::Integer) {
        const bool lower = std::isfinite(row.min), upper = std::isfinite(row.max);
        if (lower && upper)
            add(std::string(row.min_exclusive ? "(" : "[") + number(row.min) + ", " +
                number(row.max) + "]");
        else if (lower)
            add(std::string(row.min_exclusive ? "> " : ">= ") + number(row.min));
    }
    if (row.kind == ParameterKind::Choice) {
        std::string names;
        for (std::string_view c : row.choices)
            names += (names.empty() ? "" : " | ") + std::string(c);
        add(names);
    }
    add(std::string(row.equation));
    return std::string(row.help) + (notes.empty() ? "" : " (" + notes + ")");
}

}  // namespace

void add_shading_options(CLI::App& app, ShadingFlags& f) {
    const std::string group = "Shading (docs/math.md §4; colours linear RGB)";
    const ShadingSettings defaults = f.settings;
    for (const ParameterInfo& row : shading_parameters()) {
        const std::string flag = flag_for_setting(row.key);
        const std::string help = parameter_help(row);
        CLI::Option* option = nullptr;
        switch (row.kind) {
            case ParameterKind::Scalar:
                option = app.add_option(flag, f.settings.*row.scalar, help)->capture_default_str();
                break;
            case ParameterKind::Integer:
                option = app.add_option(flag, f.settings.*row.integer, help)->capture_default_str();
                break;
            case ParameterKind::Colour:
            case ParameterKind::Direction:
            case ParameterKind::Choice:
                option = app.add_option(flag, f.text[std::string(row.key)], help)
                             ->default_str(format_parameter(row, defaults));
                if (row.kind == ParameterKind::Colour) option->type_name("R,G,B");
                if (row.kind == ParameterKind::Direction) option->type_name("X,Y,Z");
                break;
        }
        option->group(group);
    }
}

ShadingSettings resolve_shading(const ShadingFlags& f) {
    ShadingSettings s = f.settings;
    for (const auto& [key, text] : f.text)
        if (!text.empty()) parse_parameter(*find_shading_parameter(key), text, s);
    validate(s);
    return s;
}

void add_lean_source_options(CLI::App& app, LeanSourceFlags& f) {
    const std::string group = "Bumps";
    std::string names;
    for (const std::string& n : builtin_bump_names()) names += (names.empty() ? "" : ", ") + n;
    app.add_option("--bumps", f.bumps,
                   "Built-in bump set (" + names +
                       "), a height/normal map image, or a .ktx2 LEAN map from `leanfade bake` "
                       "(an OBJ scene with MTL materials uses their bump maps unless --bumps "
                       "is given)")
        ->capture_default_str()
        ->each([&f](const std::string&) { f.bumps_given = true; })
        ->group(group);
    app.add_option("--from", f.from,
                   "Image inputs: " + name_list(bake_source_names()) +
                       " (auto: 1-2 channels height, 3-4 normal, as bake)")
        ->capture_default_str()
        ->group(group);
    app.add_flag("--directx", f.directx, "Normal maps use the DirectX convention (-Y)")
        ->group(group);
    app.add_flag("--strict-normals", f.strict_normals,
                 "Normal maps: refuse texels with z <= 0 instead of taking (0, 0, 0) padding as "
                 "flat and raising the others (counted and reported)")
        ->group(group);
    app.add_option("--bits", f.bits,
                   "Storage of on-the-fly bakes: " + name_list(bake_storage_names()) +
                       " (auto: 16, or 16f/32f by the predicted error, as bake)")
        ->capture_default_str()
        ->group(group);
    app.add_option("--strength-unit", f.strength_unit,
                   "Unit of --strength for height maps baked on the fly: texel (height per texel "
                   "spacing) or uv (height per UV unit: the same slopes at any resolution)")
        ->check(CLI::IsMember({"texel", "uv"}))
        ->capture_default_str()
        ->group(group);
    app.add_option("--seed", f.seed, "Seed of the built-in bump set")
        ->capture_default_str()
        ->group(group);
    app.add_option("--texture-size", f.texture_size, "Texels per side of a built-in bump set")
        ->capture_default_str()
        ->group(group);
    app.add_option("--max-size", f.max_size,
                   "Largest accepted width or height of a --bumps image or .ktx2 map (refused "
                   "before decoding)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str()
        ->group(group);
    app.add_option(map_flag(scene::MapKind::BaseRoughness), f.roughness_map,
                   "Base roughness per texel with --brdf cook-torrance, instead of --roughness: a "
                   "grey image of perceptual r in [0, 1] or a glTF metallic-roughness texture (r "
                   "in G), at the bumps' uv; alpha0^2 = r^4 is MIP-filtered linearly, as the "
                   "moments (docs/roughness.md)")
        ->group(group);
}

bool is_builtin_bumps(const std::string& source) {
    const auto& builtins = builtin_bump_names();
    return std::find(builtins.begin(), builtins.end(), source) != builtins.end();
}

void check_texture_size(int texture_size, int max_size, bool builtin) {
    const int largest =
        builtin ? std::min(max_size, kDefaultMaxImageDimension) : kDefaultMaxImageDimension;
    if (texture_size < 4 || texture_size > largest)
        throw Error("--texture-size",
                    "must be in [4, " + std::to_string(largest) + "]" +
                        (largest < kDefaultMaxImageDimension ? " (--max-size)" : "") + ", got " +
                        std::to_string(texture_size));
}

std::string map_flag(scene::MapKind kind) {
    return "--" + std::string(scene::info(kind).setting);
}

Storage on_the_fly_storage(const LeanSourceFlags& f) { return parse_bake_storage(f.bits); }

BakeOptions on_the_fly_bake_options(const LeanSourceFlags& f, const ShadingSettings& settings) {
    BakeOptions options;
    options.strength = settings.bump_strength;
    options.strength_unit = f.strength_unit == "uv" ? StrengthUnit::Uv : StrengthUnit::Texel;
    options.convention = f.directx ? NormalConvention::DirectX : NormalConvention::OpenGL;
    options.strict_normals = f.strict_normals;
    return options;
}

PackedLeanMap load_lean_map(const LeanSourceFlags& f, const ShadingSettings& settings) {
    const std::string generator = std::string("leanfade ") + LEANFADE_VERSION;
    const BakeSource source = parse_bake_source(f.from);
    check_texture_size(f.texture_size, f.max_size, is_builtin_bumps(f.bumps));
    const Storage storage = on_the_fly_storage(f);
    io::ReadOptions read_options;
    read_options.max_dimension = f.max_size;
    if (ends_with(f.bumps, ".ktx2")) return io::read_ktx2(f.bumps, read_options);
    if (!io::lean_png_pair_base(f.bumps).empty())  // NAME.lean1.png from `bake --format png`
        return io::read_lean_png_pair(f.bumps, read_options);

    const BakeOptions options = on_the_fly_bake_options(f, settings);
    // The fused fast path of `leanfade bake` (the same bytes as bake_lean_map + pack_lean_map);
    // --bits auto: baked again as 16f or 32f by auto_storage's rule, as `leanfade bake` does.
    auto bake = [&](const Image& input, BakeSource kind) {
        return bake_with_auto_storage(storage, f.bits == "auto", [&](Storage s) {
            return bake_packed(input, kind, options, s, generator, f.bumps);
        });
    };
    const auto& builtins = builtin_bump_names();
    if (std::find(builtins.begin(), builtins.end(), f.bumps) != builtins.end())
        return bake(make_builtin_height(f.bumps, f.texture_size, f.seed), BakeSource::Height)
            .packed;
    const Image image = io::read_image(f.bumps, read_options);
    PackedBakeResult baked = bake(image, source);
    // A strength other than the default was given (flag or preset) for a normal map.
    const bool strength_given = settings.bump_strength != ShadingSettings{}.bump_strength;
    if (baked.source == BakeSource::Normal && strength_given)
        throw Error(f.bumps, "is a normal map: --strength applies to height maps only");
    if (baked.packed.normal_repairs.any())
        std::fprintf(stderr, "leanfade: %s\n",
                     normal_repairs_note(f.bumps, baked.packed.normal_repairs).c_str());
    if (baked.source == BakeSource::Normal) {
        const NormalConventionCheck check = check_normal_convention(image, options.convention);
        if (check.looks_flipped())
            std::fprintf(stderr, "leanfade: warning: %s\n",
                         convention_warning(f.bumps, f.directx,
                                            check.curl_as_read /
                                                std::max(check.curl_flipped, 1e-30))
                             .c_str());
    }
    return std::move(baked.packed);
}

gl::ContextOptions context_options(const GlFlags& flags) {
    gl::ContextOptions options;
    options.device = flags.egl_device;
    return options;
}

gl::ShaderSources shader_sources(const GlFlags& flags) {
    return flags.shader_dir.empty() ? gl::ShaderSources::embedded()
                                    : gl::ShaderSources::directory(flags.shader_dir);
}

void add_camera_options(CLI::App& app, float& fov, std::string& view_dir, const char* view_from,
                        std::string* target) {
    app.add_option("--fov", fov, "Vertical field of view in degrees")->capture_default_str();
    app.add_option("--view-dir", view_dir,
                   std::string("Direction from ") + view_from +
                       " toward the eye, world space (y up)")
        ->capture_default_str();
    if (target != nullptr) {
        app.add_option("--target", *target,
                       "Point the camera looks at, world units (bounding radii; 0 = the centre)")
            ->capture_default_str();
    }
}

void add_reference_samples_option(CLI::App& app, int& ref_samples) {
    app.add_option("--ref-samples", ref_samples,
                   "Reference: k x k samples per pixel at LOD 0 (docs/math.md §7)")
        ->capture_default_str();
}

void add_gl_options(CLI::App& app, GlFlags& f) {
    const std::string group = "OpenGL";
    app.add_option("--shader-dir", f.shader_dir,
                   "Read the shaders from this folder instead of the built-in copies")
        ->group(group);
    app.add_option("--egl-device", f.egl_device,
                   "EGL device index (default: LEANFADE_EGL_DEVICE, else automatic)")
        ->group(group);
}

std::vector<float> parse_distances(const std::string& text, const std::string& flag) {
    std::vector<float> result;
    for (const std::string& part : split(text, ',')) {
        float d = 0.0f;
        if (!parse_finite(part, d))
            throw Error(flag, "expected comma-separated numbers, got '" + text + "'");
        check_camera_distance(d, flag, part);
        result.push_back(d);
    }
    return result;
}

std::pair<int, int> parse_size(const std::string& text, const std::string& flag) {
    const std::size_t x = text.find('x');
    auto parse_int = [&](const std::string& s, int& v) {
        if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
            return false;
        v = std::stoi(s);
        return true;
    };
    int w = 0, h = 0;
    if (x == std::string::npos || !parse_int(text.substr(0, x), w) ||
        !parse_int(text.substr(x + 1), h))
        throw Error(flag, "expected WIDTHxHEIGHT in pixels, got '" + text + "'");
    if (w < 16 || h < 16 || w > 8192 || h > 8192)
        throw Error(flag, "each side must be in [16, 8192] pixels, got '" + text + "'");
    return {w, h};
}

}  // namespace leanfade::cli
